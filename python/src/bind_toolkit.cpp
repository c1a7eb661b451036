// Python bindings of the toolkit (thesis ch. 5): Laplacians, smoothing, Laplacian editing, Phong
// projection, 1-forms, parametrization, the auto diffusion function.

#include "common.h"

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/toolkit/diffusion.h"
#include "geotex/toolkit/editing.h"
#include "geotex/toolkit/laplace.h"
#include "geotex/toolkit/one_form.h"
#include "geotex/toolkit/parametrization.h"
#include "geotex/toolkit/phong_projection.h"
#include "geotex/toolkit/results.h"
#include "geotex/toolkit/smoothing.h"

namespace geotex::python {

namespace {

// #n by 2 finite UVs (one row per vertex, as parametrize() returns them).
MatrixX2d to_uv(py::handle a, Eigen::Index n) {
  const auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!d || d.ndim() != 2 || d.shape(0) != n || d.shape(1) != 2)
    throw InvalidInput(fmt::format("uv: expected a {} x 2 array of numbers (one row per vertex)", n));
  MatrixX2d uv(n, 2);
  for (Eigen::Index i = 0; i < n; ++i)
    for (int k = 0; k < 2; ++k) uv(i, k) = d.data()[2 * i + k];
  if (!uv.allFinite()) throw InvalidInput("uv: non-finite coordinates");
  return uv;
}

}  // namespace

void bind_toolkit(py::module_& m) {
  register_table<SmoothingOptions>("SmoothingOptions");
  register_table<EditOptions>("EditOptions");
  register_table<ParametrizationOptions>("ParametrizationOptions");
  register_results("ParamQuality", &param_quality_results);
  register_table<PhongProjectionOptions>("PhongProjectionOptions");
  register_table<OneFormFitOptions>("OneFormFitOptions");

  const auto mass = [](const std::string& s) { return parse_enum(mass_names(), s, "mass"); };
  m.def("umbrella_laplacian", [](py::handle V, py::handle F) { return umbrella_laplacian(to_mesh(V, F)); });
  m.def("cotan_matrix", [](py::handle V, py::handle F) { return cotan_matrix(to_mesh(V, F)); });
  m.def("mass_matrix", [mass](py::handle V, py::handle F, const std::string& type) {
        return mass_matrix(to_mesh(V, F), mass(type));
      },
      py::arg("V"), py::arg("F"), py::arg("mass") = "voronoi");
  m.def("cotan_laplacian", [mass](py::handle V, py::handle F, const std::string& type) {
        return cotan_laplacian(to_mesh(V, F), mass(type));
      },
      py::arg("V"), py::arg("F"), py::arg("mass") = "voronoi");
  m.def("mean_curvature_normals", [](py::handle V, py::handle F) { return VArray(mean_curvature_normals(to_mesh(V, F))); });

  m.def("smooth", [](py::handle V, py::handle F, py::dict kw) {
        CallOptions call = call_options(kw);
        SmoothingOptions o = to_options<SmoothingOptions>(kw, call);
        o.progress = call.progress;
        const Mesh mesh = to_mesh(V, F);
        return VArray(run(call, [&] { return smooth(mesh, o); }));
      });

  m.def("deform", [](py::handle V, py::handle F, py::handle handle_ids, py::handle targets, py::dict kw) {
        CallOptions call = call_options(kw);
        const EditOptions o = to_options<EditOptions>(kw, call);
        const Mesh mesh = to_mesh(V, F);
        const Eigen::VectorXi ids = to_indices(handle_ids, static_cast<Eigen::Index>(mesh.n_vertices()), 0,
                                               "handles", "vertex id");
        const std::vector<int> handles(ids.data(), ids.data() + ids.size());
        const MatrixX3d T = to_points(targets, "targets");
        return VArray(run(call, [&] { return laplacian_edit(mesh, handles, T, o); }));
      });

  m.def("parametrize", [](py::handle V, py::handle F, py::dict kw) {
        CallOptions call = call_options(kw);
        const ParametrizationOptions o = to_options<ParametrizationOptions>(kw, call);
        const Mesh mesh = to_mesh(V, F);
        return MatrixX2d(run(call, [&] { return parametrize(mesh, o); }));
      });

  m.def("parametrization_quality", [](py::handle V, py::handle F, py::handle uv) {
        const Mesh mesh = to_mesh(V, F);
        const MatrixX2d UV = to_uv(uv, static_cast<Eigen::Index>(mesh.n_vertices()));
        py::dict d;  // the keys of `geotex param --json` but the method, vertex count and time
        put_results(d, parametrization_quality(mesh, UV), param_quality_results());
        return d;
      },
      py::arg("V"), py::arg("F"), py::arg("uv"));

  m.def("phong_project", [](py::handle V, py::handle F, py::handle P, py::dict kw) {
        CallOptions call = call_options(kw);
        const PhongProjectionOptions o = to_options<PhongProjectionOptions>(kw, call);
        const Mesh mesh = to_mesh(V, F);
        const MatrixX3d X = to_points(P, "P");
        const std::vector<PhongHit> hits = run(call, [&] { return PhongProjector(mesh, MatrixX3d(), o).project(X); });
        Eigen::VectorXi face(hits.size());
        MatrixX3d bary(hits.size(), 3), point(hits.size(), 3);
        Eigen::VectorXd dist(hits.size());
        for (size_t i = 0; i < hits.size(); ++i) {
          face[i] = hits[i].face;
          bary.row(i) = hits[i].bary.transpose();
          point.row(i) = hits[i].point.transpose();
          dist[i] = hits[i].distance;
        }
        return py::dict(py::arg("face") = face, py::arg("bary") = VArray(bary), py::arg("point") = VArray(point),
                        py::arg("distance") = dist);
      });

  m.def("one_form_fit", [](py::handle V, py::handle F, py::handle T, py::dict kw) {
        CallOptions call = call_options(kw);
        const OneFormFitOptions o = to_options<OneFormFitOptions>(kw, call);
        const Mesh mesh = to_mesh(V, F);
        const MatrixX3d field = to_points(T, "T");
        return Eigen::VectorXd(run(call, [&] { return fit_one_form(mesh, field, o); }));
      });
  m.def("one_form_to_vertices", [](py::handle V, py::handle F, py::handle c) {
        const Mesh mesh = to_mesh(V, F);
        return VArray(one_form_to_vertices(mesh, to_vector(c, mesh.n_edges(), "c")));
      });

  m.def("auto_diffusion_function", [](py::handle V, py::handle F, double t, int eigenpairs, py::dict kw) {
        CallOptions call = call_options(kw);
        DiffusionOptions o;
        o.t = t;
        o.eigenpairs = eigenpairs;
        const Mesh mesh = to_mesh(V, F);
        return Eigen::VectorXd(run(call, [&] { return auto_diffusion_function(mesh, o); }));
      });
}

}  // namespace geotex::python
