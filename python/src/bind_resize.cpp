// Python bindings of feature-aware resizing (thesis ch. 9): the same library calls as `geotex resize`
// (resize_mesh(), feature_map()), with the options of the same tables.

#include "common.h"

#include <optional>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/user_files.h"
#include "geotex/resize/resize.h"
#include "geotex/resize/results.h"

namespace geotex::python {

void bind_resize(py::module_& m) {
  register_table<ResizeRunOptions>("ResizeRunOptions");
  register_table<FeatureMapOptions>("FeatureMapOptions");
  register_results("ResizeResult", &resize_results);
  register_results("FeatureMap", &feature_map_results);

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
        RunTime time;
        const ResizeResult r = run(call, [&] {
          return timed(time.seconds, [&] { return resize_mesh(mesh, o, D ? &*D : nullptr, f ? &*f : nullptr); });
        });
        if (!r.summary.warning.empty()) warn(r.summary.warning);  // with the GIL, after the work
        // The mesh, then the fields of `geotex resize --report` (resize/results.h), then the options used.
        py::dict d;
        d["V"] = VArray(r.V);
        d["F"] = FArray(faces(mesh));
        put_results(d, r, resize_results());
        put_results(d, time, run_time_results());
        d["parameters"] = options_dict(o);
        return d;
      });

  m.def("feature_map", [](py::handle V, py::handle F, py::dict kw) {
        CallOptions call = call_options(kw);
        FeatureMapOptions o = to_options<FeatureMapOptions>(kw, call);
        o.progress = call.progress;
        const Mesh mesh = to_mesh(V, F);
        const FeatureMap r = run(call, [&] { return feature_map(mesh, o); });
        if (!r.summary.warning.empty()) warn(r.summary.warning);
        py::dict d;
        put_results(d, r, feature_map_results());
        d["parameters"] = options_dict(o);
        return d;
      });
}

}  // namespace geotex::python
