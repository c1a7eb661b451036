// Result descriptions (results.h).

#include "geotex/core/results.h"

#include <fmt/format.h>

#include "geotex/core/geometry.h"
#include "geotex/core/io.h"

namespace geotex {

std::string figure_text(const ResultFieldInfo& field, const nlohmann::json& value) {
  std::string label = field.name;
  if (!field.unit.empty() && label.size() > field.unit.size() + 1 &&
      label.compare(label.size() - field.unit.size() - 1, std::string::npos, "_" + field.unit) == 0)
    label.resize(label.size() - field.unit.size() - 1);
  std::replace(label.begin(), label.end(), '_', ' ');
  std::string text;
  if (value.is_null()) text = "none";
  else if (value.is_boolean()) text = value.get<bool>() ? "yes" : "no";
  else if (value.is_number_integer()) text = std::to_string(value.get<long long>());
  else if (value.is_number()) text = fmt::format("{:.3g}", value.get<double>());
  else if (value.is_string()) text = value.get<std::string>();
  else throw std::logic_error("result field " + field.name + " is an array or a record: not said in a caption");
  // A field named after its unit is said as the value and the unit: "seconds 0.38 s" is "0.38 s".
  static const std::pair<const char*, const char*> kUnitNames[] = {{"s", "seconds"}, {"deg", "degrees"}};
  for (const auto& [unit, name] : kUnitNames)
    if (field.unit == unit && label == name) return text + " " + field.unit;
  return label + " " + text + (field.unit.empty() ? "" : " " + field.unit);
}

nlohmann::json array_json(const Eigen::MatrixXd& a) {
  nlohmann::json j = nlohmann::json::array();
  if (a.cols() == 1) {
    for (Eigen::Index i = 0; i < a.rows(); ++i) j.push_back(a(i, 0));
    return j;
  }
  for (Eigen::Index i = 0; i < a.rows(); ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index k = 0; k < a.cols(); ++k) row.push_back(a(i, k));
    j.push_back(std::move(row));
  }
  return j;
}

const ResultTable<RunTime>& run_time_results() {
  static const auto t =
      ResultTable<RunTime>().add("seconds", [](const RunTime& r) { return r.seconds; }, "wall time of the call", "s");
  return t;
}

const ResultTable<MeshSummary>& mesh_summary_results() {
  using R = MeshSummary;
  auto point = [](const Vec3& p) { return std::vector<double>{p[0], p[1], p[2]}; };
  static const auto t = ResultTable<R>()
      .add("vertices", [](const R& r) { return r.vertices; }, "vertices")
      .add("edges", [](const R& r) { return r.edges; }, "edges")
      .add("faces", [](const R& r) { return r.faces; }, "faces")
      .add("components", [](const R& r) { return r.components; }, "connected components")
      .add("boundary_loops", [](const R& r) { return r.boundary_loops; }, "boundary loops")
      .add("closed", [](const R& r) { return r.closed; }, "no boundary")
      .add("euler_characteristic", [](const R& r) { return r.euler; }, "V - E + F")
      .add("genus", [](const R& r) { return r.genus >= 0 ? std::optional<int>(r.genus) : std::nullopt; },
           "(2 - chi - b) / 2 of a single component; none for several")
      .add("mean_edge_length", [](const R& r) { return r.mean_edge; }, "mean edge length")
      .add("area", [](const R& r) { return r.area; }, "surface area")
      .add("volume", [](const R& r) { return r.closed ? std::optional<double>(r.volume) : std::nullopt; },
           "enclosed volume of a closed mesh (negative: turned inside out); none for an open one")
      .add("zero_area_faces", [](const R& r) { return r.zero_area_faces; }, "faces of zero area")
      .add("isolated_vertices", [](const R& r) { return r.isolated_vertices; }, "vertices of no face")
      .add("bbox_min", [point](const R& r) { return point(r.box.min); }, "the bounding box's lowest corner")
      .add("bbox_max", [point](const R& r) { return point(r.box.max); }, "the bounding box's highest corner")
      .add("bbox_diagonal", [](const R& r) { return r.box.diagonal(); }, "the bounding box's diagonal");
  return t;
}

const ResultTable<ReadReport>& read_report_results() {
  using R = ReadReport;
  static const auto t = ResultTable<R>()
      .add("file_vertices", [](const R& r) { return r.file_vertices; }, "vertices in the file")
      .add("file_polygons", [](const R& r) { return r.file_polygons; }, "faces (or strips) in the file")
      .add("triangulated_polygons", [](const R& r) { return r.triangulated_polygons; },
           "polygons with more than 3 corners split into fans")
      .add("strip_triangles", [](const R& r) { return r.strip_triangles; }, "triangles decoded from triangle strips")
      .add("dropped_degenerate_faces", [](const R& r) { return r.build.degenerate_faces; },
           "faces repeating a vertex: dropped")
      .add("dropped_duplicate_faces", [](const R& r) { return r.build.duplicate_faces; },
           "faces on the vertices of an earlier one: dropped")
      .add("dropped_nonmanifold_faces", [](const R& r) { return r.build.nonmanifold_faces; },
           "faces no manifold mesh can hold: dropped")
      .add("flipped_faces", [](const R& r) { return r.build.flipped_faces; },
           "faces turned round to agree with their neighbours")
      .add("split_vertices", [](const R& r) { return r.build.split_vertices; },
           "non-manifold vertices split into one per fan")
      .add("added_vertices", [](const R& r) { return r.build.added_vertices; }, "copies the split made");
  return t;
}

}  // namespace geotex
