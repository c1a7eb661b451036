// Python bindings of the core and the tools around it: files, shapes, noise, geometry, metrics, and
// the option tables the Python wrappers make their signatures from.

#include "common.h"

#include <limits>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/core/output.h"
#include "geotex/tools/metrics.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/results.h"
#include "geotex/tools/shapes.h"

namespace geotex::python {

namespace {

// The fields of `geotex info --json` but those about the file (core/results.h).
py::dict summary_dict(const Mesh& m) {
  py::dict d;
  put_results(d, summarize(m), mesh_summary_results());
  return d;
}

const EnumNames<NormalWeighting>& weighting_names() {
  static const EnumNames<NormalWeighting> n = {
      {"area", NormalWeighting::Area}, {"angle", NormalWeighting::Angle}, {"uniform", NormalWeighting::Uniform}};
  return n;
}

}  // namespace

void bind_core(py::module_& m) {
  register_table<NoiseOptions>("NoiseOptions");
  register_results("RunTime", &run_time_results);
  register_results("MeshSummary", &mesh_summary_results);
  register_results("Comparison", &comparison_results);
  register_results("LabelScore", &label_score_results);
  m.def("_result_tables", [] {
    py::dict d;
    for (const auto& [name, describe] : result_tables()) d[py::str(name)] = describe();
    return d;
  });
  m.def("_option_tables", [] {
    py::dict d;
    for (const auto& [name, describe] : option_tables()) d[py::str(name)] = describe();
    return d;
  });
  // Raises as the call would (InvalidOption, TypeError) for options of table `name`, or returns None.
  m.def("_check_options", [](const std::string& name, py::dict kw) {
    const auto it = option_checkers().find(name);
    if (it == option_checkers().end()) throw py::key_error("no options table '" + name + "'");
    it->second(kw);
  });

  m.def("read_mesh", [](const std::string& path, bool strict) {
        ReadOptions o;
        o.strict = strict;
        ReadReport rep;
        Mesh mesh;
        {
          py::gil_scoped_release release;
          mesh = read_mesh(path, o, &rep);
        }
        for (const auto& w : rep.warnings) {
          const std::string msg = path + ": " + w;
          if (PyErr_WarnEx(PyExc_UserWarning, msg.c_str(), 1) != 0) throw py::error_already_set();
        }
        return from_mesh(mesh);
      },
      py::arg("path"), py::arg("strict") = false);

  m.def("write_mesh", [](const std::string& path, py::handle V, py::handle F, bool binary) {
        WriteOptions o;
        o.binary = binary;
        const Mesh mesh = to_mesh(V, F);
        py::gil_scoped_release release;
        write_mesh(mesh, path, o);
      },
      py::arg("path"), py::arg("V"), py::arg("F"), py::arg("binary") = true);

  m.def("info", [](py::handle V, py::handle F) { return summary_dict(to_mesh(V, F)); }, py::arg("V"), py::arg("F"));

  m.def("shape_names", &shape_names);
  m.def("generate", [](const std::string& name, int level, uint64_t seed, bool with_base) -> py::object {
        TexturedShape s;
        {
          py::gil_scoped_release release;
          s = make_shape(name, level, seed);
        }
        if (!with_base) return from_mesh(s.textured);
        return py::make_tuple(from_mesh(s.textured), from_mesh(s.base));
      },
      py::arg("name"), py::arg("level") = 1, py::arg("seed") = 1, py::arg("with_base") = false);

  m.def("add_noise", [](py::handle V, py::handle F, py::dict kw) {
        CallOptions call = call_options(kw);
        const NoiseOptions o = to_options<NoiseOptions>(kw, call);
        const Mesh mesh = to_mesh(V, F);
        return VArray(run(call, [&] { return add_noise(mesh, o); }));
      },
      py::arg("V"), py::arg("F"), py::arg("options"));

  m.def("compare", [](py::handle V, py::handle F, py::handle Vt, py::handle Ft) {
        const Mesh result = to_mesh(V, F), truth = to_mesh(Vt, Ft);
        Comparison c;
        {
          py::gil_scoped_release release;
          c = compare_meshes(result, truth);
        }
        py::dict d;  // the keys of `geotex compare --json` but the file names (tools/results.h)
        put_results(d, c, comparison_results());
        return d;
      },
      py::arg("V"), py::arg("F"), py::arg("V_truth"), py::arg("F_truth"));

  m.def("score_edge_labels", [](py::handle labelled, py::handle truth) {
        const auto pairs = [](py::handle a, const char* what) {
          // Any vertex index an int holds; beyond that named exactly, not wrapped by a cast.
          return MatrixX2i(to_indices(a, std::numeric_limits<int>::max(), 2, what, "vertex index"));
        };
        py::dict d;  // compare --json's edge_labels but the angle (tools/results.h)
        put_results(d, score_edge_labels(pairs(labelled, "labelled"), pairs(truth, "truth")), label_score_results());
        return d;
      },
      py::arg("labelled"), py::arg("truth"));

  m.def("face_normals", [](py::handle V, py::handle F) { return VArray(face_normals(to_mesh(V, F))); });
  m.def("vertex_normals", [](py::handle V, py::handle F, const std::string& weighting) {
        return VArray(vertex_normals(to_mesh(V, F), parse_enum(weighting_names(), weighting, "weighting")));
      },
      py::arg("V"), py::arg("F"), py::arg("weighting") = "area");
  m.def("face_areas", [](py::handle V, py::handle F) { return Eigen::VectorXd(face_areas(to_mesh(V, F))); });
  m.def("edges", [](py::handle V, py::handle F) { return MatrixX2i(edges(to_mesh(V, F))); });
  m.def("dihedral_angles", [](py::handle V, py::handle F) { return Eigen::VectorXd(dihedral_angles(to_mesh(V, F))); });
  m.def("mean_edge_length", [](py::handle V, py::handle F) { return mean_edge_length(to_mesh(V, F)); });
  m.def("boundary_loops", [](py::handle V, py::handle F) { return boundary_loops(to_mesh(V, F)); });
  m.def("connected_components", [](py::handle V, py::handle F) {
    return Eigen::VectorXi(connected_components(to_mesh(V, F)));
  });
}

}  // namespace geotex::python
