// geotex deform IN --handles H.json -o OUT: Laplacian surface editing (thesis Sec. 5.1.4).
//
// Handles file (JSON):
//   {"handles": [ HANDLE, ... ]}
// HANDLE selects vertices by exactly one of
//   "vertices": [i, j, ...]                          vertex ids
//   "sphere": {"center": [x,y,z], "radius": r}       every vertex within r of the centre
//   "box": {"min": [x,y,z], "max": [x,y,z]}          every vertex inside the axis-aligned box
// and gives their targets by either
//   "targets": [[x,y,z], ...]                        one per id (only with "vertices")
// or a transform x ↦ R(s (x − c)) + c + t, applied in that order (a handle without one stays put):
//   "scale": s, "rotate": {"axis": [x,y,z], "angle_deg": a, "center": [x,y,z]}, "translate": [x,y,z],
//   "center": [x,y,z]   (c for scale and rotation; default: the centroid of the selected vertices;
//                         "rotate.center" overrides it for the rotation)
// Optional "weight": w_i of Eq. (5.19) for the handle's vertices (default --weight).

#include <chrono>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "cli.h"
#include "geotex/editing.h"

namespace geotex::cli {
namespace {

using json = nlohmann::json;

struct Args {
  std::string input, output, handles;
  std::string method = "linear", laplacian = "umbrella";
  double weight = 1.0;
  bool no_scale = false, literal = false, ascii = false;
};

Vec3 vec3(const json& j, const std::string& what) {
  if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
    throw InvalidInput(fmt::format("handles file: {} must be an array of three numbers", what));
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

struct Parsed {
  std::vector<int> ids;
  std::vector<double> weights;
  MatrixX3d targets;
};

Parsed parse_handles(const std::string& path, const Mesh& mesh, double default_weight) {
  std::ifstream in(path);
  if (!in) throw IoError(fmt::format("{}: cannot open", path));
  json doc;
  try {
    in >> doc;
  } catch (const json::exception& e) {
    throw IoError(fmt::format("{}: not valid JSON ({})", path, e.what()));
  }
  if (!doc.is_object() || !doc.contains("handles") || !doc["handles"].is_array() || doc["handles"].empty())
    throw InvalidInput(fmt::format("{}: expected {{\"handles\": [ ... ]}} with at least one handle", path));
  const MatrixX3d X = positions(mesh);
  const int n = static_cast<int>(X.rows());
  Parsed out;
  std::vector<Vec3> targets;
  int index = 0;
  for (const json& h : doc["handles"]) {
    const std::string where = fmt::format("{}: handle {}", path, index++);
    if (!h.is_object()) throw InvalidInput(where + " is not an object");
    const int selectors = h.contains("vertices") + h.contains("sphere") + h.contains("box");
    if (selectors != 1) throw InvalidInput(where + " needs exactly one of \"vertices\", \"sphere\", \"box\"");
    std::vector<int> ids;
    try {
      if (h.contains("vertices")) {
        for (const json& v : h["vertices"]) {
          const int id = v.get<int>();
          if (id < 0 || id >= n) throw InvalidInput(fmt::format("{}: vertex {} is out of range [0, {})", where, id, n));
          ids.push_back(id);
        }
      } else if (h.contains("sphere")) {
        const Vec3 c = vec3(h["sphere"].at("center"), where + " sphere.center");
        const double r = h["sphere"].at("radius").get<double>();
        for (int i = 0; i < n; ++i)
          if ((X.row(i).transpose() - c).norm() <= r) ids.push_back(i);
      } else {
        const Vec3 lo = vec3(h["box"].at("min"), where + " box.min"), hi = vec3(h["box"].at("max"), where + " box.max");
        for (int i = 0; i < n; ++i) {
          const Vec3 p = X.row(i).transpose();
          if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all()) ids.push_back(i);
        }
      }
    } catch (const json::exception& e) {
      throw InvalidInput(fmt::format("{}: {}", where, e.what()));
    }
    if (ids.empty()) throw InvalidInput(where + " selects no vertices");
    const double w = h.contains("weight") ? h["weight"].get<double>() : default_weight;
    if (h.contains("targets")) {
      if (!h.contains("vertices")) throw InvalidInput(where + ": \"targets\" needs \"vertices\"");
      if (!h["targets"].is_array() || h["targets"].size() != ids.size())
        throw InvalidInput(fmt::format("{}: {} targets for {} vertices", where, h["targets"].size(), ids.size()));
      for (const json& t : h["targets"]) targets.push_back(vec3(t, where + " target"));
    } else {
      Vec3 c = Vec3::Zero();
      for (int i : ids) c += X.row(i).transpose();
      c /= static_cast<double>(ids.size());
      if (h.contains("center")) c = vec3(h["center"], where + " center");
      const double s = h.contains("scale") ? h["scale"].get<double>() : 1.0;
      if (!(s > 0)) throw InvalidInput(where + ": scale must be positive");
      Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
      Vec3 rc = c;
      if (h.contains("rotate")) {
        const json& r = h["rotate"];
        const Vec3 axis = vec3(r.at("axis"), where + " rotate.axis");
        if (axis.norm() == 0) throw InvalidInput(where + ": rotation axis is zero");
        R = Eigen::AngleAxisd(r.at("angle_deg").get<double>() * M_PI / 180.0, axis.normalized()).toRotationMatrix();
        if (r.contains("center")) rc = vec3(r["center"], where + " rotate.center");
      }
      const Vec3 t = h.contains("translate") ? vec3(h["translate"], where + " translate") : Vec3::Zero();
      for (int i : ids) {
        const Vec3 scaled = c + s * (X.row(i).transpose() - c);
        targets.push_back(rc + R * (scaled - rc) + t);
      }
    }
    for (int i : ids) {
      out.ids.push_back(i);
      out.weights.push_back(w);
    }
  }
  out.targets.resize(targets.size(), 3);
  for (size_t k = 0; k < targets.size(); ++k) out.targets.row(k) = targets[k].transpose();
  return out;
}

void run(const Args& a) {
  check_output(a.input, a.output);
  Mesh mesh = load_mesh(a.input);
  const Parsed h = parse_handles(a.handles, mesh, a.weight);
  EditOptions o;
  o.method = a.method == "plain" ? EditMethod::Plain : a.method == "membrane-fit" ? EditMethod::MembraneFit : EditMethod::Linear;
  o.laplacian = a.laplacian == "cotan" ? LaplacianType::Cotangent : LaplacianType::Umbrella;
  o.handle_weight = a.weight;
  o.allow_scale = !a.no_scale;
  o.fit_to_rest_membrane = !a.literal;
  const auto t0 = std::chrono::steady_clock::now();
  const LaplacianEditor editor(mesh, h.ids, h.weights, o);
  const auto t1 = std::chrono::steady_clock::now();
  const MatrixX3d Y = editor.solve(h.targets);
  const auto t2 = std::chrono::steady_clock::now();
  const MatrixX3d X = positions(mesh);
  double worst = 0;
  for (size_t k = 0; k < h.ids.size(); ++k) worst = std::max(worst, (Y.row(h.ids[k]) - h.targets.row(k)).norm());
  info(fmt::format("deformed {} vertices with {} handle vertices ({}, {} Laplacian): factor {:.2f} s, solve {:.2f} s; "
                   "largest handle miss {:.3g}",
                   X.rows(), h.ids.size(), a.method, a.laplacian, std::chrono::duration<double>(t1 - t0).count(),
                   std::chrono::duration<double>(t2 - t1).count(), worst));
  set_positions(mesh, Y);
  save_mesh(mesh, a.output, !a.ascii);
}

Registrar reg{70, "deform", "Laplacian surface editing with handles (Sec. 5.1.4): plain, membrane-fit or linear", [](CLI::App& app) {
  auto a = std::make_shared<Args>();
  app.add_option("IN", a->input, "input mesh")->required()->check(ExistingMeshFile);
  app.add_option("--handles", a->handles,
                 "JSON handles file: {\"handles\": [{\"vertices\"|\"sphere\"|\"box\": ..., \"targets\"|\"translate\"|"
                 "\"rotate\"|\"scale\": ..., \"weight\": w}]} (see cmd_deform.cpp)")
      ->required()->check(CLI::ExistingFile);
  app.add_option("-o,--output", a->output, "output mesh")->required();
  app.add_option("--method", a->method,
                 "plain (Eq. 5.20), membrane-fit (T_i fitted to a membrane, Eq. 5.23-5.24) or linear (T_i linear in "
                 "the positions, Eq. 5.22, Sorkine et al. 2004)")
      ->check(CLI::IsMember({"plain", "membrane-fit", "linear"}))->capture_default_str();
  app.add_option("--laplacian", a->laplacian, "umbrella (Eq. 5.8) or cotan (row-normalised cotangent weights)")
      ->check(CLI::IsMember({"umbrella", "cotan"}))->capture_default_str();
  app.add_option("--weight", a->weight, "default handle weight w_i (Eq. 5.19)")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_flag("--no-scale", a->no_scale, "fit rotations only (no isotropic scale) in membrane-fit");
  app.add_flag("--literal-fit", a->literal, "membrane-fit: fit the original 1-ring to the membrane, as Eq. (5.24) reads");
  app.add_flag("--ascii", a->ascii, "ascii PLY/STL output");
  app.callback([a] { run(*a); });
}};

}  // namespace
}  // namespace geotex::cli
