// Python bindings of the capabilities beyond the foundation: denoising (MRF, surfels), point-cloud
// surfels, parametrization, Laplacian editing, auto diffusion function, feature-aware resizing,
// Phong projection, 1-forms and height-and-tilt texture. Options are keyword arguments whose
// defaults are the library's option-struct defaults (which the CLI uses too); an unknown keyword
// raises TypeError.

#include "common.h"

#include <set>

#include <fmt/format.h>

#include "geotex/toolkit/diffusion.h"
#include "geotex/toolkit/editing.h"
#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/denoise/mrf.h"
#include "geotex/toolkit/one_form.h"
#include "geotex/toolkit/parametrization.h"
#include "geotex/toolkit/phong_projection.h"
#include "geotex/resize/resize.h"
#include "geotex/denoise/surfel.h"
#include "geotex/texture/texture.h"

namespace geotex::python {

namespace {

using V3 = Eigen::Ref<const MatrixX3d>;
using F3 = Eigen::Ref<const MatrixX3i>;

// Keyword arguments consumed by name; whatever is left at the end is an error.
class Kwargs {
 public:
  explicit Kwargs(const py::kwargs& kw, std::string where) : where_(std::move(where)) {
    for (auto item : kw) map_[py::cast<std::string>(item.first)] = py::reinterpret_borrow<py::object>(item.second);
  }
  template <class T>
  void get(const char* name, T& out) {
    auto it = map_.find(name);
    if (it == map_.end()) return;
    if (!it->second.is_none()) out = py::cast<T>(it->second);
    map_.erase(it);
  }
  bool has(const char* name) const { return map_.count(name) > 0; }
  void finish() const {
    if (map_.empty()) return;
    std::vector<std::string> names;
    for (const auto& [k, v] : map_) names.push_back(k);
    throw py::type_error(fmt::format("{}: unexpected keyword argument(s): {}", where_, fmt::join(names, ", ")));
  }

 private:
  std::string where_;
  std::map<std::string, py::object> map_;
};

void edge_options(Kwargs& kw, EdgeProcessOptions& e) {
  std::string ridges = to_string(e.ridges), opt = to_string(e.optimizer);
  kw.get("phi0", e.phi0_deg);
  kw.get("phi0_start", e.phi0_start_deg);
  kw.get("support", e.support_weight);
  kw.get("te", e.temperature);
  kw.get("te_cooling", e.cooling);
  kw.get("edge_sweeps", e.sweeps);
  kw.get("quench", e.quench);
  kw.get("ridges", ridges);
  kw.get("edge_optimizer", opt);
  e.ridges = parse_ridges(ridges);
  e.optimizer = parse_optimizer(opt);
}

// Options common to MrfOptions and MrfNormalOptions (same field names in both structs).
template <class Options>
void mrf_common_options(Kwargs& kw, Options& o) {
  std::string optimizer = to_string(o.optimizer), potential = to_string(o.potential);
  kw.get("alpha", o.alpha);
  kw.get("iterations", o.iterations);
  kw.get("seed", o.seed);
  kw.get("optimizer", optimizer);
  kw.get("potential", potential);
  kw.get("tv", o.temperature);
  kw.get("tv_cooling", o.cooling);
  kw.get("step", o.step);
  kw.get("tolerance", o.tolerance);
  kw.get("initial_labels", o.initial_labels_from_angles);
  edge_options(kw, o.edges);
  o.optimizer = parse_optimizer(optimizer);
  o.potential = parse_potential(potential);
}

py::dict mrf_result(const Mesh& input, const MrfResult& r) {
  Mesh out = input;
  set_positions(out, r.positions);
  py::dict d;
  d["V"] = VArray(r.positions);
  d["F"] = FArray(faces(out));
  d["edge_labels"] = r.edge_labels;
  d["edges"] = MatrixX2i(edges(out));
  d["vertex_energy"] = r.vertex_energy;
  d["edge_energy"] = r.edge_energy;
  d["iterations"] = r.iterations;
  d["converged"] = r.converged;
  return d;
}

py::dict denoise(V3 V, F3 F, const std::string& method, const py::kwargs& kwargs) {
  const Mesh mesh = to_mesh(V, F);
  Kwargs kw(kwargs, "denoise(method='" + method + "')");
  if (method == "mrf") {
    MrfOptions o;
    mrf_common_options(kw, o);
    kw.get("sweeps", o.vertex_sweeps);
    kw.finish();
    MrfResult r;
    {
      py::gil_scoped_release release;
      r = mrf_denoise(mesh, o);
    }
    return mrf_result(mesh, r);
  }
  if (method == "mrf-normal") {
    MrfNormalOptions o;
    mrf_common_options(kw, o);
    kw.get("normal_sweeps", o.normal_sweeps);
    kw.get("vertex_iterations", o.vertex_iterations);
    kw.get("rounds", o.rounds);
    kw.finish();
    MrfResult r;
    {
      py::gil_scoped_release release;
      r = mrf_normal_denoise(mesh, o);
    }
    return mrf_result(mesh, r);
  }
  if (method == "surfel") {
    SurfelOptions o;
    std::string retrieval = "dual", preset = "thesis";
    kw.get("preset", preset);
    if (preset != "thesis" && preset != "tuned") throw InvalidInput("preset must be 'thesis' or 'tuned'");
    const bool tuned = preset == "tuned";
    const bool given_iterations = kw.has("iterations"), given_t_start = kw.has("t_start"),
               given_weights = kw.has("weights");
    if (tuned && !kw.has("retrieval")) retrieval = "fit";
    kw.get("alpha", o.alpha);
    kw.get("beta", o.beta);
    kw.get("iterations", o.iterations);
    kw.get("t_start", o.t_start_deg);
    kw.get("t_end", o.t_end_deg);
    kw.get("iterations_per_threshold", o.iterations_per_threshold);
    kw.get("candidates", o.candidates);
    kw.get("guided", o.guided);
    kw.get("cluster_moves", o.cluster_moves);
    std::string weights = "lagged";
    kw.get("weights", weights);
    kw.get("retrieval", retrieval);
    kw.finish();
    if (retrieval != "dual" && retrieval != "primal" && retrieval != "fit")
      throw InvalidInput("retrieval must be 'dual', 'primal' or 'fit'");
    if (weights != "lagged" && weights != "irls") throw InvalidInput("weights must be 'lagged' or 'irls'");
    o.irls_weights = weights == "irls";
    const MatrixX3d X = positions(mesh);
    Mesh out;
    SurfelResult r;
    {
      py::gil_scoped_release release;
      o.unit_length = mean_edge_length(mesh);
      const Neighborhoods N = one_ring_neighborhoods(mesh);
      const Surfels S0 = initial_surfels(mesh);
      if (tuned) {  // the preset, under any option given explicitly (as the CLI's --surfel-preset)
        const SurfelOptions t = tuned_surfel_options(S0, N, o);
        if (!given_iterations) o.iterations = t.iterations;
        if (!given_t_start) o.t_start_deg = t.t_start_deg;
        if (!given_weights) o.irls_weights = t.irls_weights;
        o.cluster_moves = t.cluster_moves;
      }
      r = optimize_surfels(X, N, S0, o);
      out = retrieval == "dual"  ? triangulate_polygons(surfel_dual_polygons(mesh, X, r.surfels))
            : retrieval == "fit" ? surfel_fitted_mesh(mesh, X, r.surfels)
                                 : surfel_primal_mesh(mesh, X, r.surfels);
    }
    py::dict d;
    d["V"] = VArray(positions(out));
    d["F"] = FArray(faces(out));
    d["edge_labels"] = py::none();
    d["normals"] = VArray(r.surfels.normals);
    d["offsets"] = r.surfels.offsets;
    d["energy"] = r.energy;
    return d;
  }
  throw InvalidInput(fmt::format("unknown denoising method '{}' (mrf, mrf-normal, surfel)", method));
}

ParamMethod param_method(const std::string& s) {
  if (s == "conformal") return ParamMethod::Conformal;
  if (s == "authalic") return ParamMethod::Authalic;
  if (s == "combined") return ParamMethod::Combined;
  if (s == "natural") return ParamMethod::NaturalConformal;
  throw InvalidInput("method must be conformal, authalic, combined or natural");
}

EditMethod edit_method(const std::string& s) {
  if (s == "plain") return EditMethod::Plain;
  if (s == "membrane-fit") return EditMethod::MembraneFit;
  if (s == "linear") return EditMethod::Linear;
  throw InvalidInput("method must be plain, membrane-fit or linear");
}

LaplacianType lap(const std::string& s) {
  if (s == "umbrella") return LaplacianType::Umbrella;
  if (s == "cotan") return LaplacianType::Cotangent;
  throw InvalidInput("laplacian must be umbrella or cotan");
}

}  // namespace

void bind_extras(py::module_& m) {
  m.def("denoise", &denoise, py::arg("V"), py::arg("F"), py::arg("method") = "mrf",
        R"doc(Denoise a mesh (thesis ch. 6 and 7); the same methods and defaults as `geotex denoise`.

method='mrf' (vertex + edge process) or 'mrf-normal' (face-normal MRF + edge process) take:
  alpha, iterations, seed, optimizer ('metropolis'|'icm'|'cg'|'lbfgs'), potential ('quadratic'|'sqrt'),
  tv, tv_cooling, step, sweeps (mrf) / normal_sweeps, vertex_iterations, rounds (mrf-normal), tolerance,
  initial_labels, and the edge process' phi0 (degrees), phi0_start, support, te, te_cooling, edge_sweeps,
  quench, ridges ('all'|'convex'|'concave'), edge_optimizer ('metropolis'|'icm').
method='surfel' takes alpha, beta, iterations, t_start, t_end (degrees), iterations_per_threshold,
  candidates, guided, cluster_moves, weights ('lagged' as in the thesis | 'irls'), retrieval ('dual'|'primal'|'fit'),
  preset ('thesis' | 'tuned': irls weights, cluster moves, fit retrieval, 30 iterations, automatic t_start).

Returns a dict with V, F (the result), edge_labels (per edge of edges, or None) and energies.)doc");

  m.def("point_surfels", [](V3 P, int neighbors, int normal_neighbors, const py::kwargs& kwargs) {
        Kwargs kw(kwargs, "point_surfels");
        SurfelOptions o;
        kw.get("alpha", o.alpha);
        kw.get("beta", o.beta);
        kw.get("iterations", o.iterations);
        kw.get("t_start", o.t_start_deg);
        kw.get("t_end", o.t_end_deg);
        kw.get("unit", o.unit_length);
        kw.finish();
        const MatrixX3d X = P;
        SurfelResult r;
        {
          py::gil_scoped_release release;
          const Neighborhoods N = knn_neighborhoods(X, neighbors);
          r = optimize_surfels(X, N, surfels_from_normals(X, pca_normals(X, normal_neighbors)), o);
        }
        return py::make_tuple(VArray(surfel_centers(X, r.surfels)), VArray(r.surfels.normals));
      },
      py::arg("P"), py::arg("neighbors") = 10, py::arg("normal_neighbors") = 10,
      "Surfel reconstruction of a point cloud (kNN neighbourhoods; `geotex surfels`). Returns (centres, normals).");

  m.def("pca_normals", [](V3 P, int k) { return VArray(pca_normals(P, k)); }, py::arg("P"), py::arg("k") = 10,
        "Consistently oriented PCA normals of a point cloud.");

  m.def("parametrize", [](V3 V, F3 F, const std::string& method, double conformal_weight) {
        ParametrizationOptions o;
        o.method = param_method(method);
        o.conformal_weight = conformal_weight;
        return MatrixX2d(parametrize(to_mesh(V, F), o));
      },
      py::arg("V"), py::arg("F"), py::arg("method") = "conformal", py::arg("conformal_weight") = 0.5,
      "UV coordinates (#V×2) of a disk: conformal, authalic, combined or natural (Sec. 5.4). InvalidInput if not a disk.");

  m.def("deform", [](V3 V, F3 F, const std::vector<int>& handles, V3 targets, const std::string& method,
                     const std::string& laplacian, double handle_weight, bool allow_scale) {
        EditOptions o;
        o.method = edit_method(method);
        o.laplacian = lap(laplacian);
        o.handle_weight = handle_weight;
        o.allow_scale = allow_scale;
        const Mesh mesh = to_mesh(V, F);
        py::gil_scoped_release release;
        return VArray(laplacian_edit(mesh, handles, targets, o));
      },
      py::arg("V"), py::arg("F"), py::arg("handles"), py::arg("targets"), py::arg("method") = "linear",
      py::arg("laplacian") = "umbrella", py::arg("handle_weight") = 1.0, py::arg("allow_scale") = true,
      "Laplacian surface editing (Eq. 5.15–5.24): handle vertex ids and their #handles×3 targets. Returns #V×3.");

  m.def("auto_diffusion_function", [](V3 V, F3 F, double t, int eigenpairs) {
        DiffusionOptions o;
        o.t = t;
        o.eigenpairs = eigenpairs;
        const Mesh mesh = to_mesh(V, F);
        py::gil_scoped_release release;
        return Eigen::VectorXd(auto_diffusion_function(mesh, o));
      },
      py::arg("V"), py::arg("F"), py::arg("t") = 0.1, py::arg("eigenpairs") = 100,
      "Auto diffusion function (Gebal et al. 2009), one value per vertex.");

  m.def("resize", [](V3 V, F3 F, py::object scale, py::object deformed, py::object features, const std::string& method,
                     double feature_threshold) {
        const Mesh mesh = to_mesh(V, F);
        Eigen::VectorXd f;
        if (features.is_none() || (py::isinstance<py::str>(features) && py::cast<std::string>(features) == "auto")) {
          f = features_from_adf(mesh, 0.1, 100, feature_threshold);
        } else if (py::isinstance<py::str>(features) && py::cast<std::string>(features) == "height") {
          f = features_from_height(mesh);
        } else {
          f = py::cast<Eigen::VectorXd>(features);
          if (f.size() != static_cast<Eigen::Index>(mesh.n_vertices()))
            throw InvalidInput("features must have one weight per vertex");
        }
        ResizeOptions o;
        if (method == "sliding") o.method = ResizeMethod::Sliding;
        else if (method == "thesis") o.method = ResizeMethod::Thesis;
        else throw InvalidInput("method must be 'sliding' or 'thesis'");
        if (!deformed.is_none()) {
          const MatrixX3d D = py::cast<MatrixX3d>(deformed);
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

  m.def("phong_project", [](V3 V, F3 F, V3 P) {
        const Mesh mesh = to_mesh(V, F);
        const PhongProjector proj(mesh);
        const std::vector<PhongHit> hits = proj.project(MatrixX3d(P));
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
      },
      py::arg("V"), py::arg("F"), py::arg("P"),
      "Project points onto a mesh along its Phong-interpolated normal field (Sec. 5.2; analytic cubic). face = −1 where none.");

  m.def("one_form_fit", [](V3 V, F3 F, V3 T, bool bound_by_edge_length) {
        OneFormFitOptions o;
        o.bound_by_edge_length = bound_by_edge_length;
        return Eigen::VectorXd(fit_one_form(to_mesh(V, F), T, o));
      },
      py::arg("V"), py::arg("F"), py::arg("T"), py::arg("bound_by_edge_length") = false,
      "Least-squares 1-form (Eq. 5.81–5.82) of a per-vertex tangent field T (#V×3); one coefficient per edge.");
  m.def("one_form_to_vertices", [](V3 V, F3 F, const Eigen::VectorXd& c) {
        return VArray(one_form_to_vertices(to_mesh(V, F), c));
      },
      py::arg("V"), py::arg("F"), py::arg("c"), "Per-vertex vectors from edge coefficients (Eq. 5.78–5.79).");

  m.def("texture_extract", [](V3 V, F3 F, py::object V_base, int steps, double lambda_, const std::string& tilt_fit,
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
          B = py::cast<MatrixX3d>(V_base);
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

  m.def("texture_apply", [](V3 V_base, F3 F, const Eigen::VectorXd& height, const Eigen::VectorXd& tilt) {
        Texture t{height, tilt};
        return VArray(apply_texture(to_mesh(V_base, F), t));
      },
      py::arg("V_base"), py::arg("F"), py::arg("height"), py::arg("tilt"),
      "Reconstruct the textured surface from a base (any pose, same connectivity), heights and tilt (Eq. 8.8).");

  m.def("texture_edit", [](V3 V_base, F3 F, const Eigen::VectorXd& height, const Eigen::VectorXd& tilt,
                           const std::string& op, std::vector<double> direction, double angle, double wavelength,
                           double phase, double factor) {
        const Mesh base = to_mesh(V_base, F);
        TextureCodec codec(base);
        const Texture t{height, tilt};
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

  m.def("texture_transfer", [](V3 V_base, F3 F, const Eigen::VectorXd& height, const Eigen::VectorXd& tilt,
                               V3 V_target, F3 F_target, int source_center, double source_radius, int target_center,
                               double target_radius, double rotation) {
        TransferOptions o;
        o.source_center = source_center;
        o.source_radius = source_radius;
        o.target_center = target_center;
        o.target_radius = target_radius;
        o.rotation_deg = rotation;
        const Mesh target = to_mesh(V_target, F_target);
        const TransferResult r = transfer_texture(to_mesh(V_base, F), Texture{height, tilt}, target, o);
        return py::dict(py::arg("height") = r.texture.height, py::arg("tilt") = r.texture.tilt,
                        py::arg("V") = VArray(apply_texture(target, r.texture)),
                        py::arg("target_vertices") = r.target_vertices);
      },
      py::arg("V_base"), py::arg("F"), py::arg("height"), py::arg("tilt"), py::arg("V_target"), py::arg("F_target"),
      py::arg("source_center"), py::arg("source_radius"), py::arg("target_center"), py::arg("target_radius"),
      py::arg("rotation") = 0.0,
      "Transfer a disk patch of texture to a disk patch of another base via conformal maps (Sec. 8.3.3).");
}

}  // namespace geotex::python
