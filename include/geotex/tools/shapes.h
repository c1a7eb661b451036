#pragma once
//! \file shapes.h Procedural test shapes: the embedded defaults of the CLI, tests and demo.

#include <cstdint>
#include <string>
#include <vector>

#include "geotex/core/mesh.h"

namespace geotex {

//! Cube of side \p size centred at the origin, each face an n×n grid of quads split in two (sharp
//! edges and corners: the classic denoising test). 6n²+2 vertices, 12n² faces.
Mesh subdivided_cube(int n = 10, double size = 1.0);

//! Capped cylinder along z, centred at the origin: \p segments around, \p rings along the side;
//! the caps are meshed in concentric rings (no needle fan). Sharp edges at both rims.
Mesh cylinder(double radius = 0.5, double height = 1.0, int segments = 48, int rings = 24);

//! Icosahedron subdivided \p subdivisions times (each time ×4 faces), on a sphere of \p radius.
Mesh icosphere(int subdivisions = 4, double radius = 1.0);

//! Torus around z: major radius \p R, minor radius \p r, \p nu × \p nv quads split in two.
Mesh torus(double R = 1.0, double r = 0.35, int nu = 64, int nv = 24);

//! Capsule along x, centred at the origin: a cylinder of \p radius and \p length (the straight part)
//! closed by two hemispheres. \p segments vertices around; rings along the cylinder and latitude rings
//! on the caps are spaced to make near-equilateral triangles. A closed sphere-like surface (genus 0).
Mesh capsule(double radius = 1.0, double length = 6.0, int segments = 160);

//! Square plate in the xy-plane, side \p size, centred at the origin, n×n quads split in two
//! (an open disk with one boundary loop).
Mesh plane(int n = 40, double size = 1.0);

//! A textured shape and the base it was made from (same connectivity, same vertex order).
struct TexturedShape {
  Mesh base;
  Mesh textured;
  std::vector<int> spike_centres;  //!< vertex index of each spike's tip
  std::vector<Vec3> lean;          //!< unit tangent direction each spike leans to (at its centre)
};

struct SpikeOptions {
  int count = 24;           //!< number of spikes
  double height = 5.0;      //!< spike height, in mean edge lengths of the base
  double radius = 2.5;      //!< spike footprint radius, in mean edge lengths
  double lean_deg = 55.0;   //!< lean of the tip from the normal; large enough to overhang the foot
  bool random_lean = true;  //!< each spike leans its own random way (else all towards +x / the equator)
  uint64_t seed = 1;
};

//! Displace a base mesh by leaning spikes: within each spike's footprint the displacement is
//! h(r)·(cos θ(r) n + sin θ(r) t), with h falling from the tip to zero at the rim and the lean θ
//! growing with height. The tips overhang their feet: no height field along the normal can hold it.
TexturedShape spiky(const Mesh& base, const SpikeOptions& options = {});

//! Curved, leaning tentacles: long thin protrusions that bend over (no height field holds them).
struct TentacleOptions {
  int count = 9;            //!< number of tentacles (placed by the caller or at random)
  double radius = 0.45;     //!< footprint radius on the base, in model units
  double length = 1.3;      //!< length of each tentacle's centreline, in model units
  double thickness = 0.12;  //!< radius of the tentacle's shaft, in model units
  double foot = 0.3;        //!< share of the footprint (from its rim) that forms the flared foot
  uint64_t seed = 1;        //!< random placement and leans (when not given)
};

//! One tentacle of a generated shape.
struct Tentacle {
  int foot = -1;            //!< base vertex at the footprint's centre (it becomes the tentacle's tip)
  Vec3 lean = Vec3::Zero(); //!< unit tangent at the foot towards which the tentacle bends
  double bend_deg = 0;      //!< angle of the tip's direction from the base normal (the centreline turns linearly)
  double length = 0;        //!< |tip − foot| on the textured mesh
  double lean_deg = 0;      //!< angle between tip − foot and the base normal at the foot
};

//! Displace a base mesh into tentacles. Within each footprint (Euclidean radius \p radius around the
//! foot vertex) a vertex at distance r and polar angle ψ goes to the tentacle's centreline at an
//! arclength growing as r falls, offset by the shaft's radius in the direction ψ of the centreline's
//! normal plane: the footprint's rim stays in place, the foot flares into the shaft, the footprint's
//! centre becomes the tip. The centreline leaves along the base normal and turns towards \p leans[k] by
//! \p bend_deg[k] at the tip. Same connectivity as the base.
//! \param feet foot vertices (random interior vertices at least 3 footprints apart when empty);
//! \param leans tangent directions (random when empty); \param bend_deg tip angles (random in [40°, 80°] when empty).
//! \return the shape; TexturedShape::spike_centres are the feet, lean their lean directions, and
//! \p info (if given) receives each tentacle's measurements.
TexturedShape tentacles(const Mesh& base, const TentacleOptions& options = {}, std::vector<int> feet = {},
                        std::vector<Vec3> leans = {}, std::vector<double> bend_deg = {},
                        std::vector<Tentacle>* info = nullptr);

//! The tentacle stick: a capsule (radius 1, straight length 6, along x) with nine tentacles spread along
//! it in a spiral, bending along the axis, around it and in between. Level 1 has about 40k vertices.
//! \param info receives the tentacles (feet, leans, lengths, lean angles).
TexturedShape tentacle_stick(int level = 1, std::vector<Tentacle>* info = nullptr);

//! A square plate (side 4, in the xy-plane) with tentacles on a 3 × 3 grid, all bending towards +x
//! by 60°: a regular exemplar of tentacle texture.
TexturedShape tentacle_plane(int level = 1, std::vector<Tentacle>* info = nullptr);

//! Per-vertex membership of the tentacles' footprints (1 inside any, else 0) on \p base, for feature
//! maps' ground truth. \param radius the footprint radius used to make them.
Eigen::VectorXd tentacle_truth(const Mesh& base, const std::vector<Tentacle>& tentacles, double radius);

//! Names accepted by make_shape(): cube, cylinder, sphere, torus, plane, capsule, spiky-sphere, spiky-plane,
//! tentacle-stick, tentacle-plane, bumpy-plate and ridge-plate (bumpy_plate() and ridge_plate() of
//! resize/measure.h, 40·2^level quads a side; spike_centres the bumps' centre vertices).
std::vector<std::string> shape_names();

//! Build a named shape at a resolution level (0 = coarse, 1 = default, 2 = fine, …).
//! \throw InvalidInput for an unknown name.
TexturedShape make_shape(const std::string& name, int level = 1, uint64_t seed = 1);

// ---- the test shapes of feature-aware resizing (resize/measure.h measures them) ----

struct BumpyPlateOptions {
  int n = 80;             //!< n × n quads over [−1, 1]²
  int bumps = 3;          //!< bumps × bumps round bumps on a regular grid
  double spacing = 0.6;   //!< distance between bump centres
  double radius = 0.2;    //!< footprint radius
  double height = 0.15;   //!< bump height (profile h (1 − r²/R²)², C¹ at the rim)
  //! A ridge: the bump's profile swept along a segment of this length (0: none) on the y axis,
  //! centred at the origin (rounded ends). Scaling along x would widen it.
  double ridge_length = 0;
};

struct BumpyPlate {
  Mesh mesh;
  std::vector<Vec3> centres;  //!< footprint centres of the round bumps (z = 0)
  double radius = 0, height = 0;
  Eigen::VectorXd truth;      //!< 1 inside a footprint (bumps and ridge), else 0
  Eigen::VectorXd ridge;      //!< 1 inside the ridge's footprint, else 0
};

//! A flat square plate with round bumps (and optionally a ridge): the test shape of feature-aware resizing.
//! \throw InvalidInput for bad options or features that overlap.
BumpyPlate bumpy_plate(const BumpyPlateOptions& options = {});

//! The ridge plate: 2 × 2 bumps 1.0 apart and a ridge of length 1.2 between them (bumpy_plate()).
BumpyPlate ridge_plate(int n = 80);

}  // namespace geotex
