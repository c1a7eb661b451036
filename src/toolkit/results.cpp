// The toolkit's results as the front ends show them (toolkit/results.h); the names are those
// `geotex param --json` used before the table.

#include "geotex/toolkit/results.h"

namespace geotex {

const ResultTable<ParamQuality>& param_quality_results() {
  using R = ParamQuality;
  static const auto t = ResultTable<R>()
      .add("flipped", [](const R& r) { return r.flipped; }, "faces with a non-positive signed UV area")
      .add("mean_angle_error_deg", [](const R& r) { return r.mean_angle_error_deg; },
           "mean |angle in UV - angle in 3D| over all face corners", "deg")
      .add("max_angle_error_deg", [](const R& r) { return r.max_angle_error_deg; },
           "largest |angle in UV - angle in 3D| of a face corner", "deg")
      .add("mean_log_area_ratio", [](const R& r) { return r.mean_log_area_ratio; },
           "area distortion: area-weighted mean over faces of |log(UV area share / 3D area share)|");
  return t;
}

}  // namespace geotex
