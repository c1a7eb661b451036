// The texture module's option tables and the animation (texture.h, base_shape.h, transfer.h, geodesic.h).

#include <set>

#include <gtest/gtest.h>

#include "geotex/core/geometry.h"
#include "geotex/texture/texture.h"
#include "geotex/texture/transfer.h"
#include "geotex/toolkit/geodesic.h"
#include "geotex/tools/shapes.h"

using namespace geotex;

namespace {

template <class O>
void expect_table_is_consistent(const char* what) {
  const auto& t = O::table();
  std::set<std::string> names;
  const O defaults{};
  for (const auto& f : t.fields()) {
    EXPECT_TRUE(names.insert(f.info.name).second) << what << ": option " << f.info.name << " declared twice";
    EXPECT_FALSE(f.info.help.empty()) << what << ": " << f.info.name << " has no help";
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

}  // namespace

TEST(TextureOptions, TablesAreConsistentAndThePresetsAreTheThesis) {
  expect_table_is_consistent<TextureOptions>("TextureOptions");
  expect_table_is_consistent<BaseShapeOptions>("BaseShapeOptions");
  expect_table_is_consistent<TransferOptions>("TransferOptions");
  expect_table_is_consistent<AtlasOptions>("AtlasOptions");
  expect_table_is_consistent<AnimationOptions>("AnimationOptions");
  expect_table_is_consistent<HeatGeodesicOptions>("HeatGeodesicOptions");
  expect_table_is_consistent<TextureExtractOptions>("TextureExtractOptions");
  expect_table_is_consistent<TextureApplyOptions>("TextureApplyOptions");
  expect_table_is_consistent<TextureEditOptions>("TextureEditOptions");
  // The commands' thesis presets are their parts' thesis presets.
  TextureExtractOptions e;
  TextureExtractOptions::table().apply_preset(e, "thesis");
  EXPECT_EQ(e.base.method, BaseMethod::Smoothing);
  EXPECT_FALSE(e.base.project);
  EXPECT_EQ(e.texture.encoding, TiltEncoding::OneForm);
  TextureEditOptions d;
  TextureEditOptions::table().apply_preset(d, "thesis");
  EXPECT_EQ(d.texture.solver, TiltSolver::Direct);
  AnimationOptions a;
  AnimationOptions::table().apply_preset(a, "thesis");
  EXPECT_TRUE(a.texture.bound_tilt);
  TextureOptions t;
  TextureOptions::table().apply_preset(t, "thesis");
  EXPECT_EQ(t.encoding, TiltEncoding::OneForm);
  EXPECT_FALSE(t.tangential_fit);
  EXPECT_TRUE(t.bound_tilt);
  BaseShapeOptions b;
  BaseShapeOptions::table().apply_preset(b, "thesis");
  EXPECT_EQ(b.method, BaseMethod::Smoothing);
  TransferOptions x;
  TransferOptions::table().apply_preset(x, "thesis");
  EXPECT_EQ(x.height_rule, HeightRule::Absolute);
  EXPECT_EQ(x.falloff, 0.0);
  EXPECT_EQ(x.texture.encoding, TiltEncoding::OneForm);
  // Nested tables reach their fields by name; bad values are refused by name.
  TransferOptions::table().set(x, "tilt_encoding", std::string("lean"));
  EXPECT_EQ(x.texture.encoding, TiltEncoding::Lean);
  EXPECT_THROW(TransferOptions::table().set(x, "falloff", 2.0), InvalidOption);
  EXPECT_EQ(parse_enum(tilt_encoding_names(), "thesis", "encoding"), TiltEncoding::OneForm);
}

TEST(TextureAnimation, FramesAreTheEditsAndNeedNoRefitToMatch) {
  const TexturedShape s = make_shape("spiky-sphere", 1);
  TextureCodec codec(s.base);
  const Texture tex = codec.extract(positions(s.textured));
  const double h = mean_edge_length(s.base);
  AnimationOptions o;
  o.frames = 8;
  o.direction = Vec3(0, 0, 1);
  o.angle_deg = 40;
  o.wavelength = 0.7;
  TextureAnimator animator(s.base, tex, o);
  EXPECT_EQ(animator.frames(), 8);
  AnimationOptions direct = o;
  direct.refit = false;
  TextureAnimator fast(s.base, tex, direct);
  for (int k : {0, 3, 5}) {
    // The frame is the wiggle edit at phase k / frames (Sec. 8.4.1) ...
    const MatrixX3d edit = codec.apply(wiggle(codec, tex, o.direction, o.angle_deg, o.wavelength, double(k) / o.frames));
    const MatrixX3d frame = animator.positions(k);
    EXPECT_LT((frame - edit).rowwise().norm().maxCoeff() / h, 2e-3) << "frame " << k;
    // ... and displacing along the edited directions directly gives the same surface.
    EXPECT_LT((fast.positions(k) - frame).rowwise().norm().maxCoeff() / h, 2e-3) << "frame " << k;
  }
  // Frames move: the wave travels.
  EXPECT_GT((animator.positions(0) - animator.positions(2)).rowwise().norm().maxCoeff() / h, 0.5);
  o.kind = AnimationKind::Grow;
  TextureAnimator grow(s.base, tex, o);
  EXPECT_LT((grow.positions(0) - positions(s.base)).norm(), 1e-12);  // heights × 0 at the start
  EXPECT_LT((grow.positions(4) - codec.apply(tex)).rowwise().norm().maxCoeff() / h, 1e-9);  // full at half period
  o.frames = 0;
  EXPECT_THROW(TextureAnimator(s.base, tex, o), InvalidInput);
}
