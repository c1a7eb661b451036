// Demo step "report": pictures of every mesh the other steps wrote, their metrics against the clean
// input, 3D viewer pages, and an index.html that puts them side by side. Runs after the capability
// steps (order 900). A step only sees its own report section, so the meshes are found by scanning
// the demo folder; files are grouped by the name before their first '-' ("cube-noisy.ply" → cube).

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "cli.h"
#include "geotex/core/geometry.h"
#include "geotex/tools/metrics.h"
#include "geotex/tools/render.h"
#include "geotex/tools/viewer.h"

namespace geotex::cli {
namespace {

namespace fs = std::filesystem;

constexpr size_t kMaxFaces = 300000;  // larger meshes are listed but neither drawn nor put in a page
constexpr size_t kMaxMeshes = 80;     // keeps the step within seconds however much the other steps write

std::string html(const std::string& s) {
  std::string out;
  for (char c : s) out += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : c == '"' ? "&quot;" : std::string(1, c);
  return out;
}

struct Entry {
  fs::path file;
  std::string stem, group;
  Mesh mesh;
  MeshLayers layers;
  MeshSummary summary;
  std::string picture, page, field, note;
  std::optional<Comparison> vs_truth;
  std::string truth;
};

bool is_truth(const std::string& stem) {
  return stem.find("clean") != std::string::npos || stem.find("truth") != std::string::npos;
}

// The field a picture shows: the mesh's own "feature", "height" or "error" property, else its first
// per-vertex property (e.g. "adf"), else none.
std::string picture_field(const MeshLayers& l) {
  for (const char* name : {"feature", "height", "error"})
    if (l.fields.count(name)) return name;
  return l.fields.empty() ? "" : l.fields.begin()->first;
}

DemoRegistrar step{900, "report", [](const DemoContext& ctx) {
  nlohmann::json& r = *ctx.report;
  const auto t0 = std::chrono::steady_clock::now();
  const fs::path pictures = ctx.dir / "pictures", views = ctx.dir / "views";
  fs::create_directories(pictures);
  fs::create_directories(views);

  // Every mesh file the earlier steps wrote, in name order.
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(ctx.dir)) {
    if (!e.is_regular_file()) continue;
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    if (ext == ".ply" || ext == ".obj" || ext == ".off" || ext == ".stl") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  if (files.size() > kMaxMeshes) {
    r["summary"].push_back(fmt::format("{} meshes found; the report shows the first {}", files.size(), kMaxMeshes));
    files.resize(kMaxMeshes);
  }

  std::vector<Entry> entries;
  for (const auto& f : files) {
    Entry e;
    e.file = f;
    e.stem = f.stem().string();
    e.group = e.stem.substr(0, e.stem.find('-'));
    try {
      ReadReport rep;
      e.mesh = read_mesh(f, {}, &rep);
      e.layers = read_mesh_layers(f, e.mesh.n_vertices());
    } catch (const Error&) {
      continue;  // not a surface (e.g. an OBJ of line segments): nothing to draw
    }
    e.summary = summarize(e.mesh);
    entries.push_back(std::move(e));
  }

  // Metrics against the clean mesh: the truth of the same group, or a "<shape>-clean" whose shape
  // name appears in this file's name (mrf-cube-… → cube-clean), if it really is the same shape.
  std::vector<const Entry*> truths;
  for (const auto& e : entries)
    if (is_truth(e.stem)) truths.push_back(&e);
  for (auto& e : entries) {
    if (is_truth(e.stem) || e.mesh.n_faces() > kMaxFaces) continue;
    const Entry* truth = nullptr;
    for (const Entry* t : truths)
      if (t->group == e.group) truth = t;
    if (!truth)
      for (const Entry* t : truths)
        if (("-" + e.stem + "-").find("-" + t->group + "-") != std::string::npos) truth = t;
    if (!truth || truth->mesh.n_faces() > kMaxFaces) continue;
    const Comparison c = compare_meshes(e.mesh, truth->mesh);
    if (c.hausdorff_relative > 0.25) continue;  // a different shape after all
    e.vs_truth = c;
    e.truth = truth->stem;
    e.layers.fields["error"] = distance_to_surface(e.mesh, truth->mesh);
  }

  // Pictures and viewer pages.
  std::string script;
  try {
    script = viewer_script();
    write_text_atomic(views / "geotex-viewer.js", script);
  } catch (const IoError& err) {
    r["summary"].push_back(std::string("3D pages skipped: ") + err.what());
  }
  std::map<std::string, Camera> truth_camera;
  std::map<std::string, std::vector<const Entry*>> groups;
  size_t drawn = 0, pages = 0;
  for (auto& e : entries) {
    groups[e.group].push_back(&e);
    if (e.mesh.n_faces() > kMaxFaces) {
      e.note = "too large to draw here";
      continue;
    }
    RenderOptions o;
    o.width = 480;
    o.height = 360;
    o.up = UpAxis::Z;  // the demo's shapes are generated z-up
    RenderLayers rl;
    e.field = e.vs_truth ? "error" : picture_field(e.layers);
    if (!e.field.empty()) rl.field = e.layers.fields.at(e.field);
    rl.segments = e.layers.segments;
    rl.segment_labels = e.layers.labels;
    // Results share their clean input's camera, so that they line up with it; the legend's room is
    // kept free whenever a picture of the set may show one.
    const std::string key = e.vs_truth ? e.truth : is_truth(e.stem) ? e.stem : "";
    const int legend_room = key.empty() && e.field.empty() ? 0 : legend_width(o.width);
    if (auto it = truth_camera.find(key); !key.empty() && it != truth_camera.end()) o.camera = it->second;
    else {
      const Entry* framed = &e;
      for (const Entry* t : truths)
        if (t->stem == key) framed = t;
      o.camera = fit_camera(framed->mesh, o, legend_room);
      if (!key.empty()) truth_camera[key] = *o.camera;
    }
    const Rendering pic = render_mesh(e.mesh, o, rl);
    e.picture = "pictures/" + e.stem + ".png";
    write_png(pic.image, ctx.dir / e.picture);
    ++drawn;
    if (!script.empty()) {
      ++pages;
      ViewerOptions v;
      v.up = UpAxis::Z;
      v.title = e.file.filename().string();
      v.initial_field = e.field;
      v.script_src = "geotex-viewer.js";
      e.page = "views/" + e.stem + ".html";
      write_text_atomic(ctx.dir / e.page, viewer_page({{e.file.filename().string(), e.mesh, e.layers}}, v, script));
    }
  }

  // Group pages: up to six meshes of a group side by side with linked cameras.
  std::map<std::string, std::string> group_page;
  if (!script.empty())
    for (const auto& [g, members] : groups) {
      std::vector<ViewerMesh> ms;
      std::string field;
      for (const Entry* e : members)
        if (!e->page.empty() && ms.size() < 6) {
          ms.push_back({e->file.filename().string(), e->mesh, e->layers});
          if (e->vs_truth) field = "error";
        }
      if (ms.size() < 2) continue;
      ViewerOptions v;
      v.up = UpAxis::Z;
      v.title = "geotex demo: " + g;
      v.initial_field = field;
      v.script_src = "geotex-viewer.js";
      group_page[g] = "views/group-" + g + ".html";
      ++pages;
      write_text_atomic(ctx.dir / group_page[g], viewer_page(ms, v, script));
    }

  // index.html
  std::string body;
  for (const auto& [g, members] : groups) {
    body += fmt::format("<section><h2>{}</h2>", html(g));
    if (group_page.count(g)) body += fmt::format("<p><a href=\"{}\">compare side by side in 3D</a></p>", group_page[g]);
    body += "<div class=\"grid\">";
    for (const Entry* e : members) {
      body += "<figure>";
      if (!e->picture.empty()) {
        const std::string img = fmt::format("<img src=\"{}\" alt=\"{}\" width=\"480\" height=\"360\">", e->picture, html(e->stem));
        body += e->page.empty() ? img : fmt::format("<a href=\"{}\">{}</a>", e->page, img);
      }
      body += fmt::format("<figcaption><b><a href=\"{0}\">{0}</a></b><br>{1} vertices, {2} faces", html(e->file.filename().string()),
                          e->summary.vertices, e->summary.faces);
      if (e->summary.genus >= 0) body += fmt::format(", genus {}", e->summary.genus);
      if (e->layers.segments.rows() > 0) body += fmt::format("<br>{} labelled edges (red lines)", e->layers.segments.rows());
      if (e->vs_truth)
        body += fmt::format("<br>vs {}: normal error {:.2f}&deg;, Ev {:.2e}, Hausdorff {:.2e} (of the diagonal)",
                            html(e->truth), e->vs_truth->mean_normal_error_deg, e->vs_truth->ev_relative,
                            e->vs_truth->hausdorff_relative);
      if (!e->field.empty()) body += fmt::format("<br>colour: {}", e->field == "error" ? "distance to " + html(e->truth) : html(e->field));
      if (!e->page.empty()) body += fmt::format("<br><a href=\"{}\">3D view</a>", e->page);
      if (!e->note.empty()) body += "<br><i>" + html(e->note) + "</i>";
      body += "</figcaption></figure>";
    }
    body += "</div></section>\n";
  }
  const std::string page = fmt::format(R"(<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>geotex demo</title>
<style>
  body {{ font: 14px/1.45 system-ui, sans-serif; margin: 24px; color: #222; }}
  h1 {{ margin-top: 0; }} h2 {{ border-bottom: 1px solid #ddd; padding-bottom: 4px; margin-top: 32px; }}
  .grid {{ display: flex; flex-wrap: wrap; gap: 18px; }}
  figure {{ margin: 0; width: 480px; }} img {{ border: 1px solid #e4e4e4; display: block; }}
  figcaption {{ font-size: 13px; color: #444; margin-top: 4px; }}
</style></head><body>
<h1>geotex demo</h1>
<p>Every mesh the demo wrote, grouped by name: a picture (click for a 3D view), its size, and its distance to
the clean input where there is one (normal error in degrees, E<sub>v</sub> and Hausdorff distance relative to the
bounding-box diagonal; the colour map shows each vertex's distance). Step summaries and timings:
<a href="README.md">README.md</a>, <a href="report.json">report.json</a>.</p>
{}
</body></html>
)",
                                       body);
  write_text_atomic(ctx.dir / "index.html", page);
  const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r["index"] = (ctx.dir / "index.html").string();
  r["pictures"] = drawn;
  r["summary"].push_back(fmt::format("index.html: {} meshes in {} groups, {} pictures, {} 3D pages, in {:.1f} s",
                                     entries.size(), groups.size(), drawn, pages, sec));
}};

}  // namespace
}  // namespace geotex::cli
