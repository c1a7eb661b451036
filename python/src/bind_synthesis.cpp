// Python bindings of height-and-tilt texture synthesis (texture/synthesis.h).

#include "common.h"

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/texture/synthesis.h"

namespace geotex::python {

void bind_synthesis(py::module_& m) {
  register_table<SynthesisOptions>("SynthesisOptions");

  m.def("texture_synthesize", [](py::handle V_base, py::handle F, py::handle height, py::handle tilt, py::object lean,
                                 py::handle V_target, py::handle F_target, py::object weight, py::object guide,
                                 py::dict kw) {
        CallOptions call = call_options(kw);
        SynthesisOptions o = to_options<SynthesisOptions>(kw, call);
        o.progress = call.progress;
        const Mesh base = to_mesh(V_base, F);
        Texture ex{to_vector(height, base.n_vertices(), "height"), to_vector(tilt, base.n_edges(), "tilt"), {}};
        if (!lean.is_none()) ex.lean = to_vector(lean, base.n_vertices(), "lean");
        const Mesh target = to_mesh(V_target, F_target);
        SynthesisGuides g;
        if (!weight.is_none()) g.weight = to_vector(weight, target.n_vertices(), "weight");
        if (!guide.is_none()) g.direction = to_points(guide, "direction_guide");
        const SynthesisResult r = run(call, [&] { return synthesize_texture(base, ex, target, o, g); });
        py::dict stages;
        for (const auto& [name, sec] : r.stage_seconds) stages[py::str(name)] = sec;
        return py::dict(py::arg("V") = VArray(r.textured), py::arg("F") = FArray(faces(r.target)),
                        py::arg("V_base") = VArray(positions(r.target)), py::arg("height") = r.texture.height,
                        py::arg("tilt") = r.texture.tilt, py::arg("lean") = r.texture.lean,
                        py::arg("field") = VArray(r.field), py::arg("owner") = r.owner,
                        py::arg("centers") = r.centers, py::arg("scale") = r.scale,
                        py::arg("patch_radius") = r.patch_radius, py::arg("added_vertices") = r.added_vertices,
                        py::arg("unfolded_vertices") = r.unfolded_vertices,
                        py::arg("self_intersecting") = r.self_intersecting,
                        py::arg("base_self_intersecting") = r.base_self_intersecting,
                        py::arg("excess_self_intersecting") = r.excess_self_intersecting,
                        py::arg("shrunk_share") = r.shrunk_share, py::arg("refined_share") = r.refined_share,
                        py::arg("exemplar_share") = r.estimate.exemplar_share,
                        py::arg("estimated_vertices") = r.estimate.vertices,
                        py::arg("estimated_seconds") = r.estimate.seconds, py::arg("stage_seconds") = stages,
                        py::arg("warnings") = r.warnings);
      });
}

}  // namespace geotex::python
