// Result descriptions (results.h).

#include "geotex/core/results.h"

namespace geotex {

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

}  // namespace geotex
