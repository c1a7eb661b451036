// The option tables: one description per options struct (core/options.h).

#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/core/options.h"
#include "geotex/denoise/auto_denoise.h"
#include "geotex/denoise/mrf.h"
#include "geotex/denoise/point_surfels.h"
#include "geotex/denoise/reading_model.h"
#include "geotex/denoise/surfel.h"
#include "geotex/resize/feature_file.h"
#include "geotex/resize/feature_map.h"
#include "geotex/resize/resize.h"
#include "geotex/texture/base_shape.h"
#include "geotex/texture/measures.h"
#include "geotex/texture/synthesis.h"
#include "geotex/texture/texture.h"
#include "geotex/texture/transfer.h"
#include "geotex/toolkit/diffusion.h"
#include "geotex/toolkit/direction_field.h"
#include "geotex/toolkit/editing.h"
#include "geotex/toolkit/geodesic.h"
#include "geotex/toolkit/one_form.h"
#include "geotex/toolkit/parametrization.h"
#include "geotex/toolkit/phong_projection.h"
#include "geotex/toolkit/smoothing.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/render.h"
#include "geotex/tools/shapes.h"
#include "geotex/tools/viewer.h"

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

// Values of option \p info its table refuses: just outside each finite bound (numbers) and NaN (reals).
std::vector<OptionValue> refused_values(const OptionInfo& info) {
  std::vector<OptionValue> out;
  const Bounds& b = info.bounds;
  if (info.kind == OptionKind::Int) {
    // Bounds beyond an int are what the field can hold, not what the table declares: not reachable.
    constexpr double kIntMax = 2147483647.0;
    if (std::isfinite(b.lo) && b.lo > -kIntMax) out.push_back(static_cast<int64_t>(b.lo) - (b.lo_open ? 0 : 1));
    if (std::isfinite(b.hi) && b.hi < kIntMax) out.push_back(static_cast<int64_t>(b.hi) + (b.hi_open ? 0 : 1));
    return out;
  }
  if (info.kind != OptionKind::Real && info.kind != OptionKind::Vec3) return out;
  std::vector<double> bad = {std::nan("")};
  const auto step = [](double v) { return 1e-6 * std::max(1.0, std::abs(v)); };
  if (std::isfinite(b.lo)) bad.push_back(b.lo_open ? b.lo : b.lo - step(b.lo));
  if (std::isfinite(b.hi)) bad.push_back(b.hi_open ? b.hi : b.hi + step(b.hi));
  for (double v : bad) {
    if (info.kind == OptionKind::Real) out.push_back(v);
    else out.push_back(Vec3(Vec3::Constant(v)));
  }
  return out;
}

// Every entry point taking an O refuses, before any work, each value O's table refuses: InvalidInput
// naming the option. \p call runs the entry point with the options given.
template <class O, class Call>
void expect_entry_point_checks_its_table(const std::string& entry_point, Call call) {
  int tried = 0;
  for (const auto& f : O::table().fields()) {
    for (const OptionValue& v : refused_values(f.info)) {
      O o;
      f.assign(o, v);
      ++tried;
      const std::string what = entry_point + " with " + f.info.name + " = " + format_option_value(v);
      try {
        call(o);
        ADD_FAILURE() << what << ": accepted";
      } catch (const InvalidInput& e) {
        EXPECT_NE(std::string(e.what()).find(f.info.name), std::string::npos) << what << ": " << e.what();
      } catch (const std::exception& e) {
        ADD_FAILURE() << what << ": not InvalidInput: " << e.what();
      }
    }
  }
  EXPECT_GT(tried, 0) << entry_point << ": its table declares no range";
}

TEST(Options, EveryEntryPointRefusesWhatItsTableRefuses) {
  const Mesh disk = plane(6);
  const Mesh closed = icosphere(1);
  const MatrixX3d X = positions(disk);
  const Eigen::Index nE = disk.n_edges();
  const Texture texture = extract_texture(disk, X);
  const Eigen::VectorXd no_features = Eigen::VectorXd::Zero(X.rows());

  // toolkit
  expect_entry_point_checks_its_table<SmoothingOptions>("smooth", [&](const auto& o) { smooth(disk, o); });
  expect_entry_point_checks_its_table<EditOptions>("laplacian_edit",
                                                   [&](const auto& o) { laplacian_edit(disk, {0}, X.topRows(1), o); });
  expect_entry_point_checks_its_table<OneFormFitOptions>("fit_one_form",
                                                         [&](const auto& o) { fit_one_form(disk, X, o); });
  expect_entry_point_checks_its_table<ParametrizationOptions>("parametrize", [&](const auto& o) { parametrize(disk, o); });
  expect_entry_point_checks_its_table<PhongProjectionOptions>("PhongProjector",
                                                              [&](const auto& o) { (void)PhongProjector(disk, MatrixX3d(), o); });
  expect_entry_point_checks_its_table<DiffusionOptions>("auto_diffusion_function",
                                                        [&](const auto& o) { auto_diffusion_function(closed, o); });
  expect_entry_point_checks_its_table<DirectionFieldOptions>("direction_field",
                                                             [&](const auto& o) { direction_field(disk, X, o); });
  expect_entry_point_checks_its_table<HeatGeodesicOptions>("heat_geodesic_distance",
                                                           [&](const auto& o) { heat_geodesic_distance(disk, {0}, o); });
  // denoise
  expect_entry_point_checks_its_table<MrfOptions>("mrf_denoise", [&](const auto& o) { mrf_denoise(disk, o); });
  expect_entry_point_checks_its_table<MrfNormalOptions>("mrf_normal_denoise",
                                                        [&](const auto& o) { mrf_normal_denoise(disk, o); });
  expect_entry_point_checks_its_table<EdgeProcessOptions>("label_sharp_edges",
                                                          [&](const auto& o) { label_sharp_edges(disk, X, o); });
  expect_entry_point_checks_its_table<EdgeProcessOptions>("edge_energy", [&](const auto& o) {
    edge_energy(disk, X, Eigen::VectorXd::Zero(nE), o);
  });
  expect_entry_point_checks_its_table<EdgeProcessOptions>("edge_process_sweep", [&](const auto& o) {
    Eigen::VectorXd labels = Eigen::VectorXd::Zero(nE);
    edge_process_sweep(disk, X, labels, o, 0.1);
  });
  expect_entry_point_checks_its_table<AutoDenoiseOptions>("auto_denoise", [&](const auto& o) { auto_denoise(disk, o); });
  expect_entry_point_checks_its_table<AutoDenoiseOptions>("reading_samples",
                                                          [&](const auto& o) { reading_samples(disk, X, o); });
  expect_entry_point_checks_its_table<SurfelDenoiseOptions>("surfel_denoise",
                                                            [&](const auto& o) { surfel_denoise(disk, o); });
  expect_entry_point_checks_its_table<PointSurfelOptions>("point_surfels", [&](const auto& o) { point_surfels(X, o); });
  // resize
  expect_entry_point_checks_its_table<FeatureMapOptions>("feature_map", [&](const auto& o) { feature_map(disk, o); });
  expect_entry_point_checks_its_table<FeatureMapOptions>("importance_map", [&](const auto& o) { importance_map(disk, o); });
  expect_entry_point_checks_its_table<FeatureMapOptions>("adf_features", [&](const auto& o) { adf_features(disk, o); });
  expect_entry_point_checks_its_table<FeatureMapOptions>("features_from_height",
                                                         [&](const auto& o) { features_from_height(disk, o); });
  expect_entry_point_checks_its_table<FeatureFileOptions>("features_from_ply",
                                                          [&](const auto& o) { features_from_ply(PlyData{}, disk, o); });
  expect_entry_point_checks_its_table<FeatureFileOptions>("read_feature_file",
                                                          [&](const auto& o) { read_feature_file("none.ply", disk, o); });
  expect_entry_point_checks_its_table<SpaceMapOptions>("space_map",
                                                       [&](const auto& o) { space_map(o, bounding_box(disk)); });
  expect_entry_point_checks_its_table<ResizeOptions>("feature_aware_resize", [&](const auto& o) {
    feature_aware_resize(disk, X, no_features, o);
  });
  expect_entry_point_checks_its_table<ResizeRunOptions>("resize_mesh", [&](const auto& o) { resize_mesh(disk, o, &X); });
  // texture
  expect_entry_point_checks_its_table<TextureOptions>("extract_texture", [&](const auto& o) { extract_texture(disk, X, o); });
  expect_entry_point_checks_its_table<TextureOptions>("apply_texture", [&](const auto& o) { apply_texture(disk, texture, o); });
  expect_entry_point_checks_its_table<TextureOptions>("TextureSampler",
                                                      [&](const auto& o) { (void)TextureSampler(disk, texture, o); });
  expect_entry_point_checks_its_table<TextureApplyOptions>("apply_texture",
                                                           [&](const auto& o) { apply_texture(disk, texture, o); });
  expect_entry_point_checks_its_table<TextureExtractOptions>("texture_extraction",
                                                             [&](const auto& o) { texture_extraction(disk, &disk, o); });
  expect_entry_point_checks_its_table<TextureEditOptions>("edit_texture",
                                                          [&](const auto& o) { edit_texture(disk, texture, o); });
  expect_entry_point_checks_its_table<AnimationOptions>("TextureAnimator",
                                                        [&](const auto& o) { (void)TextureAnimator(disk, texture, o); });
  expect_entry_point_checks_its_table<BaseShapeOptions>("base_shape", [&](const auto& o) { base_shape(disk, o); });
  expect_entry_point_checks_its_table<TransferOptions>("transfer_texture", [&](const auto& o) {
    transfer_texture(disk, texture, disk, o);
  });
  expect_entry_point_checks_its_table<TransferOptions>("transfer_quality", [&](const auto& o) {
    transfer_quality(disk, texture, TransferResult{}, o);
  });
  expect_entry_point_checks_its_table<AtlasOptions>("cover_with_texture",
                                                    [&](const auto& o) { cover_with_texture(disk, texture, disk, o); });
  expect_entry_point_checks_its_table<SynthesisOptions>("synthesize_texture",
                                                        [&](const auto& o) { synthesize_texture(disk, texture, disk, o); });
  expect_entry_point_checks_its_table<SynthesisOptions>("estimate_synthesis",
                                                        [&](const auto& o) { estimate_synthesis(disk, texture, disk, o); });
  expect_entry_point_checks_its_table<SynthesisOptions>("synthesis_quality", [&](const auto& o) {
    synthesis_quality(disk, texture, SynthesisResult{}, o);
  });
  // tools
  expect_entry_point_checks_its_table<NoiseOptions>("add_noise", [&](const auto& o) { add_noise(disk, o); });
  expect_entry_point_checks_its_table<RenderOptions>("render_mesh", [&](const auto& o) { render_mesh(disk, o); });
  expect_entry_point_checks_its_table<RenderOptions>("fit_camera", [&](const auto& o) { fit_camera(X, o); });
  expect_entry_point_checks_its_table<ViewerOptions>("viewer_page", [&](const auto& o) {
    viewer_page({ViewerMesh{"disk", disk, {}}}, o, "script");
  });
}

}  // namespace
}  // namespace geotex
