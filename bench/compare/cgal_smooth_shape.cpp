// CGAL::Polygon_mesh_processing::smooth_shape (implicit mean-curvature flow) on a mesh file, for
// bench/capabilities.sh (comparison with `geotex smooth`).
// Usage: cgal_smooth_shape IN OUT LAMBDA ITERATIONS [bicgstab|cholmod]
//
// smooth_shape solves (M_c - t C_c) x = M_c x0 per iteration (cotangent weights computed once, a lumped
// mass from face areas / 6 updated per iteration), then rescales to the input volume on closed meshes.
// geotex's implicit cotangent step with barycentric mass solves (M - lambda h^2 C) x = M x0
// (h = mean edge length, C_ij = (cot a + cot b) / 2). CGAL's normalisation of C_c differs: the time
// t = lambda h^2 / 4 gives the same step (checked: on the 19,200-face noisy cube the face normals of this
// program's output and of `geotex smooth --mass barycentric --rescale --lambda L` agree to 0.000 deg
// mean; t = lambda h^2 / 2 differs by 2.6 deg). This program takes geotex's lambda and converts.
// Solver: bicgstab = CGAL's default (Eigen BiCGSTAB + IncompleteLUT); cholmod = Eigen's CHOLMOD
// supernodal LLT (the backend geotex uses).
// Prints the read / smooth / write wall times (s) and the smoothing's CPU time on stdout.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/IO/polygon_mesh_io.h>
#include <CGAL/Polygon_mesh_processing/smooth_shape.h>
#include <CGAL/Surface_mesh.h>
#include <Eigen/CholmodSupport>

#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

static double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// CPU seconds of the whole process (all threads) since c0.
static double cpu_since(std::clock_t c0) { return static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC; }

int main(int argc, char** argv) {
  if (argc < 5 || argc > 6) {
    std::fprintf(stderr, "usage: cgal_smooth_shape IN OUT LAMBDA ITERATIONS [bicgstab|cholmod]\n");
    return 2;
  }
  const double lambda = std::atof(argv[3]);
  const unsigned iterations = static_cast<unsigned>(std::atoi(argv[4]));
  const std::string solver = argc == 6 ? argv[5] : "bicgstab";
  if (solver != "bicgstab" && solver != "cholmod") {
    std::fprintf(stderr, "cgal_smooth_shape: solver must be bicgstab or cholmod\n");
    return 2;
  }
  Mesh mesh;
  auto t0 = std::chrono::steady_clock::now();
  if (!PMP::IO::read_polygon_mesh(argv[1], mesh) || !CGAL::is_triangle_mesh(mesh)) {
    std::fprintf(stderr, "cgal_smooth_shape: cannot read a triangle mesh from %s\n", argv[1]);
    return 1;
  }
  const double t_read = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  double sum = 0;
  for (auto e : mesh.edges()) sum += std::sqrt(CGAL::squared_distance(mesh.point(mesh.vertex(e, 0)),
                                                                      mesh.point(mesh.vertex(e, 1))));
  const double h = sum / static_cast<double>(mesh.number_of_edges());
  const double time = lambda * h * h / 4;
  if (solver == "bicgstab") {
    PMP::smooth_shape(mesh, time, CGAL::parameters::number_of_iterations(iterations));
  } else {
    using Cholmod = Eigen::CholmodSupernodalLLT<CGAL::Eigen_sparse_matrix<double>::EigenType>;
    CGAL::Eigen_solver_traits<Cholmod> traits;
    PMP::smooth_shape(mesh, time,
                      CGAL::parameters::number_of_iterations(iterations).sparse_linear_solver(traits));
  }
  const double t_op = seconds_since(t0), c_op = cpu_since(c0);

  t0 = std::chrono::steady_clock::now();
  if (!CGAL::IO::write_polygon_mesh(argv[2], mesh, CGAL::parameters::use_binary_mode(true).stream_precision(17))) {
    std::fprintf(stderr, "cgal_smooth_shape: cannot write %s\n", argv[2]);
    return 1;
  }
  std::printf("read %.3f s, smooth_shape %.3f s wall %.3f s CPU (time %.4g = lambda %g * h^2 / 4, %u iterations, %s), "
              "write %.3f s, %zu vertices, %zu faces\n",
              t_read, t_op, c_op, time, lambda, iterations, solver.c_str(), seconds_since(t0),
              static_cast<size_t>(mesh.number_of_vertices()), static_cast<size_t>(mesh.number_of_faces()));
  return 0;
}
