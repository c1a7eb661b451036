// Cancellation points (progress.h, issue 30 item 7): with the caller's flag set (what Python's Ctrl-C does
// through its InterruptGuard), each long computation reachable from Python stops with Interrupted instead
// of running to its end. The loops tested here had no check: the spectrum's shift-invert iterations, the
// sparse factorizations and solves, the rasterizer's OpenMP bands, simplification passes.

#include <atomic>

#include <gtest/gtest.h>

#include "geotex/core/geometry.h"
#include "geotex/core/progress.h"
#include "geotex/toolkit/diffusion.h"
#include "geotex/toolkit/editing.h"
#include "geotex/toolkit/laplace.h"
#include "geotex/toolkit/linear_solver.h"
#include "geotex/toolkit/simplify.h"
#include "geotex/tools/render.h"
#include "geotex/tools/shapes.h"

using namespace geotex;

namespace {

// \p f run inside an InterruptScope whose flag is set before it starts.
template <class F>
void expect_interrupted(F&& f, const char* what) {
  std::atomic<bool> flag{true};
  InterruptScope scope(flag);
  EXPECT_THROW(f(), Interrupted) << what << " ran to its end with the interrupt flag set";
}

}  // namespace

TEST(Interrupt, WithoutAScopeNothingIsInterrupted) {
  const Mesh m = icosphere(1);
  EXPECT_NO_THROW(check_interrupt());
  EXPECT_EQ(auto_diffusion_function(m, {0.1, 10}).size(), static_cast<Eigen::Index>(m.n_vertices()));
  std::atomic<bool> flag{false};
  InterruptScope scope(flag);
  EXPECT_NO_THROW(render_mesh(m));
}

TEST(Interrupt, LongComputationsStopWhenTheFlagIsSet) {
  const Mesh m = icosphere(2);
  expect_interrupted([&] { auto_diffusion_function(m, {0.1, 10}); }, "auto_diffusion_function");
  expect_interrupted([&] { laplace_spectrum(m, 10); }, "laplace_spectrum");
  expect_interrupted([&] { render_mesh(m); }, "render_mesh");
  expect_interrupted([&] { laplacian_edit(m, {0, 1, 2}, positions(m).topRows(3)); }, "laplacian_edit");
  expect_interrupted([&] { simplify(m, 50); }, "simplify");
  expect_interrupted([&] {
    SparseMatrix I(m.n_vertices(), m.n_vertices());
    I.setIdentity();
    SpdSolver s;
    s.factorize(SparseMatrix(I - cotan_matrix(m)));  // I + the (positive semi-definite) cotan Laplacian
  }, "SpdSolver::factorize");
}
