// Python bindings of denoising (thesis ch. 6-7): the MRF methods, surfels on meshes and point clouds.

#include "common.h"

#include <fmt/format.h>

#include "geotex/denoise/auto_denoise.h"
#include "geotex/denoise/mrf.h"
#include "geotex/denoise/point_surfels.h"
#include "geotex/denoise/results.h"
#include "geotex/denoise/surfel.h"

namespace geotex::python {

namespace {

// A denoising result: the mesh (V, F, its edges and their labels), then the fields of the run's and the
// method's result tables (the keys of `geotex denoise --report`), then the parameters used.
template <class R, class O>
py::dict denoise_result(const Mesh& mesh, const Eigen::VectorXd& edge_labels, const DenoiseRun& run, const R& r,
                        const ResultTable<R>& table, const O& used) {
  py::dict d;
  d["V"] = VArray(positions(mesh));
  d["F"] = FArray(faces(mesh));
  d["edge_labels"] = edge_labels;
  d["edges"] = MatrixX2i(edges(mesh));
  put_results(d, run, denoise_run_results());
  put_results(d, r, table);
  d["parameters"] = options_dict(used);
  return d;
}

template <class O>
py::dict mrf_result(const Mesh& input, const MrfResult& r, const O& used, const DenoiseRun& run) {
  Mesh out = input;
  set_positions(out, r.positions);
  return denoise_result(out, r.edge_labels, run, r, mrf_results(), used);
}

}  // namespace

void bind_denoise(py::module_& m) {
  register_table<AutoDenoiseOptions>("AutoDenoiseOptions");
  register_table<MrfOptions>("MrfOptions");
  register_table<MrfNormalOptions>("MrfNormalOptions");
  register_table<SurfelDenoiseOptions>("SurfelDenoiseOptions");
  register_table<PointSurfelOptions>("PointSurfelOptions");
  register_results("DenoiseRun", &denoise_run_results);
  register_results("AutoDenoiseResult", &auto_denoise_results);
  register_results("MrfResult", &mrf_results);
  register_results("SurfelDenoiseResult", &surfel_denoise_results);

  m.def("denoise_auto", [](py::handle V, py::handle F, py::dict kw) {
    CallOptions call = call_options(kw);
    AutoDenoiseOptions o = to_options<AutoDenoiseOptions>(kw, call);
    o.progress = call.progress;
    const Mesh mesh = to_mesh(V, F);
    DenoiseRun info{"auto"};
    const AutoDenoiseResult r = run(call, [&] { return timed(info.seconds, [&] { return auto_denoise(mesh, o); }); });
    if (r.turned_over > 0) warn(fmt::format("geotex: {} faces are left turned over", r.turned_over));
    Mesh out = mesh;
    set_positions(out, r.positions);
    return denoise_result(out, r.edge_labels, info, r, auto_denoise_results(), r.resolved);
  });
  m.def("denoise_mrf", [](py::handle V, py::handle F, py::dict kw) {
    CallOptions call = call_options(kw);
    MrfOptions o = to_options<MrfOptions>(kw, call);
    o.progress = call.progress;
    const Mesh mesh = to_mesh(V, F);
    DenoiseRun info{"mrf"};
    const MrfResult r = run(call, [&] { return timed(info.seconds, [&] { return mrf_denoise(mesh, o); }); });
    return mrf_result(mesh, r, o, info);
  });
  m.def("denoise_mrf_normal", [](py::handle V, py::handle F, py::dict kw) {
    CallOptions call = call_options(kw);
    MrfNormalOptions o = to_options<MrfNormalOptions>(kw, call);
    o.progress = call.progress;
    const Mesh mesh = to_mesh(V, F);
    DenoiseRun info{"mrf-normal"};
    const MrfResult r = run(call, [&] { return timed(info.seconds, [&] { return mrf_normal_denoise(mesh, o); }); });
    return mrf_result(mesh, r, o, info);
  });
  m.def("denoise_surfel", [](py::handle V, py::handle F, py::dict kw) {
    CallOptions call = call_options(kw);
    SurfelDenoiseOptions o = to_options<SurfelDenoiseOptions>(kw, call);
    o.progress = call.progress;
    const Mesh mesh = to_mesh(V, F);
    DenoiseRun info{"surfel"};
    const SurfelDenoiseResult r =
        run(call, [&] { return timed(info.seconds, [&] { return surfel_denoise(mesh, o); }); });
    SurfelDenoiseOptions used = o;
    used.t_start_deg = r.t_start_deg;
    return denoise_result(r.mesh, r.edge_labels, info, r, surfel_denoise_results(), used);
  });
  m.def("point_surfels", [](py::handle P, py::dict kw) {
    CallOptions call = call_options(kw);
    PointSurfelOptions o = to_options<PointSurfelOptions>(kw, call);
    o.progress = call.progress;
    const MatrixX3d X = to_points(P, "P");
    const PointSurfelResult r = run(call, [&] { return point_surfels(X, o); });
    return py::make_tuple(VArray(r.centers), VArray(r.normals));
  });
  m.def("pca_normals", [](py::handle P, int k) { return VArray(pca_normals(to_points(P, "P"), k)); }, py::arg("P"),
        py::arg("k") = 10);
}

}  // namespace geotex::python
