// The option tables: one description per options struct (core/options.h).

#include <set>

#include <gtest/gtest.h>

#include "geotex/core/options.h"
#include "geotex/denoise/mrf.h"
#include "geotex/toolkit/editing.h"
#include "geotex/toolkit/parametrization.h"
#include "geotex/toolkit/phong_projection.h"
#include "geotex/toolkit/smoothing.h"
#include "geotex/tools/noise.h"

namespace geotex {
namespace {

template <class O>
void expect_table_is_consistent(const char* what) {
  const auto& t = O::table();
  std::set<std::string> names;
  const O defaults{};
  for (const auto& f : t.fields()) {
    EXPECT_TRUE(names.insert(f.info.name).second) << what << ": option " << f.info.name << " declared twice";
    EXPECT_FALSE(f.info.help.empty()) << what << ": " << f.info.name << " has no help";
    // The default (the struct's initializer) is valid, and survives text → value → struct → value.
    const OptionValue v = f.get(defaults);
    EXPECT_NO_THROW(check_option_value(f.info, v)) << what << ": default of " << f.info.name;
    O o;
    f.set(o, parse_option_value(f.info, format_option_value(v)));
    EXPECT_EQ(format_option_value(f.get(o)), format_option_value(v)) << what << ": " << f.info.name;
  }
  EXPECT_NO_THROW(t.check(defaults));
  for (const auto& p : t.presets()) {
    O o;
    p.apply(o);
    EXPECT_NO_THROW(t.check(o)) << what << ": preset " << p.name;
  }
}

TEST(Options, TablesAreConsistent) {
  expect_table_is_consistent<SmoothingOptions>("SmoothingOptions");
  expect_table_is_consistent<MrfOptions>("MrfOptions");
  expect_table_is_consistent<MrfNormalOptions>("MrfNormalOptions");
  expect_table_is_consistent<NoiseOptions>("NoiseOptions");
  expect_table_is_consistent<EditOptions>("EditOptions");
  expect_table_is_consistent<ParametrizationOptions>("ParametrizationOptions");
  expect_table_is_consistent<PhongProjectionOptions>("PhongProjectionOptions");
}

TEST(Options, SettingByNameReachesTheField) {
  MrfOptions o;
  const auto& t = MrfOptions::table();
  t.set(o, "alpha", 0.25);
  t.set(o, "phi0", int64_t{30});  // a nested field (EdgeProcessOptions), integer given for a real
  t.set(o, "potential", std::string("sqrt"));
  t.set(o, "iterations", int64_t{7});
  EXPECT_EQ(o.alpha, 0.25);
  EXPECT_EQ(o.edges.phi0_deg, 30.0);
  EXPECT_EQ(o.potential, SmoothnessPotential::SquareRoot);
  EXPECT_EQ(o.iterations, 7);
  EXPECT_THROW(t.set(o, "no_such_option", 1.0), InvalidOption);
}

TEST(Options, BadValuesAreRefusedWithTheOptionsName) {
  const auto& t = MrfOptions::table();
  const auto& alpha = t.find("alpha")->info;
  for (const char* bad : {"nan", "NaN", "inf", "-inf", "1e999", "-0.5", "", " 1", "1x", "0x10p", "auto"}) {
    try {
      parse_option_value(alpha, bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InvalidOption& e) {
      EXPECT_NE(std::string(e.what()).find("alpha"), std::string::npos) << e.what();
    }
  }
  const auto& phi0 = t.find("phi0")->info;
  EXPECT_THROW(parse_option_value(phi0, "181"), InvalidOption);
  EXPECT_NO_THROW(parse_option_value(phi0, "180"));
  const auto& it = t.find("iterations")->info;
  EXPECT_THROW(parse_option_value(it, "2.5"), InvalidOption);
  EXPECT_THROW(parse_option_value(it, "1e300"), InvalidOption);
  EXPECT_THROW(parse_option_value(it, "99999999999"), InvalidOption);  // beyond int
  EXPECT_EQ(std::get<int64_t>(parse_option_value(it, "1e3")), 1000);
  EXPECT_THROW(parse_option_value(t.find("potential")->info, "cubic"), InvalidOption);
  MrfOptions o;
  o.alpha = std::nan("");
  EXPECT_THROW(t.check(o), InvalidOption);
}

TEST(Options, ThesisPresetSetsTheThesisRun) {
  MrfOptions o;
  MrfOptions::table().apply_preset(o, "thesis");
  EXPECT_EQ(o.optimizer, MrfOptimizer::Metropolis);
  EXPECT_EQ(o.iterations, 20);
  EXPECT_EQ(o.edges.temperature, 0.05);
  EXPECT_EQ(o.edges.cooling, 0.9);
  EXPECT_EQ(o.alpha, 0.1);
  EXPECT_EQ(o.edges.phi0_deg, 40.0);
  EXPECT_THROW(MrfOptions::table().apply_preset(o, "best"), InvalidOption);
}

TEST(Options, Vec3AndAutomaticValues) {
  OptionInfo v;
  v.name = "direction";
  v.kind = OptionKind::Vec3;
  EXPECT_EQ(std::get<Vec3>(parse_option_value(v, "1,0,-2.5")), Vec3(1, 0, -2.5));
  for (const char* bad : {"1,0", "1,0,0,0", "1,,0", "1,nan,0", "a,b,c"}) EXPECT_THROW(parse_option_value(v, bad), InvalidOption) << bad;
  OptionInfo a;
  a.name = "alpha";
  a.kind = OptionKind::Real;
  a.automatic = true;
  EXPECT_TRUE(std::holds_alternative<std::monostate>(parse_option_value(a, "auto")));
  EXPECT_EQ(format_option_value(std::monostate{}), "auto");
}

}  // namespace
}  // namespace geotex
