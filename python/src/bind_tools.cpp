// Python bindings of the tools: software-rendered pictures and self-contained 3D viewer pages.

#include "common.h"

#include <filesystem>
#include <vector>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/io.h"
#include "geotex/tools/render.h"
#include "geotex/tools/viewer.h"

namespace geotex::python {

namespace {

// Optional per-mesh layers: a field (#V values) and labelled edges, given as #S × 2 vertex pairs or as
// #E labels in edges(mesh) order (a result's edge_labels; an edge labelled above ½ is drawn, as the
// viewer reads a PLY edge element's labels).
MeshLayers layers_of(const Mesh& mesh, py::handle field, py::handle edges, const std::string& field_name) {
  MeshLayers l;
  if (!field.is_none()) l.fields[field_name] = to_vector(field, mesh.n_vertices(), "field");
  if (edges.is_none()) return l;
  const py::array a = py::array::ensure(edges);
  if (a && a.ndim() == 1) {
    const Eigen::VectorXd labels = to_vector(a, -1, "edges");
    const MatrixX2i E = geotex::edges(mesh);
    if (labels.size() != E.rows())
      throw InvalidInput(fmt::format("edges: {} labels given, but the mesh has {} edges (labels are per edge, in "
                                     "edges() order)", labels.size(), E.rows()));
    std::vector<int> keep;
    for (Eigen::Index e = 0; e < labels.size(); ++e)
      if (labels[e] > 0.5) keep.push_back(static_cast<int>(e));
    l.segments.resize(static_cast<Eigen::Index>(keep.size()), 2);
    for (size_t k = 0; k < keep.size(); ++k) l.segments.row(static_cast<Eigen::Index>(k)) = E.row(keep[k]);
  } else {
    if (!a || a.ndim() != 2 || a.shape(1) != 2 || (a.dtype().kind() != 'i' && a.dtype().kind() != 'u'))
      throw InvalidInput("edges: expected an N x 2 array of vertex indices or one label per edge");
    // Checked as int64/uint64 (a cast to int would wrap 2^32 + 1 to 1: a wrong edge drawn, no error).
    l.segments = to_indices(a, static_cast<Eigen::Index>(mesh.n_vertices()), 2, "edges", "vertex index");
  }
  l.labels = Eigen::VectorXi::Ones(l.segments.rows());
  return l;
}

}  // namespace

void bind_tools(py::module_& m) {
  register_table<RenderOptions>("RenderOptions");
  register_table<ViewerOptions>("ViewerOptions");

  m.def("render", [](py::handle V, py::handle F, py::object path, py::object field, py::object edges, py::dict kw) {
    CallOptions call = call_options(kw);
    const RenderOptions o = to_options<RenderOptions>(kw, call);
    const Mesh mesh = to_mesh(V, F);
    const MeshLayers l = layers_of(mesh, field, edges, "field");
    RenderLayers rl;
    if (l.fields.count("field")) rl.field = l.fields.at("field");
    rl.segments = l.segments;
    rl.segment_labels = l.labels;
    std::string out = path.is_none() ? std::string() : py::str(path).cast<std::string>();
    const Rendering r = run(call, [&] {
      Rendering pic = render_mesh(mesh, o, rl);
      if (!out.empty()) write_png(pic.image, out);
      return pic;
    });
    py::array_t<uint8_t> img({r.image.height, r.image.width, 3});
    std::copy(r.image.rgb.begin(), r.image.rgb.end(), img.mutable_data());
    return img;
  });

  m.def("view", [](py::list meshes, py::object path, py::dict kw) {
    CallOptions call = call_options(kw);
    const ViewerOptions o = to_options<ViewerOptions>(kw, call);
    std::vector<ViewerMesh> ms;
    for (py::handle item : meshes) {
      const py::tuple t = py::reinterpret_borrow<py::tuple>(item);  // (name, V, F, field, edges)
      ViewerMesh vm;
      vm.name = t[0].cast<std::string>();
      vm.mesh = to_mesh(t[1], t[2]);
      vm.layers = layers_of(vm.mesh, t[3], t[4], o.initial_field.empty() ? "field" : o.initial_field);
      ms.push_back(std::move(vm));
    }
    const std::string out = py::str(path).cast<std::string>();
    run(call, [&] { write_text_atomic(out, viewer_page(ms, o, o.script_src.empty() ? viewer_script() : "")); });
  });
}

}  // namespace geotex::python
