// Demo step "report": index.html, the pictures the other steps asked for (add_figure() in cli.h) in the
// pipeline's order (input, toolkit, denoising, texture, resizing), each with its caption, and 3D viewer
// pages. Figures of one comparison share their camera and their colour range. Runs last (order 900);
// mesh files no figure shows are listed at the end.

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <optional>
#include <set>

#include <fmt/format.h>

#include "cli.h"
#include "geotex/core/geometry.h"
#include "geotex/tools/render.h"
#include "geotex/tools/viewer.h"

namespace geotex::cli {
namespace demo_report {  // named, not anonymous: a unity build compiles several commands in one unit

namespace fs = std::filesystem;

constexpr size_t kMaxFaces = 300000;  // larger meshes are listed but neither drawn nor put in a page
// Pictures are drawn full size (what "click to enlarge" opens: legible colour bars) and shown at half
// of it in the grid (sharp on high-density screens; the browser's downscaling is the anti-aliasing,
// so one sample per pixel: the cost of the former 400x300 pictures with 2x2 samples).
constexpr int kWidth = 800, kHeight = 600, kShrink = 2, kSamples = 1;

std::string html_escape(const std::string& s) {
  std::string out;
  for (char c : s) out += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : c == '"' ? "&quot;" : std::string(1, c);
  return out;
}

std::string id_of(const std::string& s) {
  std::string out;
  for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) ? static_cast<char>(std::tolower(c)) : '-';
  return out;
}

struct Loaded {
  Mesh mesh;
  MeshLayers layers;
};

struct Figure {
  std::string section, step;
  nlohmann::json spec;  // as add_figure() wrote it
  const Loaded* data = nullptr;
  Eigen::VectorXd field;  // the colours' values (empty: none)
  MeshLayers layers;      // what the 3D page shows (with the error field and the edges)
  std::string picture, page, problem;
};

//! The up axis a figure asked for (generated shapes: z; real models: read from the model).
UpAxis figure_up(const Figure& f) { return parse_enum(up_axis_names(), f.spec.value("up", std::string("z")), "up"); }

using Steps = std::vector<std::pair<std::string, std::string>>;  // (section, step) in order
using Notes = std::map<std::string, std::vector<std::string>>;     // step → notes

// The figures the steps asked for, in the steps' order; the steps with figures or notes, and the notes.
std::vector<Figure> collect_figures(const DemoContext& ctx, Steps& steps, Notes& notes) {
  std::vector<Figure> figures;
  if (!ctx.steps) return figures;
  for (const auto& s : *ctx.steps) {
    const std::string section = s.value("section", std::string("Other")), name = s.value("name", std::string());
    if (s.contains("notes"))
      for (const auto& n : s["notes"]) notes[name].push_back(n.get<std::string>());
    if (!s.contains("figures") && !notes.count(name)) continue;
    steps.emplace_back(section, name);
    if (s.contains("figures"))
      for (const auto& f : s["figures"]) figures.push_back({section, name, f});
  }
  return figures;
}

// Each figure's mesh (read once each into \p meshes), field and edges; what cannot be drawn is the
// figure's problem.
void load_figures(const DemoContext& ctx, std::vector<Figure>& figures, std::map<std::string, Loaded>& meshes) {
  auto load = [&](const std::string& file) -> const Loaded* {
    if (auto it = meshes.find(file); it != meshes.end()) return &it->second;
    Loaded l;
    l.mesh = read_mesh(ctx.dir / file);
    l.layers = read_mesh_layers(ctx.dir / file, l.mesh.n_vertices());
    return &meshes.emplace(file, std::move(l)).first->second;
  };
  for (auto& f : figures) {
    const nlohmann::json& sp = f.spec;
    try {
      f.data = load(sp["mesh"].get<std::string>());
      if (f.data->mesh.n_faces() > kMaxFaces) {
        f.problem = "too large to draw here";
        continue;
      }
      f.layers = f.data->layers;
      const std::string field = sp.value("field", std::string());
      if (field == "error") {
        f.field = distance_to_surface(f.data->mesh, load(sp["truth"].get<std::string>())->mesh);
        f.layers.fields["error"] = f.field;
      } else if (!field.empty()) {
        if (!f.layers.fields.count(field)) throw InvalidInput("no vertex property '" + field + "'");
        f.field = f.layers.fields.at(field);
      }
      if (sp.contains("edges")) read_edge_labels(ctx.dir / sp["edges"].get<std::string>(), f.data->mesh.n_vertices(), f.layers);
    } catch (const Error& e) {
      f.problem = e.what();
    }
  }
}

// A comparison: its figures share one camera and one colour range.
struct Shared {
  std::vector<Figure*> members;
  double lo = 0, hi = 0;
  std::optional<Camera> camera;
};

RenderOptions picture_options() {
  RenderOptions base;
  base.width = kWidth;
  base.height = kHeight;
  base.supersampling = kSamples;
  return base;
}

// The comparisons by key, each with the camera that fits all its meshes and the range of its fields.
std::map<std::string, Shared> comparisons(std::vector<Figure>& figures) {
  std::map<std::string, Shared> shared;
  for (auto& f : figures)
    if (f.spec.contains("compare") && f.problem.empty()) shared[f.spec["compare"].get<std::string>()].members.push_back(&f);
  for (auto& [key, g] : shared) {
    bool error = false, any_field = false;
    Eigen::Index rows = 0;
    std::vector<double> values;  // of the members that set the range
    for (Figure* f : g.members) {
      rows += face_vertices(f->data->mesh).rows();
      if (f->field.size() == 0) continue;
      any_field = true;
      const std::string field = f->spec.value("field", std::string());
      error = error || field == "error" || field == "detail";  // errors: ≥ 0, a few large ones
      if (f->spec.value("sets_range", true)) values.insert(values.end(), f->field.data(), f->field.data() + f->field.size());
    }
    if (!values.empty()) {
      // Error maps: from 0 to the 98th percentile of all the row's errors (a few large errors of one
      // result must not leave the others in one dark colour); other fields: their whole range.
      std::sort(values.begin(), values.end());
      g.lo = error ? 0.0 : values.front();
      g.hi = error ? values[static_cast<size_t>(0.98 * (values.size() - 1))] : values.back();
      if (!(g.hi > g.lo)) g.hi = g.lo + 1;
    }
    MatrixX3d all(rows, 3);
    Eigen::Index at = 0;
    for (Figure* f : g.members) {
      const MatrixX3d P = face_vertices(f->data->mesh);
      all.middleRows(at, P.rows()) = P;
      at += P.rows();
    }
    RenderOptions o = picture_options();
    o.view = view_direction_from_name(g.members.front()->spec.value("view", std::string("iso")));
    o.up = figure_up(*g.members.front());
    g.camera = fit_camera(all, o, any_field ? legend_width(o.width, o.height) : 0);
  }
  return shared;
}

// Draw every figure that can be drawn into pictures/. \return the pictures drawn; \p shown gets the
// mesh files the figures show.
size_t draw_pictures(const DemoContext& ctx, std::vector<Figure>& figures, const std::map<std::string, Shared>& shared,
                     std::set<std::string>& shown) {
  size_t drawn = 0;
  for (auto& f : figures) {
    if (f.data) shown.insert(f.spec["mesh"].get<std::string>());
    if (!f.problem.empty()) continue;
    RenderOptions o = picture_options();
    o.view = view_direction_from_name(f.spec.value("view", std::string("iso")));
    o.up = figure_up(f);
    RenderLayers rl;
    rl.field = f.field;
    rl.segments = f.layers.segments;
    rl.segment_labels = f.layers.labels;
    if (f.spec.value("checker", false)) {
      const auto& u = f.layers.fields;
      if (!u.count("param_u") || !u.count("param_v")) {
        f.problem = "no param_u, param_v vertex properties for the checkerboard";
        continue;
      }
      rl.uv.resize(f.data->mesh.n_vertices(), 2);
      rl.uv.col(0) = u.at("param_u");
      rl.uv.col(1) = u.at("param_v");
      rl.checker_size = 0.125;
      rl.field.resize(0);
    }
    if (f.spec.contains("compare")) {
      const Shared& g = shared.at(f.spec["compare"].get<std::string>());
      o.camera = g.camera;
      rl.field_lo = g.lo;
      rl.field_hi = g.hi;
    }
    const std::string stem = fs::path(f.spec["mesh"].get<std::string>()).stem().string();
    f.picture = "pictures/" + stem + ".png";
    write_png(render_mesh(f.data->mesh, o, rl).image, ctx.dir / f.picture);
    ++drawn;
  }
  return drawn;
}

// 3D pages in views/: one per comparison (up to six meshes, linked cameras), one per figure outside any.
// \return the pages written (none, with a line in the summary, when the viewer's script is missing).
size_t write_pages(const DemoContext& ctx, std::vector<Figure>& figures, std::map<std::string, Shared>& shared) {
  std::string script;
  try {
    script = viewer_script();
    write_text_atomic(ctx.dir / "views" / "geotex-viewer.js", script);
  } catch (const IoError& err) {
    (*ctx.report)["summary"].push_back(std::string("3D pages skipped: ") + err.what());
    return 0;
  }
  size_t pages = 0;
  auto page = [&](const std::vector<Figure*>& fs_, const std::string& name, const std::string& title) {
    std::vector<ViewerMesh> ms;
    std::string field;
    for (Figure* f : fs_) {
      if (ms.size() == 6) break;
      ms.push_back({f->spec["mesh"].get<std::string>(), f->data->mesh, f->layers});
      if (field.empty()) field = f->spec.value("field", std::string());
    }
    ViewerOptions v;
    v.up = figure_up(*fs_.front());
    v.title = title;
    v.initial_field = field;
    v.script_src = "geotex-viewer.js";
    const std::string path = "views/" + name + ".html";
    write_text_atomic(ctx.dir / path, viewer_page(ms, v, script));
    ++pages;
    for (Figure* f : fs_) f->page = path;
  };
  for (auto& [key, g] : shared) page(g.members, "compare-" + id_of(key), "geotex demo: " + key);
  for (auto& f : figures)
    if (f.problem.empty() && !f.spec.contains("compare"))
      page({&f}, fs::path(f.spec["mesh"].get<std::string>()).stem().string(), f.spec["mesh"].get<std::string>());
  return pages;
}

// One figure: its picture (a link to the full size), its caption, file, faces, 3D page and problem.
std::string figure_html(const Figure& f) {
  const std::string file = f.spec["mesh"].get<std::string>();
  std::string out = "<figure>";
  if (!f.picture.empty())
    out += fmt::format("<a href=\"{0}\"><img src=\"{0}\" alt=\"{1}\" width=\"{2}\" height=\"{3}\" loading=\"lazy\"></a>",
                       f.picture, html_escape(file), kWidth / kShrink, kHeight / kShrink);
  // Captions are written by the steps as HTML (entities, <b>, <sub>).
  out += "<figcaption>" + f.spec.value("caption", std::string());
  out += fmt::format(" <span class=\"files\"><a href=\"{0}\">{0}</a>", html_escape(file));
  if (f.data) out += fmt::format(", {} faces", f.data->mesh.n_faces());
  if (!f.page.empty()) out += fmt::format(" &middot; <a href=\"{}\">3D</a>", f.page);
  out += "</span>";
  if (!f.problem.empty()) out += "<br><i>" + html_escape(f.problem) + "</i>";
  return out + "</figcaption></figure>";
}

// A section per part of the pipeline, a heading per step with its notes, a grid of captioned pictures
// per comparison (side by side; the next comparison below).
std::string sections_html(const Steps& steps, Notes& notes, const std::vector<Figure>& figures) {
  std::string body, section;
  for (const auto& [sec, name] : steps) {
    if (sec != section) {
      if (!section.empty()) body += "</section>\n";
      section = sec;
      body += fmt::format("<section id=\"{}\" data-section=\"{}\"><h2>{}</h2>\n", id_of(sec), html_escape(sec),
                          html_escape(sec));
    }
    body += fmt::format("<h3 data-step=\"{0}\">{0}</h3>", html_escape(name));
    for (const auto& n : notes[name]) body += "<p class=\"note\">" + html_escape(n) + "</p>";
    std::optional<std::string> row;
    for (const auto& f : figures) {
      if (f.step != name) continue;
      const std::string key = f.spec.value("compare", std::string());
      if (!row || *row != key) {
        body += row ? "</div><div class=\"grid\">" : "<div class=\"grid\">";
        row = key;
      }
      body += figure_html(f);
    }
    if (row) body += "</div>\n";
  }
  if (!section.empty()) body += "</section>\n";
  return body;
}

// The mesh files in the folder that no figure shows, sorted.
std::vector<std::string> other_files(const DemoContext& ctx, const std::set<std::string>& shown) {
  std::vector<std::string> rest;
  for (const auto& e : fs::directory_iterator(ctx.dir)) {
    const std::string ext = e.path().extension().string();
    if (e.is_regular_file() && (ext == ".ply" || ext == ".obj" || ext == ".off" || ext == ".stl") &&
        !shown.count(e.path().filename().string()))
      rest.push_back(e.path().filename().string());
  }
  std::sort(rest.begin(), rest.end());
  return rest;
}

std::string other_files_html(const std::vector<std::string>& rest) {
  if (rest.empty()) return {};
  std::string body = "<section id=\"files\" data-section=\"Files\"><h2>Other files</h2><p class=\"files\">";
  for (size_t k = 0; k < rest.size(); ++k)
    body += fmt::format("{}<a href=\"{}\">{}</a>", k ? " &middot; " : "", html_escape(rest[k]), html_escape(rest[k]));
  return body + "</p></section>\n";
}

void write_index(const DemoContext& ctx, const std::string& body) {
  const std::string html = fmt::format(R"(<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>geotex demo</title>
<style>
  body {{ font: 13px/1.4 system-ui, sans-serif; margin: 16px 24px; color: #222; }}
  h1 {{ margin: 0 0 4px; }} h2 {{ border-bottom: 1px solid #ccc; margin: 20px 0 4px; }} h3 {{ margin: 10px 0 4px; font-size: 14px; }}
  .grid {{ display: grid; grid-template-columns: repeat(auto-fill, {}px); gap: 10px 12px; margin-bottom: 12px; }}
  figure {{ margin: 0; }} img {{ border: 1px solid #e4e4e4; display: block; }}
  figcaption {{ font-size: 11.5px; line-height: 1.3; color: #333; margin-top: 2px; }} .files {{ color: #777; }} .note {{ color: #a33; margin: 2px 0; }}
</style></head><body>
<h1>geotex demo</h1>
<p>The pipeline in order: input, the differential-geometry toolkit, denoising, texture, resizing. Each picture's
caption says what it shows and what was measured; pictures of one row share their camera and colour range (the
bar at their right). Click a picture to enlarge it, "3D" for a viewer page. Step summaries and timings:
<a href="README.md">README.md</a>, <a href="report.json">report.json</a>.</p>
{}
</body></html>
)",
                                       kWidth / kShrink, body);
  write_text_atomic(ctx.dir / "index.html", html);
}

DemoRegistrar step{900, "report", [](const DemoContext& ctx) {
  nlohmann::json& r = *ctx.report;
  const auto t0 = std::chrono::steady_clock::now();
  fs::create_directories(ctx.dir / "pictures");
  fs::create_directories(ctx.dir / "views");

  Steps steps;
  Notes notes;
  std::vector<Figure> figures = collect_figures(ctx, steps, notes);
  std::map<std::string, Loaded> meshes;  // the figures point into it
  load_figures(ctx, figures, meshes);
  std::map<std::string, Shared> shared = comparisons(figures);
  std::set<std::string> shown;
  const size_t drawn = draw_pictures(ctx, figures, shared, shown);
  const size_t pages = write_pages(ctx, figures, shared);
  const std::vector<std::string> rest = other_files(ctx, shown);
  write_index(ctx, sections_html(steps, notes, figures) + other_files_html(rest));

  const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r["index"] = (ctx.dir / "index.html").string();
  r["pictures"] = drawn;
  r["summary"].push_back(fmt::format("index.html: {} figures in {} steps, {} pictures, {} 3D pages, {} other files, in {:.1f} s",
                                     figures.size(), steps.size(), drawn, pages, rest.size(), sec));
}};

}  // namespace demo_report
}  // namespace geotex::cli
