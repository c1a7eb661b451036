// Demo steps for the differential-geometry toolkit: Laplacian editing (Sec. 5.1.4), parametrization
// (Sec. 5.4) and the auto diffusion function (Gębal et al. 2009).

#include <map>

#include <fmt/format.h>

#include "cli.h"
#include "geotex/toolkit/diffusion.h"
#include "geotex/toolkit/editing.h"
#include "geotex/core/geometry.h"
#include "geotex/toolkit/parametrization.h"
#include "geotex/toolkit/results.h"
#include "geotex/tools/shapes.h"

namespace geotex::cli {
namespace demo_edit {  // named, not anonymous: a unity build compiles several commands in one unit

DemoRegistrar edit{21, "laplacian editing", [](const DemoContext& ctx) {
  nlohmann::json& r = *ctx.report;
  // A spiky plate: the left end held, the right end turned by 90 degrees about y (a bend).
  const TexturedShape sh = make_shape("spiky-plane", 1);
  const Mesh& m = sh.textured;
  const MatrixX3d X = positions(m);
  std::vector<int> h;
  std::vector<char> moved(X.rows(), 0);
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    if (X(i, 0) < -0.4 || X(i, 0) > 0.4) {
      h.push_back(static_cast<int>(i));
      moved[i] = X(i, 0) > 0.4;
    }
  const Eigen::Matrix3d R = Eigen::AngleAxisd(-M_PI / 2, Vec3::UnitY()).toRotationMatrix();
  MatrixX3d C(h.size(), 3);
  for (size_t k = 0; k < h.size(); ++k) {
    const Vec3 x = X.row(h[k]).transpose();
    C.row(k) = (moved[h[k]] ? Vec3(R * (x - Vec3(0.4, 0, 0)) + Vec3(0.4, 0, 0.1)) : x).transpose();
  }
  save_mesh(m, (ctx.dir / "edit-input.ply").string());
  add_figure(ctx, {.mesh = "edit-input.ply",
                   .caption = fmt::format("Laplacian editing (Sec. 5.1.4): the spiky plate; {} vertices at the ends are "
                                          "handles, the right end is turned by 90&deg; about y.", h.size()),
                   .compare = "edit"});
  for (auto [method, name] : {std::pair{EditMethod::Plain, "plain"}, std::pair{EditMethod::MembraneFit, "membrane-fit"},
                              std::pair{EditMethod::Linear, "linear"}}) {
    EditOptions o;
    o.method = method;
    const MatrixX3d Y = LaplacianEditor(m, h, {}, o).solve(C);
    Mesh out = m;
    set_positions(out, Y);
    const Eigen::VectorXd d = detail_error(m, X, Y);
    PlyExtras x;
    x.vertex_scalars["detail"] = std::vector<double>(d.data(), d.data() + d.size());
    write_ply(out, ctx.dir / fmt::format("edit-{}.ply", name), x);
    const double e = d.mean();
    r["detail_error"][name] = e;
    add_figure(ctx, {.mesh = fmt::format("edit-{}.ply", name),
                     .caption = fmt::format("{} editing: mean detail error {:.3f} (|&delta;' &minus; sR&delta;| / mean "
                                            "|&delta;|; colour, shared by the row): the spikes should turn with the plate.",
                                            name, e),
                     .compare = "edit", .field = "detail"});
    r["summary"].push_back(fmt::format("spiky plate, right end turned 90 deg, {}: mean detail error {:.3f} "
                                       "(|delta' - s R delta| / mean |delta|)", name, e));
  }
}};

DemoRegistrar param{22, "parametrization", [](const DemoContext& ctx) {
  nlohmann::json& r = *ctx.report;
  // A spherical cap (the icosphere above z = -0.5: large enough for the maps to differ), mapped to the unit disk.
  const Mesh s = icosphere(4);
  const MatrixX3d V = positions(s);
  const MatrixX3i F = faces(s);
  std::vector<int> keep_f;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    if ((V(F(f, 0), 2) + V(F(f, 1), 2) + V(F(f, 2), 2)) / 3 > -0.5) keep_f.push_back(static_cast<int>(f));
  std::vector<int> id(V.rows(), -1);
  int nv = 0;
  MatrixX3i Fc(keep_f.size(), 3);
  for (size_t k = 0; k < keep_f.size(); ++k)
    for (int c = 0; c < 3; ++c) {
      int& v = id[F(keep_f[k], c)];
      if (v < 0) v = nv++;
      Fc(k, c) = v;
    }
  MatrixX3d Vc(nv, 3);
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (id[i] >= 0) Vc.row(id[i]) = V.row(i);
  const Mesh cap = make_mesh(Vc, Fc);
  for (auto [method, name] : {std::pair{ParamMethod::Conformal, "conformal"}, std::pair{ParamMethod::Authalic, "authalic"},
                              std::pair{ParamMethod::Combined, "combined"}, std::pair{ParamMethod::NaturalConformal, "natural"}}) {
    const MatrixX2d uv = parametrize(cap, {method});
    write_obj_with_uv(cap, uv, ctx.dir / fmt::format("cap-uv-{}.obj", name));
    PlyExtras x;  // the same UVs as vertex properties, for the report's checkerboard
    for (int c : {0, 1}) x.vertex_scalars[c ? "param_v" : "param_u"] = std::vector<double>(uv.col(c).data(), uv.col(c).data() + uv.rows());
    write_ply(cap, ctx.dir / fmt::format("cap-uv-{}.ply", name), x);
    const ParamQuality q = parametrization_quality(cap, uv);
    // The figures as `geotex param --json` and Python name them (results.h: figures()).
    const std::string figures =
        param_quality_results().figures(q, {"mean_angle_error_deg", "mean_log_area_ratio", "flipped"});
    r["summary"].push_back(fmt::format("spherical cap ({} faces), {}: {}", cap.n_faces(), name, figures));
    static const std::map<std::string, std::string> what = {
        {"conformal", "aims to keep angles (squares stay square)"},
        {"authalic", "aims to keep areas (squares keep their size)"},
        {"combined", "a mix of the two"},
        {"natural", "conformal with a free boundary (the rim is not forced onto a circle)"}};
    add_figure(ctx, {.mesh = fmt::format("cap-uv-{}.ply", name),
                     .caption = fmt::format("Parametrization (Sec. 5.4), {}: a UV checkerboard on the spherical cap; "
                                            "{}. {}.", name, what.at(name), figures),
                     .compare = "param", .checker = true});
  }
}};

DemoRegistrar adf{23, "auto diffusion function", [](const DemoContext& ctx) {
  nlohmann::json& r = *ctx.report;
  const TexturedShape sh = make_shape("spiky-sphere", 0);
  const LaplaceSpectrum sp = laplace_spectrum(sh.textured, 100);
  for (double t : {0.05, 0.5}) {
    const Eigen::VectorXd a = auto_diffusion_function(sp, t);
    PlyExtras x;
    x.vertex_scalars["adf"] = std::vector<double>(a.data(), a.data() + a.size());
    write_ply(sh.textured, ctx.dir / fmt::format("spiky-sphere-adf-t{}.ply", t), x);
    double tips = 0;
    for (int v : sh.spike_centres) tips += a[v];
    r["summary"].push_back(fmt::format("spiky sphere, ADF t = {} over 100 eigenpairs: mean at the {} spike tips {:.3g}, "
                                       "mean overall {:.3g}", t, sh.spike_centres.size(), tips / sh.spike_centres.size(),
                                       a.mean()));
    add_figure(ctx, {.mesh = fmt::format("spiky-sphere-adf-t{}.ply", t),
                     .caption = fmt::format("Auto diffusion function, t = {} (100 eigenpairs): {:.3g} on average at the "
                                            "{} spike tips, {:.3g} overall; {}.",
                                            t, tips / sh.spike_centres.size(), sh.spike_centres.size(), a.mean(),
                                            t < 0.1 ? "small t picks out the tips" : "large t shows the coarse shape"),
                     .field = "adf"});
  }
}};

}  // namespace demo_edit
}  // namespace geotex::cli
