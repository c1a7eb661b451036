// Python bindings of feature-aware resizing (thesis ch. 9).

#include "common.h"

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/resize/resize.h"

namespace geotex::python {

void bind_resize(py::module_& m) {
  m.def("resize", [](py::handle V, py::handle F, py::object scale, py::object deformed, py::object features, const std::string& method,
                     double feature_threshold) {
        const Mesh mesh = to_mesh(V, F);
        Eigen::VectorXd f;
        if (features.is_none() || (py::isinstance<py::str>(features) && py::cast<std::string>(features) == "auto")) {
          f = features_from_adf(mesh, 0.1, 100, feature_threshold);
        } else if (py::isinstance<py::str>(features) && py::cast<std::string>(features) == "height") {
          f = features_from_height(mesh);
        } else {
          f = to_vector(features, mesh.n_vertices(), "features");
          if (f.size() != static_cast<Eigen::Index>(mesh.n_vertices()))
            throw InvalidInput("features must have one weight per vertex");
        }
        ResizeOptions o;
        if (method == "sliding") o.method = ResizeMethod::Sliding;
        else if (method == "thesis") o.method = ResizeMethod::Thesis;
        else throw InvalidInput("method must be 'sliding' or 'thesis'");
        if (!deformed.is_none()) {
          const MatrixX3d D = to_points(deformed, "deformed");
          py::gil_scoped_release release;
          return VArray(feature_aware_resize(mesh, D, f, o));
        }
        const std::vector<double> s = scale.is_none() ? std::vector<double>{2, 1, 1} : py::cast<std::vector<double>>(scale);
        if (s.size() != 3) throw InvalidInput("scale must have 3 values");
        py::gil_scoped_release release;
        return VArray(feature_aware_resize(mesh, scale_map(Vec3(s[0], s[1], s[2]), bounding_box(mesh).center()), f, o));
      },
      py::arg("V"), py::arg("F"), py::arg("scale") = py::none(), py::arg("deformed") = py::none(),
      py::arg("features") = "auto", py::arg("method") = "sliding", py::arg("feature_threshold") = 0.5,
      R"doc(Feature-aware resizing (ch. 9). Give scale=(sx, sy, sz) (about the box centre) or deformed=#V×3
positions from any space deformation. features: 'auto' (ADF threshold), 'height', or #V weights in [0, 1].
method: 'sliding' (default: background slides along the surface) or 'thesis' (Eq. 9.2–9.3).)doc");

}

}  // namespace geotex::python
