// OpenMesh's Jacobi Laplace smoother on a mesh file, for bench/capabilities.sh (comparison with
// `geotex smooth`). Usage: openmesh_smooth IN OUT ITERATIONS
// Configuration: Tangential_and_Normal, C0 continuity: uniform (umbrella) weights, each iteration
// p += 0.5 (mean of neighbours - p) for every interior vertex (boundary vertices fixed) — the same
// update as `geotex smooth --laplacian umbrella --explicit --lambda 0.5 --steps ITERATIONS`.
// Prints the read / smooth / write wall times (s) and the smoothing's CPU time on stdout.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Smoother/JacobiLaplaceSmootherT.hh>

#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>

struct DoubleTraits : OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
using Mesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

static double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// CPU seconds of the whole process (all threads) since c0.
static double cpu_since(std::clock_t c0) { return static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC; }

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: openmesh_smooth IN OUT ITERATIONS\n");
    return 2;
  }
  const int iterations = std::atoi(argv[3]);
  Mesh mesh;
  auto t0 = std::chrono::steady_clock::now();
  if (!OpenMesh::IO::read_mesh(mesh, argv[1])) {
    std::fprintf(stderr, "openmesh_smooth: cannot read %s\n", argv[1]);
    return 1;
  }
  const double t_read = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  {
    OpenMesh::Smoother::JacobiLaplaceSmootherT<Mesh> smoother(mesh);
    smoother.initialize(OpenMesh::Smoother::SmootherT<Mesh>::Tangential_and_Normal,
                        OpenMesh::Smoother::SmootherT<Mesh>::C0);
    smoother.smooth(static_cast<unsigned>(iterations));
  }
  const double t_op = seconds_since(t0), c_op = cpu_since(c0);

  t0 = std::chrono::steady_clock::now();
  if (!OpenMesh::IO::write_mesh(mesh, argv[2], OpenMesh::IO::Options::Binary)) {
    std::fprintf(stderr, "openmesh_smooth: cannot write %s\n", argv[2]);
    return 1;
  }
  std::printf("read %.3f s, smooth %.3f s wall %.3f s CPU (%d iterations), write %.3f s, %zu vertices, %zu faces\n", t_read,
              t_op, c_op, iterations, seconds_since(t0), mesh.n_vertices(), mesh.n_faces());
  return 0;
}
