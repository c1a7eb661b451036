// Python bindings of feature-aware resizing (thesis ch. 9): the same library calls as `geotex resize`
// (resize_mesh(), feature_map()), with the options of the same tables.

#include "common.h"

#include <optional>

#include "geotex/core/error.h"
#include "geotex/core/user_files.h"
#include "geotex/resize/resize.h"

namespace geotex::python {

void bind_resize(py::module_& m) {
  register_table<ResizeRunOptions>("ResizeRunOptions");
  register_table<FeatureMapOptions>("FeatureMapOptions");

  // features: None (the map options.features), #V weights, or a feature file path (str).
  m.def("resize", [](py::handle V, py::handle F, py::handle deformed, py::handle weights, py::handle feature_file,
                     py::dict kw) {
        CallOptions call = call_options(kw);
        ResizeRunOptions o = to_options<ResizeRunOptions>(kw, call);
        o.progress = call.progress;
        const Mesh mesh = to_mesh(V, F);
        std::optional<MatrixX3d> D;
        if (!deformed.is_none()) D = to_points(deformed, "deformed");
        std::optional<Eigen::VectorXd> f;
        if (!weights.is_none()) f = to_vector(weights, mesh.n_vertices(), "features");
        else if (!feature_file.is_none()) f = read_feature_file(py::cast<std::string>(feature_file), mesh, o.feature_file);
        const ResizeResult r = run(call, [&] { return resize_mesh(mesh, o, D ? &*D : nullptr, f ? &*f : nullptr); });
        if (!r.summary.warning.empty()) warn(r.summary.warning);  // with the GIL, after the work
        return VArray(r.V);
      });

  m.def("feature_map", [](py::handle V, py::handle F, py::dict kw) {
        CallOptions call = call_options(kw);
        FeatureMapOptions o = to_options<FeatureMapOptions>(kw, call);
        o.progress = call.progress;
        const Mesh mesh = to_mesh(V, F);
        const FeatureMap r = run(call, [&] { return feature_map(mesh, o); });
        if (!r.summary.warning.empty()) warn(r.summary.warning);
        return py::dict(py::arg("weights") = r.weights, py::arg("field") = r.field,
                        py::arg("detector") = enum_name(feature_map_names(), r.method),
                        py::arg("marked_fraction") = r.summary.marked_fraction,
                        py::arg("marked_vertices") = r.summary.marked_vertices, py::arg("regions") = r.summary.regions,
                        py::arg("warning") = r.summary.warning, py::arg("parameters") = options_dict(o));
      });
}

}  // namespace geotex::python
