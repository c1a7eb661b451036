// Python bindings of height-and-tilt geometric texture (thesis ch. 8).

#include "common.h"

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/texture/texture.h"

namespace geotex::python {

namespace {
Texture texture_of(const Mesh& base, py::handle height, py::handle tilt) {
  return Texture{to_vector(height, base.n_vertices(), "height"), to_vector(tilt, base.n_edges(), "tilt")};
}
}  // namespace

void bind_texture(py::module_& m) {
  m.def("texture_extract", [](py::handle V, py::handle F, py::object V_base, int steps, double lambda_, const std::string& tilt_fit,
                              const std::string& tilt_solver) {
        if (tilt_fit != "tangential" && tilt_fit != "full")
          throw InvalidInput("texture_extract: tilt_fit must be 'tangential' or 'full', got '" + tilt_fit + "'");
        if (tilt_solver != "iterative" && tilt_solver != "direct")
          throw InvalidInput("texture_extract: tilt_solver must be 'iterative' or 'direct', got '" + tilt_solver + "'");
        const Mesh textured = to_mesh(V, F);
        MatrixX3d B;
        if (V_base.is_none()) {
          BaseShapeOptions o;
          o.steps = steps;
          o.lambda = lambda_;
          B = extract_base_shape(textured, o);
        } else {
          B = to_points(V_base, "V_base");
        }
        Mesh base = textured;
        set_positions(base, B);
        TextureOptions to;
        to.tangential_fit = tilt_fit == "tangential";
        to.solver = tilt_solver == "direct" ? TiltSolver::Direct : TiltSolver::Iterative;
        const Texture t = extract_texture(base, positions(textured), to);
        return py::dict(py::arg("V_base") = VArray(B), py::arg("height") = t.height, py::arg("tilt") = t.tilt,
                        py::arg("edges") = MatrixX2i(edges(base)));
      },
      py::arg("V"), py::arg("F"), py::arg("V_base") = py::none(), py::arg("steps") = 0, py::arg("lambda_") = 1.0,
      py::arg("tilt_fit") = "tangential", py::arg("tilt_solver") = "iterative",
      R"doc(Extract a height-and-tilt texture (Eq. 8.4–8.7). The base is V_base (same connectivity) or, by
default, implicit smoothing until the shape stops changing (steps=0). tilt_fit: "tangential" (the tilt's
tangent components) or "full" (Eq. 5.81 as in the thesis); tilt_solver: "iterative" or "direct" (as the
CLI's --tilt-fit and --tilt-solver). Returns V_base, height (#V), tilt (#E).)doc");

  m.def("texture_apply", [](py::handle V_base, py::handle F, py::handle height_, py::handle tilt_) {
        const Mesh base = to_mesh(V_base, F);
        return VArray(apply_texture(base, texture_of(base, height_, tilt_)));
      },
      py::arg("V_base"), py::arg("F"), py::arg("height"), py::arg("tilt"),
      "Reconstruct the textured surface from a base (any pose, same connectivity), heights and tilt (Eq. 8.8).");

  m.def("texture_edit", [](py::handle V_base, py::handle F, py::handle height_, py::handle tilt_,
                           const std::string& op, std::vector<double> direction, double angle, double wavelength,
                           double phase, double factor) {
        const Mesh base = to_mesh(V_base, F);
        TextureCodec codec(base);
        const Texture t = texture_of(base, height_, tilt_);
        if (direction.size() != 3) throw InvalidInput("direction must have 3 values");
        const Vec3 dir(direction[0], direction[1], direction[2]);
        Texture out;
        if (op == "set-tilt") out = set_tilt(codec, t, dir, angle);
        else if (op == "wrap") out = wrap(codec, t, dir, angle);
        else if (op == "wiggle")
          out = wiggle(codec, t, dir, angle, wavelength > 0 ? wavelength : bounding_box(base).diagonal() / 4, phase);
        else if (op == "scale-height") out = scale_height(t, factor);
        else throw InvalidInput("op must be set-tilt, wrap, wiggle or scale-height");
        return py::make_tuple(out.height, out.tilt);
      },
      py::arg("V_base"), py::arg("F"), py::arg("height"), py::arg("tilt"), py::arg("op"),
      py::arg("direction") = std::vector<double>{1, 0, 0}, py::arg("angle") = 30.0, py::arg("wavelength") = 0.0,
      py::arg("phase") = 0.0, py::arg("factor") = 1.0,
      "Edit a texture (Sec. 8.4.1): set-tilt, wrap, wiggle, scale-height. Returns (height, tilt).");

  m.def("texture_transfer", [](py::handle V_base, py::handle F, py::handle height_, py::handle tilt_,
                               py::handle V_target, py::handle F_target, int source_center, double source_radius, int target_center,
                               double target_radius, double rotation) {
        TransferOptions o;
        o.source_center = source_center;
        o.source_radius = source_radius;
        o.target_center = target_center;
        o.target_radius = target_radius;
        o.rotation_deg = rotation;
        const Mesh target = to_mesh(V_target, F_target);
        const Mesh source = to_mesh(V_base, F);
        const TransferResult r = transfer_texture(source, texture_of(source, height_, tilt_), target, o);
        // The texture lives on r.target (the target refined in the patch when it was coarser): apply it
        // there, and return its faces (applying it to the unrefined target failed with a size error).
        return py::dict(py::arg("height") = r.texture.height, py::arg("tilt") = r.texture.tilt,
                        py::arg("V") = VArray(apply_texture(r.target, r.texture)), py::arg("F") = FArray(faces(r.target)),
                        py::arg("target_vertices") = r.target_vertices);
      },
      py::arg("V_base"), py::arg("F"), py::arg("height"), py::arg("tilt"), py::arg("V_target"), py::arg("F_target"),
      py::arg("source_center"), py::arg("source_radius"), py::arg("target_center"), py::arg("target_radius"),
      py::arg("rotation") = 0.0,
      "Transfer a disk patch of texture to a disk patch of another base via conformal maps (Sec. 8.3.3).");
}

}  // namespace geotex::python
