// A user's feature map from a file (feature_file.h).

#include "geotex/resize/feature_file.h"

#include <cctype>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/user_files.h"
#include "geotex/resize/feature_map.h"

namespace geotex {

namespace fs = std::filesystem;

const OptionTable<FeatureFileOptions>& FeatureFileOptions::table() {
  using O = FeatureFileOptions;
  static const auto t = OptionTable<O>()
      .add("height_threshold", &O::height_threshold,
           "feature PLY with 'height': features where |height| exceeds this many mean edge lengths", positive())
      .add("height_dilate", &O::dilate, "feature PLY with 'height': grow the thresholded features by this many vertex rings",
           between(0, 10000));
  return t;
}

Eigen::VectorXd features_from_ply(const PlyData& ply, const Mesh& mesh, const FeatureFileOptions& options,
                                  const std::string& name) {
  check_options(options);
  const size_t n = mesh.n_vertices();
  const PlyElement* v = ply.find("vertex");
  if (!v || v->count != n)
    throw InvalidInput(fmt::format("{}: needs {} vertices (the input's), has {}", name, n, v ? v->count : 0));
  for (const char* prop : {"feature", "height"}) {
    if (!v->scalars.count(prop)) continue;
    const auto& s = v->scalars.at(prop);
    if (s.size() != n)  // e.g. a property declared twice
      throw InvalidInput(fmt::format("{}: {} values of '{}' for {} vertices", name, s.size(), prop, n));
    Eigen::VectorXd values = Eigen::Map<const Eigen::VectorXd>(s.data(), static_cast<Eigen::Index>(n));
    if (!values.allFinite()) throw InvalidInput(fmt::format("{}: non-finite '{}' value", name, prop));
    if (std::string(prop) == "feature") {
      require_unit_weights(values, name);
      return values;
    }
    const double h = mean_edge_length(mesh);
    if (!(h > 0)) throw InvalidInput(fmt::format("{}: 'height' needs a mesh with edges", name));
    return features_from_values(mesh, values / h, options.height_threshold, options.dilate);
  }
  throw InvalidInput(fmt::format("{}: no vertex property \"feature\" or \"height\"", name));
}

Eigen::VectorXd read_feature_file(const fs::path& path, const Mesh& mesh, const FeatureFileOptions& options) {
  check_options(options);
  std::string e = path.extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (e == ".ply") return features_from_ply(read_ply_data(path), mesh, options, path.string());
  return parse_feature_weights(read_regular_file(path, kMaxTextFileBytes, "a feature file"), mesh.n_vertices(), path.string());
}

}  // namespace geotex
