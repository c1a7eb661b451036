#pragma once
//! \file render.h Pictures of meshes without a GPU: a small software rasterizer (z-buffer, flat or
//! smooth Lambert + Blinn-Phong shading, per-vertex colour maps, edge lines, a legend bar) and a
//! self-contained PNG writer (deflate with fixed Huffman codes; no zlib needed).
//!
//! The camera is orthographic and fitted to the mesh, so that pictures of different results of the
//! same input line up when rendered with the same camera (pass the first rendering's camera on).
//! Geometry is z-up, like the shapes of shapes.h.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "geotex/core/mesh.h"

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
//! \throw InvalidInput for a name other than iso, front, top.
ViewDirection view_direction_from_name(const std::string& name);

//! An orthographic camera: screen x = scale * dot(p − centre, right) + width/2, screen y likewise
//! with up (downwards in the image); depth = dot(p − centre, forward).
struct Camera {
  Vec3 centre = Vec3::Zero();
  Vec3 right = Vec3::UnitX(), up = Vec3::UnitZ(), forward = Vec3::UnitY();  //!< orthonormal
  double scale = 1.0;  //!< pixels per model unit
  int width = 0, height = 0;
};

//! The camera that fits the vertices of \p V (#V by 3) into a width × height frame, leaving \p margin
//! (a fraction of the smaller side) free on each side. \p up is the model's up axis (z for geotex
//! shapes, y for most scans); view directions are named relative to it.
Camera fit_camera(const MatrixX3d& V, ViewDirection view, int width, int height, double margin = 0.06,
                  const Vec3& up = Vec3::UnitZ());

struct RenderOptions {
  int width = 800;                        //!< picture width in pixels
  int height = 600;                       //!< picture height in pixels
  ViewDirection view = ViewDirection::Iso;  //!< camera direction (ignored when camera is set)
  Vec3 up = Vec3::UnitZ();                //!< the model's up axis (y for most scans)
  std::optional<Camera> camera;           //!< reuse a camera (same framing across results)
  bool smooth = true;                     //!< interpolate vertex normals (false: flat, per face)
  int supersampling = 2;                  //!< k × k samples per pixel (anti-aliasing); 1 = none
  double margin = 0.06;                   //!< free border, fraction of the smaller side
  Vec3 background{1.0, 1.0, 1.0};         //!< background colour (RGB in [0, 1])
  Vec3 base_colour{0.74, 0.76, 0.80};     //!< surface colour without a field
  double ambient = 0.25;                  //!< ambient light
  double specular = 0.25;                 //!< Blinn-Phong highlight strength (0 = Lambert only)
  double shininess = 40.0;                //!< Blinn-Phong exponent
  double line_width = 2.0;                //!< edge-line width in pixels
  bool legend = true;                     //!< draw a colour bar with the field range when a field is shown
};

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

//! Encode as PNG (8-bit RGB, deflate with LZ77 + fixed Huffman codes, per-row adaptive filters).
std::string encode_png(const Image& image);
//! Write a PNG file atomically. \throw IoError on failure.
void write_png(const Image& image, const std::filesystem::path& path);

//! CRC-32 as used by PNG chunks (ISO 3309 / ITU-T V.42).
uint32_t png_crc32(const uint8_t* data, size_t n, uint32_t crc = 0);

//! Per-vertex unsigned distance from each vertex of \p mesh to the surface of \p reference
//! (an error field for the viewer and pictures). \return #V distances.
Eigen::VectorXd distance_to_surface(const Mesh& mesh, const Mesh& reference);

}  // namespace geotex
