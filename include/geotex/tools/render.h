#pragma once
//! \file render.h Pictures of meshes without a GPU: a small software rasterizer (z-buffer, flat or
//! smooth Lambert + Blinn-Phong shading, per-vertex colour maps, edge lines, a legend bar) and PNG
//! files (libpng).
//!
//! The camera is orthographic and fitted to the faces of the mesh, so that pictures of different
//! results of the same input line up when rendered with the same camera (pass the first rendering's
//! camera on). The up axis is read from the model unless given (UpAxis).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "geotex/core/mesh.h"
#include "geotex/core/options.h"

namespace geotex {

//! An 8-bit RGB picture, rows top to bottom, 3 bytes per pixel.
struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  //!< width * height * 3 bytes
  uint8_t* pixel(int x, int y) { return rgb.data() + 3 * (static_cast<size_t>(y) * width + x); }
  const uint8_t* pixel(int x, int y) const { return rgb.data() + 3 * (static_cast<size_t>(y) * width + x); }
};

//! Where the camera looks from, for up = z: iso (from +x, −y, +z), front (from −y), top (from +z).
//! For another up axis the same directions are rotated with it (up = y: front is from +z).
enum class ViewDirection { Iso, Front, Top };
//! "iso", "front", "top".
const EnumNames<ViewDirection>& view_direction_names();
//! \throw InvalidInput (InvalidOption) for a name other than iso, front, top.
ViewDirection view_direction_from_name(const std::string& name);

//! The model's up axis. Auto decides from the points (the vertices of the faces), in this order:
//!  1. flat: when the thinnest extent is below 0.3 of the middle one, up is the thin axis (plates,
//!     terrains, tori, planar meshes: the camera looks onto the flat side);
//!  2. resting on a ground plane: when the lowest z is 0 and the lowest y is not, z (and the reverse,
//!     y), as exporters place models on their floor;
//!  3. the side it stands on: for each of ±x, ±y, ±z the footprint of the points within 1% of the
//!     lowest (the convex hull of four hooves, a plinth, the rim of an open bottom) as a share of the
//!     box's cross section, halved when the centroid is outside it; the best side is up when its
//!     share is at least 0.05 and twice y's (a z-up bust on its plinth, a CAD part on its base);
//!  4. otherwise y: scans (Stanford, Cyberware) and most exchange files are y-up.
//! geotex's own generated shapes are z-up: pass Z for an exact picture of them.
enum class UpAxis { Auto, X, Y, Z, NegX, NegY, NegZ };
//! "auto", "x", "y", "z", "-x", "-y", "-z".
const EnumNames<UpAxis>& up_axis_names();
//! The help line of an `up` option (render, view).
inline constexpr const char* up_axis_help =
    "the model's up axis; auto: the thin axis of a flat model, else the axis it rests on at 0, else the side it "
    "stands on (its footprint) when clearly better than y's, else y";
//! The unit vector \p up names; Auto decides from \p points (#P by 3) by the rule of UpAxis.
Vec3 up_vector(UpAxis up, const MatrixX3d& points);

//! What the fitted camera keeps in the picture.
enum class Framing {
  Tight,  //!< the extent of the mesh as seen from the view direction (the largest picture)
  Sphere  //!< the bounding sphere about the box centre: the same scale from every view direction
};
//! "tight", "sphere".
const EnumNames<Framing>& framing_names();

//! An orthographic camera: screen x = scale * dot(p − centre, right) + width/2, screen y likewise
//! with up (downwards in the image); depth = dot(p − centre, forward).
struct Camera {
  Vec3 centre = Vec3::Zero();
  Vec3 right = Vec3::UnitX(), up = Vec3::UnitZ(), forward = Vec3::UnitY();  //!< orthonormal
  double scale = 1.0;  //!< pixels per model unit
  int width = 0, height = 0;
};

struct RenderOptions {
  int width = 800;                          //!< picture width in pixels
  int height = 600;                         //!< picture height in pixels
  ViewDirection view = ViewDirection::Iso;  //!< camera direction (ignored when camera is set)
  UpAxis up = UpAxis::Auto;                 //!< the model's up axis (auto: from the bounding box)
  Framing frame = Framing::Tight;           //!< what the fitted camera keeps in the picture
  double zoom = 1.0;                        //!< magnification of the fitted camera (2: twice as large)
  std::optional<Vec3> centre;               //!< point at the picture's centre (unset: the framed mesh's centre)
  double margin = 0.06;                     //!< free border, fraction of the smaller side (at zoom 1)
  std::optional<Camera> camera;             //!< reuse a camera (same framing across results); not an option
  bool smooth = true;                       //!< interpolate vertex normals (false: flat, per face)
  int supersampling = 2;                    //!< k × k samples per pixel (anti-aliasing); 1 = none
  Vec3 background{1.0, 1.0, 1.0};           //!< background colour (RGB in [0, 1])
  Vec3 base_colour{0.74, 0.76, 0.80};       //!< surface colour without a field
  double ambient = 0.25;                    //!< ambient light
  double specular = 0.25;                   //!< Blinn-Phong highlight strength (0 = Lambert only)
  double shininess = 40.0;                  //!< Blinn-Phong exponent
  double line_width = 2.0;                  //!< edge-line width in pixels
  bool legend = true;                       //!< draw a colour bar with the field range when a field is shown

  static const OptionTable<RenderOptions>& table();
};

//! Width in pixels of the legend column at the right of a picture \p width by \p height pixels
//! (its labels' font grows with the height: legible at any size).
int legend_width(int width, int height);

//! The camera that frames \p points (#P by 3) as \p options say (view, up, frame, zoom, centre,
//! margin) in the left options.width − \p reserved_right pixels of the picture (the rest is kept for
//! a legend). \throw InvalidInput for no points or a bad size.
Camera fit_camera(const MatrixX3d& points, const RenderOptions& options, int reserved_right = 0);
//! The same for the vertices of \p mesh that belong to a face: a stray vertex must not push the
//! model into a corner of its picture.
Camera fit_camera(const Mesh& mesh, const RenderOptions& options, int reserved_right = 0);

//! The vertices of \p mesh that belong to at least one face (#P by 3, in index order); all vertices
//! when no face refers to any (a point set).
MatrixX3d face_vertices(const Mesh& mesh);

//! What to draw on top of the shaded surface.
struct RenderLayers {
  //! #V per-vertex values shown through a colour map (empty: base colour)
  Eigen::VectorXd field;
  //! colour-map range; when lo >= hi the field's own min and max are used
  double field_lo = 0.0, field_hi = 0.0;
  //! #S by 2 vertex indices of line segments (e.g. labelled sharp edges)
  MatrixX2i segments;
  //! #S per-segment labels choosing the line colour (empty: all label 1)
  Eigen::VectorXi segment_labels;
  //! #V by 2 texture coordinates shown as a checkerboard (empty: none; it replaces the field's colours):
  //! a parametrization's angle distortion shows as squares turned into diamonds, its area distortion as
  //! squares of different sizes. Interpolated per pixel (exact for the orthographic camera).
  MatrixX2d uv;
  double checker_size = 0.1;  //!< side of a checker square in uv units
};

struct Rendering {
  Image image;
  Camera camera;                //!< the camera used (pass on through RenderOptions::camera)
  double field_lo = 0, field_hi = 0;  //!< the colour-map range used
  size_t covered_pixels = 0;    //!< pixels where the surface is visible (before anti-aliasing)
};

//! Render a mesh. \throw InvalidInput for an empty mesh, a bad size, or layers of the wrong size.
Rendering render_mesh(const Mesh& mesh, const RenderOptions& options = {}, const RenderLayers& layers = {});

//! A perceptually ordered colour map (viridis), t in [0, 1] (clamped). \return RGB in [0, 1].
Vec3 colour_map(double t);
//! The line colour for an edge label (1 = red, 2 = blue, …; cycles through a small palette).
Vec3 label_colour(int label);

//! Encode as PNG (8-bit RGB) with libpng: adaptive row filters, zlib's default compression.
//! \throw InvalidInput when the pixel data does not match the size; IoError if libpng fails.
std::string encode_png(const Image& image);
//! Write a PNG file atomically. \throw IoError on failure.
void write_png(const Image& image, const std::filesystem::path& path);

//! Per-vertex unsigned distance from each vertex of \p mesh to the surface of \p reference
//! (an error field for the viewer and pictures). \return #V distances.
Eigen::VectorXd distance_to_surface(const Mesh& mesh, const Mesh& reference);

}  // namespace geotex
