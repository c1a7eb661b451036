// CGAL Surface_mesh_parameterization on a disk-topology mesh file, for bench/capabilities.sh
// (comparison with `geotex param`). Usage: cgal_param IN OUT.obj [dcm|lscm]
//   dcm  = Discrete_conformal_map_parameterizer_3 (cotangent weights, boundary on a circle by arc length,
//          CGAL's default solver Eigen BiCGSTAB + IncompleteLUT): the same map as `geotex param`
//          (--method conformal);
//   lscm = LSCM_parameterizer_3 (free boundary, two pinned vertices, default solver Eigen
//          SimplicialLDLT): the counterpart of `geotex param --method natural`.
// Writes an OBJ with one vt per vertex and prints the read / parametrize / write wall times (s), the
// parametrization's CPU time,
// number of flipped faces and the mean |UV angle - 3D angle| over face corners (degrees, the measure
// of geotex's ParamQuality::mean_angle_error_deg) on stdout.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/IO/polygon_mesh_io.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_parameterization/Discrete_conformal_map_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/LSCM_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>

#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <unordered_map>

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;
using VD = Mesh::Vertex_index;
namespace SMP = CGAL::Surface_mesh_parameterization;

static double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// CPU seconds of the whole process (all threads) since c0.
static double cpu_since(std::clock_t c0) { return static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC; }

static double angle(double ax, double ay, double az, double bx, double by, double bz) {
  const double d = ax * bx + ay * by + az * bz;
  const double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
  return std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), d);
}

int main(int argc, char** argv) {
  if (argc < 3 || argc > 4) {
    std::fprintf(stderr, "usage: cgal_param IN OUT.obj [dcm|lscm]\n");
    return 2;
  }
  const std::string method = argc == 4 ? argv[3] : "dcm";
  if (method != "dcm" && method != "lscm") {
    std::fprintf(stderr, "cgal_param: method must be dcm or lscm\n");
    return 2;
  }
  Mesh mesh;
  auto t0 = std::chrono::steady_clock::now();
  if (!CGAL::Polygon_mesh_processing::IO::read_polygon_mesh(argv[1], mesh) || !CGAL::is_triangle_mesh(mesh)) {
    std::fprintf(stderr, "cgal_param: cannot read a triangle mesh from %s\n", argv[1]);
    return 1;
  }
  const double t_read = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  const auto bhd = CGAL::Polygon_mesh_processing::longest_border(mesh).first;
  if (bhd == Mesh::null_halfedge()) {
    std::fprintf(stderr, "cgal_param: %s has no boundary\n", argv[1]);
    return 1;
  }
  auto uv = mesh.add_property_map<VD, K::Point_2>("v:uv").first;
  SMP::Error_code err;
  if (method == "dcm") {
    err = SMP::parameterize(mesh, SMP::Discrete_conformal_map_parameterizer_3<Mesh>(), bhd, uv);
  } else {
    err = SMP::parameterize(mesh, SMP::LSCM_parameterizer_3<Mesh>(), bhd, uv);
  }
  const double t_op = seconds_since(t0), c_op = cpu_since(c0);
  if (err != SMP::OK) {
    std::fprintf(stderr, "cgal_param: %s\n", SMP::get_error_message(err));
    return 1;
  }

  // Distortion: flipped faces (signed UV area <= 0) and the mean corner-angle error.
  size_t flipped = 0, corners = 0;
  double angle_error = 0;
  for (auto f : mesh.faces()) {
    VD v[3];
    int k = 0;
    for (auto vd : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) v[k++] = vd;
    const K::Point_2 q[3] = {uv[v[0]], uv[v[1]], uv[v[2]]};
    const double area = (q[1].x() - q[0].x()) * (q[2].y() - q[0].y()) - (q[2].x() - q[0].x()) * (q[1].y() - q[0].y());
    if (!(area > 0)) ++flipped;
    for (int i = 0; i < 3; ++i) {
      const auto& p = mesh.point(v[i]);
      const auto& a = mesh.point(v[(i + 1) % 3]);
      const auto& b = mesh.point(v[(i + 2) % 3]);
      const double a3 = angle(a.x() - p.x(), a.y() - p.y(), a.z() - p.z(), b.x() - p.x(), b.y() - p.y(), b.z() - p.z());
      const K::Point_2& s = q[i];
      const K::Point_2& ua = q[(i + 1) % 3];
      const K::Point_2& ub = q[(i + 2) % 3];
      const double a2 = angle(ua.x() - s.x(), ua.y() - s.y(), 0, ub.x() - s.x(), ub.y() - s.y(), 0);
      angle_error += std::abs(a2 - a3);
      ++corners;
    }
  }

  t0 = std::chrono::steady_clock::now();
  {
    std::ofstream out(argv[2]);
    out.precision(17);
    std::unordered_map<VD, size_t> index;
    size_t n = 0;
    for (auto vd : mesh.vertices()) {
      const auto& p = mesh.point(vd);
      out << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
      index[vd] = ++n;
    }
    for (auto vd : mesh.vertices()) out << "vt " << uv[vd].x() << ' ' << uv[vd].y() << '\n';
    for (auto f : mesh.faces()) {
      out << 'f';
      for (auto vd : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) out << ' ' << index[vd] << '/' << index[vd];
      out << '\n';
    }
    if (!out) {
      std::fprintf(stderr, "cgal_param: cannot write %s\n", argv[2]);
      return 1;
    }
  }
  std::printf("read %.3f s, parameterize %.3f s wall %.3f s CPU (%s), write %.3f s, %zu vertices, %zu faces, flipped %zu, "
              "mean angle error %.3f deg\n",
              t_read, t_op, c_op, method.c_str(), seconds_since(t0), static_cast<size_t>(mesh.number_of_vertices()),
              static_cast<size_t>(mesh.number_of_faces()), flipped, angle_error / static_cast<double>(corners) * 180 / M_PI);
  return 0;
}
