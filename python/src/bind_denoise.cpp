// Python bindings of denoising (thesis ch. 6-7): the MRF methods, surfels on meshes and point clouds.

#include "common.h"

#include <fmt/format.h>

#include "geotex/denoise/auto_denoise.h"
#include "geotex/denoise/mrf.h"
#include "geotex/denoise/point_surfels.h"
#include "geotex/denoise/surfel.h"

namespace geotex::python {

namespace {

template <class O>
py::dict mrf_result(const Mesh& input, const MrfResult& r, const O& used) {
  Mesh out = input;
  set_positions(out, r.positions);
  py::dict d;
  d["V"] = VArray(r.positions);
  d["F"] = FArray(faces(out));
  d["edge_labels"] = r.edge_labels;
  d["edges"] = MatrixX2i(edges(out));
  d["vertex_energy"] = r.vertex_energy;
  d["edge_energy"] = r.edge_energy;
  d["iterations"] = r.iterations;
  d["converged"] = r.converged;
  d["parameters"] = options_dict(used);
  return d;
}

}  // namespace

void bind_denoise(py::module_& m) {
  register_table<AutoDenoiseOptions>("AutoDenoiseOptions");
  register_table<MrfOptions>("MrfOptions");
  register_table<MrfNormalOptions>("MrfNormalOptions");
  register_table<SurfelDenoiseOptions>("SurfelDenoiseOptions");
  register_table<PointSurfelOptions>("PointSurfelOptions");

  m.def("denoise_auto", [](py::handle V, py::handle F, py::dict kw) {
    CallOptions call = call_options(kw);
    AutoDenoiseOptions o = to_options<AutoDenoiseOptions>(kw, call);
    o.progress = call.progress;
    const Mesh mesh = to_mesh(V, F);
    const AutoDenoiseResult r = run(call, [&] { return auto_denoise(mesh, o); });
    if (r.turned_over > 0) warn(fmt::format("geotex: {} faces are left turned over", r.turned_over));
    py::dict d;
    d["V"] = VArray(r.positions);
    d["F"] = FArray(faces(mesh));
    d["edge_labels"] = r.edge_labels;
    d["edges"] = MatrixX2i(edges(mesh));
    d["noise_sigma"] = r.noise.sigma;
    d["noise_normal_sigma"] = r.noise.normal_sigma;
    d["choices"] = r.choices;
    d["turned_over"] = r.turned_over;
    d["creased"] = r.creased;
    d["creased_share"] = r.creased_share;
    d["parameters"] = options_dict(r.resolved);
    return d;
  });
  m.def("denoise_mrf", [](py::handle V, py::handle F, py::dict kw) {
    CallOptions call = call_options(kw);
    MrfOptions o = to_options<MrfOptions>(kw, call);
    o.progress = call.progress;
    const Mesh mesh = to_mesh(V, F);
    return mrf_result(mesh, run(call, [&] { return mrf_denoise(mesh, o); }), o);
  });
  m.def("denoise_mrf_normal", [](py::handle V, py::handle F, py::dict kw) {
    CallOptions call = call_options(kw);
    MrfNormalOptions o = to_options<MrfNormalOptions>(kw, call);
    o.progress = call.progress;
    const Mesh mesh = to_mesh(V, F);
    return mrf_result(mesh, run(call, [&] { return mrf_normal_denoise(mesh, o); }), o);
  });
  m.def("denoise_surfel", [](py::handle V, py::handle F, py::dict kw) {
    CallOptions call = call_options(kw);
    SurfelDenoiseOptions o = to_options<SurfelDenoiseOptions>(kw, call);
    o.progress = call.progress;
    const Mesh mesh = to_mesh(V, F);
    const SurfelDenoiseResult r = run(call, [&] { return surfel_denoise(mesh, o); });
    SurfelDenoiseOptions used = o;
    used.t_start_deg = r.t_start_deg;
    py::dict d;
    d["V"] = VArray(positions(r.mesh));
    d["F"] = FArray(faces(r.mesh));
    d["edge_labels"] = r.edge_labels;
    d["edges"] = MatrixX2i(edges(r.mesh));
    d["normals"] = VArray(r.surfels.surfels.normals);
    d["offsets"] = r.surfels.surfels.offsets;
    d["energy"] = r.surfels.energy;
    d["median_angle_deg"] = r.median_angle_deg;
    d["parameters"] = options_dict(used);
    return d;
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
