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

//! Names accepted by make_shape(): cube, cylinder, sphere, torus, plane, spiky-sphere, spiky-plane.
std::vector<std::string> shape_names();

//! Build a named shape at a resolution level (0 = coarse, 1 = default, 2 = fine, …).
//! \throw InvalidInput for an unknown name.
TexturedShape make_shape(const std::string& name, int level = 1, uint64_t seed = 1);

}  // namespace geotex
