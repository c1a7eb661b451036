#pragma once
//! \file feature_file.h A user's feature map for feature-aware resizing (thesis ch. 9), from a file:
//! weights in [0, 1] per vertex (text, or a PLY's "feature" property), or a PLY's "height" property
//! thresholded into features (features_from_values() in feature_map.h). Texture synthesis reads its
//! weight file the same way.

#include <filesystem>
#include <string>

#include "geotex/core/io.h"
#include "geotex/core/mesh.h"
#include "geotex/core/options.h"

namespace geotex {

//! How a feature PLY's "height" becomes weights (features_from_values() in feature_map.h).
struct FeatureFileOptions {
  double height_threshold = 0.5;  //!< |height| threshold in mean edge lengths (option "height_threshold")
  int dilate = 2;                 //!< grow thresholded features by this many vertex rings (option "height_dilate")
  static const OptionTable<FeatureFileOptions>& table();
};

//! Feature weights from a PLY's vertex element: property "feature" (weights in [0, 1]) or "height"
//! (|height| / mean edge length > threshold, dilated). Returns #V weights.
//! \throw InvalidInput if the element does not match \p mesh or has neither property.
Eigen::VectorXd features_from_ply(const PlyData& ply, const Mesh& mesh, const FeatureFileOptions& options = {},
                                  const std::string& name = "<memory>");

//! A feature file: PLY (by extension) as features_from_ply(), anything else as parse_feature_weights() (core/user_files.h).
Eigen::VectorXd read_feature_file(const std::filesystem::path& path, const Mesh& mesh,
                                  const FeatureFileOptions& options = {});

}  // namespace geotex
