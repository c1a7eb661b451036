// Result tables (core/results.h): a caption's figures are said from the same table as the report's keys.

#include <gtest/gtest.h>

#include <optional>

#include <fmt/format.h>
#include <stdexcept>

#include "geotex/core/results.h"
#include "geotex/tools/metrics.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/results.h"
#include "geotex/tools/shapes.h"

namespace geotex {
namespace {

struct Sample {
  double error = 2.8149;
  int count = 3;
  bool ok = true;
  std::string name = "cube";
  std::optional<double> volume;
  Eigen::VectorXd values = Eigen::VectorXd::Ones(2);
};

const ResultTable<Sample>& sample_results() {
  static const auto t = ResultTable<Sample>()
      .add("mean_error_deg", [](const Sample& r) { return r.error; }, "mean error", "deg")
      .add("count", [](const Sample& r) { return r.count; }, "things counted")
      .add("ok", [](const Sample& r) { return r.ok; }, "it worked")
      .add("name", [](const Sample& r) { return r.name; }, "what it is")
      .add("volume", [](const Sample& r) { return r.volume; }, "enclosed volume")
      .array("values", [](const Sample& r) { return r.values; }, "per vertex");
  return t;
}

TEST(ResultTable, FiguresSayTheAskedFieldsInOrderWithTheUnitOffTheNameAndOnTheValue) {
  const Sample s;
  EXPECT_EQ(sample_results().figures(s, {"mean_error_deg", "count", "ok", "name", "volume"}),
            "mean error 2.81 deg, count 3, ok yes, name cube, volume none");
  EXPECT_EQ(sample_results().figures(s, {"name", "count"}), "name cube, count 3");
  Sample big;
  big.error = 12345.6;
  big.ok = false;
  EXPECT_EQ(sample_results().figures(big, {"mean_error_deg", "ok"}), "mean error 1.23e+04 deg, ok no");
  EXPECT_EQ(run_time_results().figures(RunTime{0.3841}, {"seconds"}), "0.384 s");  // named after its unit
}

TEST(ResultTable, FiguresRefuseANameTheTableDoesNotHaveAndAnArray) {
  const Sample s;
  EXPECT_THROW(sample_results().figures(s, {"mean_error"}), std::logic_error);
  EXPECT_THROW(sample_results().figures(s, {"values"}), std::logic_error);
}

// A caption's figure is the report's value, rounded to three significant digits.
TEST(ResultTable, ACaptionsFigureIsTheReportsValue) {
  const Mesh clean = icosphere(2, 1.0);
  Mesh noisy = clean;
  NoiseOptions n;
  n.sigma = 0.2;
  set_positions(noisy, add_noise(clean, n));
  const Comparison c = compare_meshes(noisy, clean);
  const std::string said = comparison_results().figures(c, {"mean_normal_error_deg", "ev_relative"});
  const nlohmann::json report = comparison_results().report(c);
  const double error = report.at("mean_normal_error_deg").get<double>();
  const double ev = report.at("ev_relative").get<double>();
  ASSERT_GT(error, 0);
  EXPECT_EQ(said, fmt::format("mean normal error {:.3g} deg, ev relative {:.3g}", error, ev));
  const std::string number = said.substr(said.find("error ") + 6, said.find(" deg") - said.find("error ") - 6);
  EXPECT_NEAR(std::stod(number), error, 0.005 * error);
}

}  // namespace
}  // namespace geotex
