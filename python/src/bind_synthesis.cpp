// Python bindings of height-and-tilt texture synthesis (texture/synthesis.h).

#include "common.h"

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/texture/results.h"
#include "geotex/texture/synthesis.h"

namespace geotex::python {

void bind_synthesis(py::module_& m) {
  register_table<SynthesisOptions>("SynthesisOptions");
  register_results("SynthesisResult", &synthesis_results);
  register_results("SynthesisQuality", &synthesis_quality_results);

  m.def("texture_synthesize", [](py::handle V_base, py::handle F, py::handle height, py::handle tilt, py::object lean,
                                 py::handle V_target, py::handle F_target, py::object weight, py::object guide,
                                 py::dict kw) {
        // on_estimate(dict): the estimate before the work (issue 27), as the CLI's first line states it.
        py::object on_estimate = py::none();
        if (kw.contains("on_estimate")) {
          on_estimate = kw["on_estimate"];
          PyDict_DelItemString(kw.ptr(), "on_estimate");
          if (!on_estimate.is_none() && !PyCallable_Check(on_estimate.ptr()))
            throw py::type_error("on_estimate: expected a callable(estimate: dict)");
        }
        CallOptions call = call_options(kw);
        SynthesisOptions o = to_options<SynthesisOptions>(kw, call);
        o.progress = call.progress;
        if (!on_estimate.is_none()) {
          auto holder = std::make_shared<py::object>(on_estimate);
          o.on_estimate = [holder](const SynthesisEstimate& e) {  // called without the GIL, as progress is
            py::gil_scoped_acquire gil;
            py::dict d;
            d["vertices"] = e.vertices;
            d["seconds"] = e.seconds;
            d["exemplar_share"] = e.exemplar_share;
            d["scale"] = e.scale;
            d["refine"] = e.refine;
            (*holder)(d);
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
          };
        }
        const Mesh base = to_mesh(V_base, F);
        Texture ex{to_vector(height, base.n_vertices(), "height"), to_vector(tilt, base.n_edges(), "tilt"), {}};
        if (!lean.is_none()) ex.lean = to_vector(lean, base.n_vertices(), "lean");
        const Mesh target = to_mesh(V_target, F_target);
        SynthesisGuides g;
        if (!weight.is_none()) g.weight = to_vector(weight, target.n_vertices(), "weight");
        if (!guide.is_none()) g.direction = to_points(guide, "direction_guide");
        RunTime time;
        SynthesisQuality quality;
        const SynthesisResult r = run(call, [&] {
          SynthesisResult res = timed(time.seconds, [&] { return synthesize_texture(base, ex, target, o, g); });
          quality = synthesis_quality(base, ex, res, o);  // measured as `--report` measures it
          return res;
        });
        // The textured target and its texture, then the fields of `geotex texture synthesize --report`
        // (texture/results.h), then the options used.
        py::dict d;
        d["V"] = VArray(r.textured);
        d["F"] = FArray(faces(r.target));
        d["V_base"] = VArray(positions(r.target));
        d["height"] = r.texture.height;
        d["tilt"] = r.texture.tilt;
        d["lean"] = r.texture.lean;
        put_results(d, r, synthesis_results());
        put_results(d, quality, synthesis_quality_results());
        put_results(d, time, run_time_results());
        d["parameters"] = options_dict(o);
        return d;
      });
}

}  // namespace geotex::python
