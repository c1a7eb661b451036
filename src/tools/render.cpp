// Software rendering of meshes and PNG files (see render.h).

#include "geotex/tools/render.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <tuple>

#include <fmt/format.h>
#include <png.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/core/progress.h"
#include "geotex/core/spatial.h"

namespace geotex {
namespace {

// ------------------------------------------------------------------------------------------------
// Camera

void view_axes(ViewDirection view, const Vec3& model_up, Vec3& right, Vec3& up, Vec3& forward) {
  Vec3 world_up = Vec3::UnitZ();
  switch (view) {
    case ViewDirection::Iso: forward = -Vec3(1, -1, 1).normalized(); break;
    case ViewDirection::Front: forward = Vec3::UnitY(); break;
    case ViewDirection::Top:
      forward = -Vec3::UnitZ();
      world_up = Vec3::UnitY();
      break;
  }
  // Directions are defined for z-up models; rotate them onto the model's up axis.
  if (model_up.norm() < 1e-12) throw InvalidInput("the up axis must not be zero");
  const Eigen::Matrix3d R = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), model_up.normalized()).toRotationMatrix();
  forward = R * forward;
  world_up = R * world_up;
  right = forward.cross(world_up).normalized();
  up = right.cross(forward);
}

struct Projected {
  double x, y, depth;
};

Projected project(const Camera& c, const Vec3& p, double cx, double cy, double scale) {
  const Vec3 d = p - c.centre;
  return {cx + scale * d.dot(c.right), cy - scale * d.dot(c.up), d.dot(c.forward)};
}

// ------------------------------------------------------------------------------------------------
// A 5×7 bitmap font for the legend's numbers (each row: 5 bits, most significant = leftmost).

const std::array<uint8_t, 7>* glyph(char ch) {
  static const std::array<uint8_t, 7> digits[10] = {
      {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}, {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E},
      {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}, {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E},
      {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}, {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E},
      {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}, {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08},
      {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}, {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}};
  static const std::array<uint8_t, 7> dot{0, 0, 0, 0, 0, 0x0C, 0x0C}, minus{0, 0, 0, 0x1F, 0, 0, 0},
      plus{0, 0x04, 0x04, 0x1F, 0x04, 0x04, 0}, e{0, 0, 0x0E, 0x11, 0x1F, 0x10, 0x0E};
  if (ch >= '0' && ch <= '9') return &digits[ch - '0'];
  switch (ch) {
    case '.': return &dot;
    case '-': return &minus;
    case '+': return &plus;
    case 'e': return &e;
    default: return nullptr;
  }
}

void draw_text(Image& img, int x, int y, const std::string& s, int px, const Vec3& colour) {
  for (char ch : s) {
    if (const auto* g = glyph(ch))
      for (int r = 0; r < 7; ++r)
        for (int c = 0; c < 5; ++c)
          if ((*g)[r] & (0x10 >> c))
            for (int dy = 0; dy < px; ++dy)
              for (int dx = 0; dx < px; ++dx) {
                const int X = x + c * px + dx, Y = y + r * px + dy;
                if (X < 0 || Y < 0 || X >= img.width || Y >= img.height) continue;
                uint8_t* p = img.pixel(X, Y);
                for (int k = 0; k < 3; ++k) p[k] = static_cast<uint8_t>(std::lround(255 * colour[k]));
              }
    x += 6 * px;
  }
}

uint8_t to_byte(double v) { return static_cast<uint8_t>(std::lround(255.0 * std::clamp(v, 0.0, 1.0))); }

}  // namespace

// --------------------------------------------------------------------------------------------------

const EnumNames<ViewDirection>& view_direction_names() {
  static const EnumNames<ViewDirection> names{
      {"iso", ViewDirection::Iso}, {"front", ViewDirection::Front}, {"top", ViewDirection::Top}};
  return names;
}

ViewDirection view_direction_from_name(const std::string& name) {
  return parse_enum(view_direction_names(), name, "view");
}

const EnumNames<UpAxis>& up_axis_names() {
  static const EnumNames<UpAxis> names{{"auto", UpAxis::Auto}, {"x", UpAxis::X},     {"y", UpAxis::Y},
                                       {"z", UpAxis::Z},       {"-x", UpAxis::NegX}, {"-y", UpAxis::NegY},
                                       {"-z", UpAxis::NegZ}};
  return names;
}

const EnumNames<Framing>& framing_names() {
  static const EnumNames<Framing> names{{"tight", Framing::Tight}, {"sphere", Framing::Sphere}};
  return names;
}

const OptionTable<RenderOptions>& RenderOptions::table() {
  using O = RenderOptions;
  static const auto t = OptionTable<O>()
      .add("width", &O::width, "picture width in pixels", between(1, 16384))
      .add("height", &O::height, "picture height in pixels", between(1, 16384))
      .choice("view", &O::view, view_direction_names(), "camera direction: iso, front (from -y for up z) or top")
      .choice("up", &O::up, up_axis_names(),
              up_axis_help)
      .choice("frame", &O::frame, framing_names(),
              "tight: fit the mesh as seen; sphere: fit its bounding sphere (same scale from every direction)")
      .add("zoom", &O::zoom, "magnification of the fitted camera (2: twice as large)", positive())
      .add("centre", &O::centre, "point x,y,z at the picture's centre (auto: the centre of the framed mesh)")
      .alias("center")
      .add("margin", &O::margin, "free border at zoom 1, fraction of the smaller side", between(0, 0.45))
      .add("smooth", &O::smooth, "interpolate vertex normals (false: flat shading, one normal per face)")
      .alias("flat", "false")
      .add("supersampling", &O::supersampling, "anti-aliasing: k x k samples per pixel", between(1, 8))
      .add("background", &O::background, "background colour r,g,b in [0, 1]", unit_interval())
      .add("base_colour", &O::base_colour, "surface colour r,g,b in [0, 1] where no field is shown", unit_interval())
      .add("ambient", &O::ambient, "ambient light", unit_interval())
      .add("specular", &O::specular, "Blinn-Phong highlight strength (0: Lambert only)", non_negative())
      .add("shininess", &O::shininess, "Blinn-Phong exponent", positive())
      .add("line_width", &O::line_width, "edge-line width in pixels", positive())
      .add("legend", &O::legend, "draw a colour bar with the field's range when a field is shown");
  return t;
}

int legend_text_scale(int height) { return std::max(1, height / 200); }

int legend_width(int width, int height) {
  // 8 pixels of margin, the bar (8 font pixels wide), 4 pixels of gap, labels of up to 8 characters.
  const int px = legend_text_scale(height);
  return std::min(width / 4, std::max(110, 8 + 8 * px + 4 + 8 * 6 * px + 2));
}

MatrixX3d face_vertices(const Mesh& mesh) {
  std::vector<char> used(mesh.n_vertices(), 0);
  size_t n = 0;
  for (auto f : mesh.faces())
    for (auto v : mesh.fv_range(f))
      if (!used[v.idx()]) used[v.idx()] = 1, ++n;
  if (n == 0) return positions(mesh);
  MatrixX3d P(n, 3);
  Eigen::Index k = 0;
  for (auto v : mesh.vertices())
    if (used[v.idx()]) P.row(k++) = to_eigen(mesh.point(v)).transpose();
  return P;
}

Camera fit_camera(const MatrixX3d& V, const RenderOptions& o, int reserved_right) {
  check_options(o);
  if (V.rows() == 0) throw InvalidInput("fit_camera: no vertices");
  const int width = o.width - reserved_right, height = o.height;
  if (width <= 0) throw InvalidInput(fmt::format("no room for the picture: width {}, {} reserved", o.width, reserved_right));
  Camera c;
  const Vec3 lo = V.colwise().minCoeff().transpose(), hi = V.colwise().maxCoeff().transpose();
  view_axes(o.view, up_vector(o.up, V), c.right, c.up, c.forward);
  const Vec3 c0 = 0.5 * (lo + hi);
  double extent_r = 0, extent_u = 0;
  if (o.frame == Framing::Sphere) {
    const double radius = (V.rowwise() - c0.transpose()).rowwise().norm().maxCoeff();
    c.centre = c0;
    extent_r = extent_u = 2 * radius;
  } else {
    double r0 = std::numeric_limits<double>::max(), r1 = -r0, u0 = r0, u1 = -r0;
    for (Eigen::Index i = 0; i < V.rows(); ++i) {
      const Vec3 d = V.row(i).transpose() - c0;
      r0 = std::min(r0, d.dot(c.right));
      r1 = std::max(r1, d.dot(c.right));
      u0 = std::min(u0, d.dot(c.up));
      u1 = std::max(u1, d.dot(c.up));
    }
    // The projected extent's centre, not the box centre: from an oblique view they differ.
    c.centre = c0 + 0.5 * (r0 + r1) * c.right + 0.5 * (u0 + u1) * c.up;
    extent_r = r1 - r0;
    extent_u = u1 - u0;
  }
  if (o.centre) c.centre = *o.centre;
  const double free = 2.0 * o.margin * std::min(width, height);
  c.scale = o.zoom * std::max(1e-12, std::min((width - free) / std::max(extent_r, 1e-12),
                                              (height - free) / std::max(extent_u, 1e-12)));
  c.width = width;
  c.height = height;
  return c;
}

Camera fit_camera(const Mesh& mesh, const RenderOptions& options, int reserved_right) {
  return fit_camera(face_vertices(mesh), options, reserved_right);
}

Vec3 colour_map(double t) {
  // Viridis sampled at 9 stops, linearly interpolated.
  static const double stops[9][3] = {{0.267, 0.005, 0.329}, {0.283, 0.141, 0.458}, {0.254, 0.265, 0.530},
                                     {0.207, 0.372, 0.553}, {0.164, 0.471, 0.558}, {0.128, 0.567, 0.551},
                                     {0.135, 0.659, 0.518}, {0.478, 0.821, 0.318}, {0.993, 0.906, 0.144}};
  if (!std::isfinite(t)) t = 0;
  t = std::clamp(t, 0.0, 1.0) * 8.0;
  const int k = std::min(7, static_cast<int>(t));
  const double f = t - k;
  return {(1 - f) * stops[k][0] + f * stops[k + 1][0], (1 - f) * stops[k][1] + f * stops[k + 1][1],
          (1 - f) * stops[k][2] + f * stops[k + 1][2]};
}

Vec3 label_colour(int label) {
  static const Vec3 palette[] = {{0.86, 0.10, 0.12}, {0.12, 0.35, 0.85}, {0.10, 0.65, 0.20},
                                 {0.95, 0.55, 0.05}, {0.60, 0.20, 0.70}, {0.05, 0.70, 0.75}};
  const int n = static_cast<int>(std::size(palette));
  return palette[((std::max(label, 1) - 1) % n + n) % n];
}

namespace {
// \p n copies of \p v, written a slice at a time with a cancellation point between slices: first touching
// the pages of 4096² samples took seconds (of a Ctrl-C's wait) on a loaded machine.
template <class T>
std::vector<T> filled(size_t n, T v) {
  constexpr size_t kSlice = size_t(1) << 20;
  std::vector<T> out;
  out.reserve(n);
  for (size_t i = 0; i < n; i += kSlice) {
    check_interrupt();
    out.insert(out.end(), std::min(kSlice, n - i), v);
  }
  return out;
}

void check_layers(const RenderLayers& layers, Eigen::Index nv) {
  if (layers.field.size() > 0 && layers.field.size() != nv)
    throw InvalidInput(fmt::format("field has {} values for a mesh of {} vertices", layers.field.size(), nv));
  if (layers.segments.rows() > 0 && (layers.segments.minCoeff() < 0 || layers.segments.maxCoeff() >= nv))
    throw InvalidInput("edge segment refers to a vertex outside the mesh");
  if (layers.segment_labels.size() > 0 && layers.segment_labels.size() != layers.segments.rows())
    throw InvalidInput("segment labels and segments differ in number");
  const bool has_uv = layers.uv.rows() > 0;
  if (has_uv && layers.uv.rows() != nv)
    throw InvalidInput(fmt::format("uv has {} rows for a mesh of {} vertices", layers.uv.rows(), nv));
  if (has_uv && !(layers.checker_size > 0)) throw InvalidInput("checker size must be positive");
}

// The colour map's range: the layers' own, else the field's finite values (never empty).
std::pair<double, double> colour_range(const RenderLayers& layers) {
  double lo = layers.field_lo, hi = layers.field_hi;
  if (layers.field.size() > 0 && !(lo < hi)) {
    lo = std::numeric_limits<double>::max();
    hi = -lo;
    for (Eigen::Index i = 0; i < layers.field.size(); ++i)
      if (std::isfinite(layers.field[i])) lo = std::min(lo, layers.field[i]), hi = std::max(hi, layers.field[i]);
    if (!(lo <= hi)) lo = hi = 0;
    if (hi - lo < 1e-300) hi = lo + 1.0;
  }
  return {lo, hi};
}

// The picture at k× resolution: k×k samples per pixel, each with its depth, the face seen and its colour.
struct Samples {
  int k = 1, W = 0, H = 0;
  std::vector<Projected> P;   // the vertices on screen, in samples
  std::vector<float> depth;
  std::vector<int> face_at;   // -1: background
  std::vector<float> colour;  // RGB
};

// Rasterize the faces into the depth and face buffers (two-sided), in horizontal bands in parallel.
Samples rasterize(const MatrixX3d& V, const MatrixX3i& F, const Camera& cam, const RenderOptions& o) {
  Samples S;
  S.k = o.supersampling;
  S.W = o.width * S.k, S.H = o.height * S.k;
  const int k = S.k, W = S.W, H = S.H;
  const double scale = cam.scale * k;
  const double cx = 0.5 * cam.width * k, cy = 0.5 * cam.height * k;
  S.P.resize(V.rows());
  for (Eigen::Index i = 0; i < V.rows(); ++i) S.P[i] = project(cam, V.row(i).transpose(), cx, cy, scale);
  S.depth = filled(static_cast<size_t>(W) * H, std::numeric_limits<float>::infinity());
  S.face_at = filled(static_cast<size_t>(W) * H, -1);
  const std::vector<Projected>& P = S.P;
  std::vector<float>& depth = S.depth;
  std::vector<int>& face_at = S.face_at;
  const int bands = std::max(1, std::min(H, 64));
  // Ctrl-C (Python): the workers skip what is left once the caller's flag is set (progress.h).
  const std::atomic<bool>* stop = InterruptScope::current();
  check_interrupt();
#pragma omp parallel for schedule(dynamic)
  for (int b = 0; b < bands; ++b) {
    const int y_begin = static_cast<int>(static_cast<int64_t>(H) * b / bands);
    const int y_end = static_cast<int>(static_cast<int64_t>(H) * (b + 1) / bands);
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
      if (f % 4096 == 0 && interrupt_requested(stop)) break;
      const Projected &a = P[F(f, 0)], &bb = P[F(f, 1)], &c = P[F(f, 2)];
      const double ymin = std::min({a.y, bb.y, c.y}), ymax = std::max({a.y, bb.y, c.y});
      int y0 = std::max(y_begin, static_cast<int>(std::ceil(ymin - 0.5)));
      int y1 = std::min(y_end - 1, static_cast<int>(std::floor(ymax - 0.5)));
      if (y0 > y1) continue;
      const double xmin = std::min({a.x, bb.x, c.x}), xmax = std::max({a.x, bb.x, c.x});
      const int x0 = std::max(0, static_cast<int>(std::ceil(xmin - 0.5)));
      const int x1 = std::min(W - 1, static_cast<int>(std::floor(xmax - 0.5)));
      if (x0 > x1) continue;
      const double area = (bb.x - a.x) * (c.y - a.y) - (bb.y - a.y) * (c.x - a.x);
      if (std::abs(area) < 1e-18) continue;
      const double inv = 1.0 / area;
      for (int y = y0; y <= y1; ++y) {
        const double py = y + 0.5;
        // The row's span inside the triangle: each barycentric coordinate is linear in px, w = i + s px.
        // Scanning only the span (one pixel wider against rounding; the test below decides) keeps a
        // sliver's cost at its pixels, not its bounding box's (a 10^6 fan: 30 s before).
        double lo = x0, hi = x1 + 1.0;
        const double i0 = (bb.x * (c.y - py) - (bb.y - py) * c.x) * inv, s0 = (bb.y - c.y) * inv;
        const double i1 = (c.x * (a.y - py) - (c.y - py) * a.x) * inv, s1 = (c.y - a.y) * inv;
        const double is[3] = {i0, i1, 1.0 - i0 - i1}, ss[3] = {s0, s1, -s0 - s1};
        for (int m = 0; m < 3; ++m) {
          if (ss[m] > 0) lo = std::max(lo, -is[m] / ss[m]);
          else if (ss[m] < 0) hi = std::min(hi, -is[m] / ss[m]);
        }
        lo = std::min(lo, x1 + 1.0), hi = std::max(hi, double(x0));
        const int xa = std::max(x0, static_cast<int>(std::ceil(lo - 0.5)) - 1);
        const int xb = std::min(x1, static_cast<int>(std::floor(hi - 0.5)) + 1);
        for (int x = xa; x <= xb; ++x) {
          const double px = x + 0.5;
          // Barycentric coordinates from edge functions; both orientations are drawn (two-sided).
          const double w0 = ((bb.x - px) * (c.y - py) - (bb.y - py) * (c.x - px)) * inv;
          const double w1 = ((c.x - px) * (a.y - py) - (c.y - py) * (a.x - px)) * inv;
          const double w2 = 1.0 - w0 - w1;
          if (w0 < 0 || w1 < 0 || w2 < 0) continue;
          const float z = static_cast<float>(w0 * a.depth + w1 * bb.depth + w2 * c.depth);
          const size_t idx = static_cast<size_t>(y) * W + x;
          if (z < depth[idx]) {
            depth[idx] = z;
            face_at[idx] = static_cast<int>(f);
          }
        }
      }
    }
  }
  check_interrupt();
  return S;
}

// Shade every covered sample: Lambert + Blinn-Phong, one key light above-left of the camera; the
// surface coloured by the field (colour map over [lo, hi]), the UV checker or the base colour.
// \return the samples covered.
size_t shade(Samples& S, const Mesh& mesh, const MatrixX3i& F, const Camera& cam, const RenderOptions& o,
             const RenderLayers& layers, double lo, double hi) {
  const bool has_field = layers.field.size() > 0, has_uv = layers.uv.rows() > 0;
  const MatrixX3d N = o.smooth ? vertex_normals(mesh) : face_normals(mesh);
  const Vec3 view_dir = -cam.forward;
  const Vec3 light = (view_dir + 0.55 * cam.up - 0.35 * cam.right).normalized();
  const Vec3 half = (light + view_dir).normalized();
  const int W = S.W, H = S.H;
  const std::vector<Projected>& P = S.P;
  S.colour = filled(static_cast<size_t>(W) * H * 3, 0.0f);
  std::vector<float>& colour = S.colour;
  const std::atomic<bool>* stop = InterruptScope::current();
  size_t covered = 0;
#pragma omp parallel for reduction(+ : covered) schedule(static)
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W && !interrupt_requested(stop); ++x) {
      const size_t idx = static_cast<size_t>(y) * W + x;
      const int f = S.face_at[idx];
      Vec3 c = o.background;
      if (f >= 0) {
        ++covered;
        const Projected &a = P[F(f, 0)], &b = P[F(f, 1)], &cc = P[F(f, 2)];
        const double px = x + 0.5, py = y + 0.5;
        const double area = (b.x - a.x) * (cc.y - a.y) - (b.y - a.y) * (cc.x - a.x);
        double w0 = ((b.x - px) * (cc.y - py) - (b.y - py) * (cc.x - px)) / area;
        double w1 = ((cc.x - px) * (a.y - py) - (cc.y - py) * (a.x - px)) / area;
        double w2 = 1.0 - w0 - w1;
        Vec3 n = o.smooth ? Vec3(w0 * N.row(F(f, 0)) + w1 * N.row(F(f, 1)) + w2 * N.row(F(f, 2)))
                          : Vec3(N.row(f).transpose());
        if (n.norm() < 1e-12) n = view_dir;
        n.normalize();
        if (n.dot(view_dir) < 0) n = -n;  // back faces of open surfaces are lit like front faces
        Vec3 base = o.base_colour;
        if (has_field) {
          const double v = w0 * layers.field[F(f, 0)] + w1 * layers.field[F(f, 1)] + w2 * layers.field[F(f, 2)];
          base = colour_map((v - lo) / (hi - lo));
        }
        if (has_uv) {
          const Eigen::Vector2d t = w0 * layers.uv.row(F(f, 0)) + w1 * layers.uv.row(F(f, 1)) + w2 * layers.uv.row(F(f, 2));
          const auto cell = [&](double c) { return static_cast<int64_t>(std::floor(c / layers.checker_size)); };
          base = ((cell(t[0]) + cell(t[1])) & 1) ? Vec3(0.95, 0.95, 0.95) : Vec3(0.20, 0.38, 0.70);
        }
        const double diffuse = std::max(0.0, n.dot(light));
        const double spec = o.specular * std::pow(std::max(0.0, n.dot(half)), o.shininess);
        c = base * (o.ambient + (1.0 - o.ambient) * diffuse) + Vec3::Constant(spec);
      }
      for (int j = 0; j < 3; ++j) colour[3 * idx + j] = static_cast<float>(c[j]);
    }
  check_interrupt();
  return covered;
}

// Edge lines: disks stamped along each segment, hidden where the surface lies in front.
void draw_segments(Samples& S, const MatrixX3d& V, const RenderOptions& o, const RenderLayers& layers) {
  const double extent = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  const double bias = 0.01 * extent;
  const double radius = 0.5 * o.line_width * S.k;
  const int r = static_cast<int>(std::ceil(radius));
  for (Eigen::Index s = 0; s < layers.segments.rows(); ++s) {
    if (s % 1024 == 0) check_interrupt();
    const Projected &a = S.P[layers.segments(s, 0)], &b = S.P[layers.segments(s, 1)];
    const Vec3 lc = label_colour(layers.segment_labels.size() ? layers.segment_labels[s] : 1);
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    const int steps = std::max(1, static_cast<int>(std::ceil(len / 0.5)));
    for (int t = 0; t <= steps; ++t) {
      const double u = static_cast<double>(t) / steps;
      const double px = a.x + u * (b.x - a.x), py = a.y + u * (b.y - a.y);
      const double pz = a.depth + u * (b.depth - a.depth);
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          const int X = static_cast<int>(std::floor(px)) + dx, Y = static_cast<int>(std::floor(py)) + dy;
          if (X < 0 || Y < 0 || X >= S.W || Y >= S.H) continue;
          if (std::hypot(X + 0.5 - px, Y + 0.5 - py) > radius) continue;
          const size_t idx = static_cast<size_t>(Y) * S.W + X;
          if (pz > S.depth[idx] + bias) continue;
          for (int j = 0; j < 3; ++j) S.colour[3 * idx + j] = static_cast<float>(lc[j]);
        }
    }
  }
}

// Box-filter the samples down to the picture.
Image downsample(const Samples& S, int width, int height) {
  const int k = S.k;
  Image img;
  img.width = width;
  img.height = height;
  img.rgb.assign(static_cast<size_t>(width) * height * 3, 0);
#pragma omp parallel for schedule(static)
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int j = 0; j < 3; ++j) {
        double sum = 0;
        for (int sy = 0; sy < k; ++sy)
          for (int sx = 0; sx < k; ++sx) sum += S.colour[3 * ((static_cast<size_t>(y) * k + sy) * S.W + x * k + sx) + j];
        img.pixel(x, y)[j] = to_byte(sum / (k * k));
      }
  return img;
}

// "1.37e-06" → "1.37e-6": short labels fit beside the bar.
std::string legend_label(double v) {
  std::string s = fmt::format("{:.3g}", v);
  const size_t e = s.find('e');
  if (e != std::string::npos) {
    size_t d = e + 2;
    while (d + 1 < s.size() && s[d] == '0') s.erase(d, 1);
    if (s[e + 1] == '+') s.erase(e + 1, 1);
  }
  return s;
}

// Legend: a vertical colour bar at the right with the range's ends.
void draw_legend(Image& img, double lo, double hi) {
  const int legend_w = legend_width(img.width, img.height), text_px = legend_text_scale(img.height);
  const int bar_w = std::max(8, 8 * text_px);
  const int bx = img.width - legend_w + 8, by0 = img.height / 8, by1 = img.height - img.height / 8;
  for (int y = by0; y <= by1; ++y) {
    const Vec3 c = colour_map(1.0 - static_cast<double>(y - by0) / std::max(1, by1 - by0));
    for (int x = bx; x < bx + bar_w && x < img.width; ++x)
      for (int j = 0; j < 3; ++j) img.pixel(x, y)[j] = to_byte(c[j]);
  }
  const Vec3 ink(0.1, 0.1, 0.1);
  const int room = img.width - (bx + bar_w + 4) - 2;
  for (const auto& [value, y] : {std::pair{hi, by0}, std::pair{lo, by1}}) {
    const std::string s = legend_label(value);
    // The font's pixels scale with the picture (7 rows of text_px pixels), narrower when the label
    // would not fit beside the bar.
    int px = text_px;
    while (px > 1 && 6 * px * static_cast<int>(s.size()) > room) --px;
    draw_text(img, bx + bar_w + 4, y - (y == by1 ? 7 * px : 0), s, px, ink);
  }
}

}  // namespace

Rendering render_mesh(const Mesh& mesh, const RenderOptions& o, const RenderLayers& layers) {
  check_options(o);
  require_valid(mesh, "mesh to render");
  const MatrixX3d V = positions(mesh);
  const MatrixX3i F = faces(mesh);
  check_layers(layers, V.rows());
  const bool has_field = layers.field.size() > 0, has_uv = layers.uv.rows() > 0;

  Rendering out;
  const bool show_legend = has_field && !has_uv && o.legend;
  out.camera = o.camera ? *o.camera : fit_camera(mesh, o, show_legend ? legend_width(o.width, o.height) : 0);
  std::tie(out.field_lo, out.field_hi) = colour_range(layers);
  Samples S = rasterize(V, F, out.camera, o);
  const size_t covered = shade(S, mesh, F, out.camera, o, layers, out.field_lo, out.field_hi);
  out.covered_pixels = static_cast<size_t>(std::llround(static_cast<double>(covered) / (S.k * S.k)));
  if (layers.segments.rows() > 0) draw_segments(S, V, o, layers);
  out.image = downsample(S, o.width, o.height);
  if (show_legend) draw_legend(out.image, out.field_lo, out.field_hi);
  return out;
}

std::string encode_png(const Image& img) {
  if (img.width <= 0 || img.height <= 0 || img.rgb.size() != static_cast<size_t>(img.width) * img.height * 3)
    throw InvalidInput("encode_png: image size and pixel data disagree");
  // libpng's simplified API: no setjmp here; libpng picks the row filters adaptively (PNG spec 12.8).
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(img.width);
  image.height = static_cast<png_uint_32>(img.height);
  image.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  const auto* pixels = img.rgb.data();
  if (!png_image_write_to_memory(&image, nullptr, &size, 0, pixels, 0, nullptr))
    throw IoError(fmt::format("libpng: {}", image.message));
  std::string png(size, '\0');
  if (!png_image_write_to_memory(&image, png.data(), &size, 0, pixels, 0, nullptr))
    throw IoError(fmt::format("libpng: {}", image.message));
  png.resize(size);
  return png;
}

void write_png(const Image& image, const std::filesystem::path& path) {
  if (path.extension() != ".png" && path.extension() != ".PNG")
    throw IoError(fmt::format("{}: a picture's name must end in .png", path.string()));
  write_text_atomic(path, encode_png(image));
}

Eigen::VectorXd distance_to_surface(const Mesh& mesh, const Mesh& reference) {
  require_valid(reference, "reference mesh");
  const TriangleTree tree(reference);
  const MatrixX3d V = positions(mesh);
  Eigen::VectorXd d(V.rows());
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < V.rows(); ++i) d[i] = std::sqrt(tree.closest(V.row(i).transpose()).sq_distance);
  return d;
}

}  // namespace geotex
