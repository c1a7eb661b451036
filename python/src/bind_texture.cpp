// Python bindings of height-and-tilt geometric texture (thesis ch. 8): one function per `geotex texture`
// subcommand, options from the same tables, and texture files.
//
// A texture crosses the boundary as its base (V_base, F) and its arrays (height #V, tilt #E, lean #V or
// empty); the Python side (geotex/__init__.py) packs them into Result objects.

#include "common.h"

#include <optional>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/texture/results.h"
#include "geotex/texture/texture.h"
#include "geotex/texture/transfer.h"

namespace geotex::python {

namespace {

struct PyTexture {
  Mesh base;
  Texture texture;
};

// A texture from its base and arrays (the GIL held: conversions may warn).
PyTexture texture_of(py::handle V_base, py::handle F, py::handle height, py::handle tilt, py::handle lean) {
  PyTexture t;
  t.base = to_mesh(V_base, F);
  const auto nv = static_cast<Eigen::Index>(t.base.n_vertices());
  t.texture.height = to_vector(height, nv, "height");
  t.texture.tilt = to_vector(tilt, static_cast<Eigen::Index>(t.base.n_edges()), "tilt");
  if (!lean.is_none() && py::len(lean) > 0) {
    t.texture.lean = to_vector(lean, nv, "lean");
    t.texture.rest = positions(t.base);  // the lean's direction is kept in this base's tangent frames
  }
  return t;
}

py::dict texture_dict(const Mesh& base, const Texture& t) {
  py::dict d;
  d["V_base"] = VArray(positions(base));
  d["F"] = FArray(faces(base));
  d["height"] = t.height;
  d["tilt"] = t.tilt;
  d["lean"] = t.lean;
  d["edges"] = MatrixX2i(edges(base));
  return d;
}

// A transfer's or an atlas' result: the textured target (V, F), its texture, then the fields of the
// subcommand's --report (texture/results.h), then the options used.
template <class R, class O>
py::dict textured_result(const MatrixX3d& Y, const R& r, const ResultTable<R>& table, const RunTime& time,
                         const O& used) {
  py::dict d;
  d["V"] = VArray(Y);
  d["F"] = FArray(faces(r.target));
  d["texture"] = texture_dict(r.target, r.texture);
  put_results(d, r, table);
  put_results(d, time, run_time_results());
  d["parameters"] = options_dict(used);
  return d;
}

std::optional<Vec3> point_or_none(py::handle p, const char* what) {
  if (p.is_none()) return std::nullopt;
  OptionInfo info;
  info.name = what;
  info.kind = OptionKind::Vec3;
  return std::get<Vec3>(from_python(info, p));
}

// A mesh of \p stored's connectivity: \p V (#V by 3) over \p F, or over stored's faces when F is None.
Mesh same_connectivity(const Mesh& stored, py::handle V, py::handle F, const char* what) {
  Mesh m = stored;
  if (F.is_none()) {
    const MatrixX3d X = to_points(V, what);
    if (X.rows() != static_cast<Eigen::Index>(stored.n_vertices()))
      throw InvalidInput(std::string(what) + ": expected " + std::to_string(stored.n_vertices()) + " positions, got " +
                         std::to_string(X.rows()));
    set_positions(m, X);
    return m;
  }
  m = to_mesh(V, F);
  if (m.n_vertices() != stored.n_vertices() || faces(m) != faces(stored))
    throw InvalidInput(std::string(what) + ": must have the texture's connectivity (" +
                       std::to_string(stored.n_vertices()) + " vertices, " + std::to_string(stored.n_faces()) + " faces)");
  return m;
}

// texture_extract: a texture from a textured surface and its base (given or made).
void bind_texture_extraction(py::module_& m) {
  m.def("texture_extract", [](py::handle V, py::handle F, py::handle V_base, py::handle F_base, py::dict kw) {
    CallOptions call = call_options(kw);
    // As on the command line: the automatic base's options mean nothing with a given base (only the
    // options given reach here), and projection onto a base nothing without one.
    for (auto item : kw) {
      std::string name = py::cast<std::string>(item.first);
      if (!name.empty() && name.back() == '_') name.pop_back();
      if (!V_base.is_none() && BaseShapeOptions::table().find(name))
        throw InvalidOption("option " + name + " sets the automatic base; it does not apply with base=");
      if (V_base.is_none() && name == "project_onto_base") throw InvalidOption("option project_onto_base needs base=");
    }
    TextureExtractOptions o = to_options<TextureExtractOptions>(kw, call);
    o.base.progress = call.progress;
    const Mesh textured = to_mesh(V, F);
    std::optional<Mesh> base;
    if (!V_base.is_none()) base = F_base.is_none() ? same_connectivity(textured, V_base, F_base, "base") : to_mesh(V_base, F_base);
    RunTime time;
    const TextureExtraction r = run(call, [&] {
      return timed(time.seconds, [&] { return texture_extraction(textured, base ? &*base : nullptr, o); });
    });
    for (const auto& w : r.warnings) warn(w);  // the GIL held again
    // The texture, then the fields of `geotex texture extract --report` (texture/results.h), the options used.
    py::dict d = texture_dict(r.base, r.texture);
    put_results(d, r, texture_extraction_results());
    put_results(d, time, run_time_results());
    d["parameters"] = options_dict(o);
    return d;
  });
}

// texture_apply, texture_edit, texture_animate: a texture on its own base.
void bind_texture_editing(py::module_& m) {
  m.def("texture_apply", [](py::handle V_base, py::handle F, py::handle height, py::handle tilt, py::handle lean,
                            py::handle V_new, py::handle F_new, py::dict kw) {
    CallOptions call = call_options(kw);
    const TextureApplyOptions o = to_options<TextureApplyOptions>(kw, call);
    const PyTexture t = texture_of(V_base, F, height, tilt, lean);
    const Mesh base = V_new.is_none() ? t.base : same_connectivity(t.base, V_new, F_new, "base");
    return VArray(run(call, [&] { return apply_texture(base, t.texture, o); }));
  });

  m.def("texture_edit", [](py::handle V_base, py::handle F, py::handle height, py::handle tilt, py::handle lean,
                           py::dict kw) {
    CallOptions call = call_options(kw);
    const TextureEditOptions o = to_options<TextureEditOptions>(kw, call);
    const PyTexture t = texture_of(V_base, F, height, tilt, lean);
    const Texture edited = run(call, [&] { return edit_texture(t.base, t.texture, o); });
    py::dict d = texture_dict(t.base, edited);
    d["parameters"] = options_dict(o);
    return d;
  });

  m.def("texture_animate", [](py::handle V_base, py::handle F, py::handle height, py::handle tilt, py::handle lean,
                              py::dict kw) {
    CallOptions call = call_options(kw);
    const AnimationOptions o = to_options<AnimationOptions>(kw, call);
    const PyTexture t = texture_of(V_base, F, height, tilt, lean);
    const auto n = static_cast<py::ssize_t>(t.base.n_vertices());
    py::array_t<double> frames({static_cast<py::ssize_t>(o.frames), n, py::ssize_t(3)});
    double* out = frames.mutable_data();
    run(call, [&] {
      TextureAnimator animator(t.base, t.texture, o);
      for (int k = 0; k < o.frames; ++k) {
        const MatrixX3d X = animator.positions(k);
        Eigen::Map<VArray>(out + k * n * 3, n, 3) = X;
        report(call.progress, double(k + 1) / o.frames, "frames");
      }
    });
    py::dict d;
    d["frames"] = frames;
    d["F"] = FArray(faces(t.base));
    d["parameters"] = options_dict(o);
    return d;
  });
}

// texture_transfer, texture_atlas: a texture onto another surface.
void bind_texture_transfer(py::module_& m) {
  m.def("texture_transfer", [](py::handle V_base, py::handle F, py::handle height, py::handle tilt, py::handle lean,
                               py::handle V_target, py::handle F_target, py::handle source_near, py::handle target_near,
                               py::dict kw) {
    CallOptions call = call_options(kw);
    TransferOptions o = to_options<TransferOptions>(kw, call);
    const auto snear = point_or_none(source_near, "source_near"), tnear = point_or_none(target_near, "target_near");
    if (snear && kw.contains("source_center")) throw InvalidOption("give source_center or source_near, not both");
    if (tnear && kw.contains("target_center")) throw InvalidOption("give target_center or target_near, not both");
    o.progress = call.progress;
    const PyTexture s = texture_of(V_base, F, height, tilt, lean);
    const Mesh target = to_mesh(V_target, F_target);
    if (snear) o.source_center = nearest_vertex(s.base, *snear);
    if (tnear) o.target_center = nearest_vertex(target, *tnear);
    MatrixX3d Y;
    RunTime time;
    const TransferResult r = run(call, [&] {
      TransferResult res = timed(time.seconds, [&] { return transfer_texture(s.base, s.texture, target, o); });
      Y = apply_texture(res.target, res.texture, o.texture);
      return res;
    });
    for (const auto& w : r.warnings) warn(w);  // the GIL held again
    return textured_result(Y, r, transfer_results(), time, o);
  });

  m.def("texture_atlas", [](py::handle V_base, py::handle F, py::handle height, py::handle tilt, py::handle lean,
                            py::handle V_target, py::handle F_target, py::handle source_near, py::dict kw) {
    CallOptions call = call_options(kw);
    AtlasOptions o = to_options<AtlasOptions>(kw, call);
    const auto snear = point_or_none(source_near, "source_near");
    if (snear && kw.contains("source_center")) throw InvalidOption("give source_center or source_near, not both");
    o.progress = call.progress;
    const PyTexture s = texture_of(V_base, F, height, tilt, lean);
    const Mesh target = to_mesh(V_target, F_target);
    if (snear) o.source_center = nearest_vertex(s.base, *snear);
    MatrixX3d Y;
    RunTime time;
    const AtlasResult r = run(call, [&] {
      AtlasResult res = timed(time.seconds, [&] { return cover_with_texture(s.base, s.texture, target, o); });
      Y = apply_texture(res.target, res.texture, o.texture);
      return res;
    });
    for (const auto& w : r.warnings) warn(w);  // the GIL held again
    return textured_result(Y, r, atlas_results(), time, o);
  });
}

// read_texture, write_texture: texture files.
void bind_texture_files(py::module_& m) {
  m.def("read_texture", [](const std::string& path) {
    TextureFile f;
    {
      py::gil_scoped_release release;
      f = read_texture(path);
    }
    return texture_dict(f.base, f.texture);
  });

  m.def("write_texture", [](const std::string& path, py::handle V_base, py::handle F, py::handle height,
                            py::handle tilt, py::handle lean, bool binary) {
    const PyTexture t = texture_of(V_base, F, height, tilt, lean);
    py::gil_scoped_release release;
    write_texture(path, t.base, t.texture, binary);
  });
}

}  // namespace

void bind_texture(py::module_& m) {
  register_table<TextureExtractOptions>("TextureExtractOptions");
  register_table<TextureApplyOptions>("TextureApplyOptions");
  register_table<TextureEditOptions>("TextureEditOptions");
  register_table<AnimationOptions>("AnimationOptions");
  register_table<TransferOptions>("TransferOptions");
  register_table<AtlasOptions>("AtlasOptions");
  register_results("TextureExtraction", &texture_extraction_results);
  register_results("TransferResult", &transfer_results);
  register_results("AtlasResult", &atlas_results);

  bind_texture_extraction(m);
  bind_texture_editing(m);
  bind_texture_transfer(m);
  bind_texture_files(m);
}

}  // namespace geotex::python
