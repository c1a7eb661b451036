// glTF 2.0 (.glb, and .gltf with data-URI or external .bin buffers) through tinygltf, which parses
// the JSON, the binary container and the buffers; this file turns the scene into one triangle mesh
// and back. Images are neither decoded nor loaded (geotex keeps geometry only).

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <unordered_map>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/io.h"
#include "io_detail.h"

namespace geotex::detail {

namespace fs = std::filesystem;

namespace {

using Mat4 = std::array<double, 16>;  // column-major, as glTF stores it

Mat4 identity() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }

Mat4 multiply(const Mat4& a, const Mat4& b) {
  Mat4 c{};
  for (int col = 0; col < 4; ++col)
    for (int row = 0; row < 4; ++row) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a[k * 4 + row] * b[col * 4 + k];
      c[col * 4 + row] = s;
    }
  return c;
}

// A node's local transform: its matrix, or T * R * S (glTF 2.0, section 3.5.3 "Transformations").
Mat4 local_transform(const tinygltf::Node& n) {
  if (n.matrix.size() == 16) {
    Mat4 m;
    std::copy(n.matrix.begin(), n.matrix.end(), m.begin());
    return m;
  }
  Mat4 t = identity(), r = identity(), s = identity();
  if (n.translation.size() == 3) t[12] = n.translation[0], t[13] = n.translation[1], t[14] = n.translation[2];
  if (n.rotation.size() == 4) {  // unit quaternion (x, y, z, w)
    const double x = n.rotation[0], y = n.rotation[1], z = n.rotation[2], w = n.rotation[3];
    r = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),     0,
         2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),     0,
         2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y), 0,
         0,                       0,                       0,                       1};
  }
  if (n.scale.size() == 3) s[0] = n.scale[0], s[5] = n.scale[1], s[10] = n.scale[2];
  return multiply(t, multiply(r, s));
}

double det3(const Mat4& m) {
  return m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) + m[8] * (m[1] * m[6] - m[5] * m[2]);
}

struct Reader {
  const tinygltf::Model& model;
  const std::string name;
  GltfSoup out;
  size_t dropped_points = 0, dropped_lines = 0, instances = 0, primitives = 0, strips_or_fans = 0;
  std::unordered_map<std::string, int64_t> seen;  // exact positions already in the soup

  [[noreturn]] void fail(const std::string& what) const {
    throw IoError(fmt::format("{}: {}", name, what));
  }

  // The bytes of an accessor's elements, bounds-checked against its buffer view and buffer.
  struct View {
    const unsigned char* data;
    size_t stride, count;
  };
  View view(int index, size_t element_size, const std::string& what) const {
    if (index < 0 || static_cast<size_t>(index) >= model.accessors.size())
      fail(fmt::format("{} refers to accessor {}, but there are {}", what, index, model.accessors.size()));
    const tinygltf::Accessor& a = model.accessors[index];
    if (a.sparse.isSparse) fail(fmt::format("accessor {} is sparse, which geotex does not read", index));
    if (a.bufferView < 0) fail(fmt::format("accessor {} has no buffer view (all zeros), which geotex does not read", index));
    if (static_cast<size_t>(a.bufferView) >= model.bufferViews.size())
      fail(fmt::format("accessor {} refers to buffer view {}, but there are {}", index, a.bufferView,
                       model.bufferViews.size()));
    const tinygltf::BufferView& bv = model.bufferViews[a.bufferView];
    if (bv.buffer < 0 || static_cast<size_t>(bv.buffer) >= model.buffers.size())
      fail(fmt::format("buffer view {} refers to buffer {}, but there are {}", a.bufferView, bv.buffer,
                       model.buffers.size()));
    const auto& buf = model.buffers[bv.buffer].data;
    const size_t stride = bv.byteStride ? bv.byteStride : element_size;
    const uint64_t begin = uint64_t(bv.byteOffset) + a.byteOffset;
    const uint64_t need = a.count == 0 ? 0 : uint64_t(a.count - 1) * stride + element_size;
    if (a.byteOffset + need > bv.byteLength || bv.byteOffset + bv.byteLength > buf.size())
      fail(fmt::format("accessor {} ({} elements) reaches past the end of its buffer (truncated?)", index, a.count));
    return {buf.data() + begin, stride, a.count};
  }

  void add_primitive(const tinygltf::Primitive& p, const Mat4& m, size_t mesh_index) {
    const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
    if (mode == TINYGLTF_MODE_POINTS) return void(++dropped_points);
    if (mode == TINYGLTF_MODE_LINE || mode == TINYGLTF_MODE_LINE_LOOP || mode == TINYGLTF_MODE_LINE_STRIP)
      return void(++dropped_lines);
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN)
      fail(fmt::format("mesh {} has a primitive of unknown mode {}", mesh_index, mode));
    const auto pos = p.attributes.find("POSITION");
    if (pos == p.attributes.end()) fail(fmt::format("mesh {} has a triangle primitive without POSITION", mesh_index));
    if (pos->second < 0 || static_cast<size_t>(pos->second) >= model.accessors.size())
      fail(fmt::format("mesh {}: POSITION refers to accessor {}, but there are {}", mesh_index, pos->second,
                       model.accessors.size()));
    const tinygltf::Accessor& pa = model.accessors[pos->second];
    if (pa.type != TINYGLTF_TYPE_VEC3 || pa.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
      fail(fmt::format("mesh {}: POSITION is not float VEC3 (quantized positions are not read)", mesh_index));
    const View pv = view(pos->second, 12, fmt::format("mesh {} POSITION", mesh_index));
    // Corners of this primitive: vertex indices into the soup.
    std::vector<int64_t> vid(pv.count);
    for (size_t i = 0; i < pv.count; ++i) {
      float f[3];
      std::memcpy(f, pv.data + i * pv.stride, 12);
      double q[3];
      for (int r = 0; r < 3; ++r)
        q[r] = m[0 * 4 + r] * double(f[0]) + m[1 * 4 + r] * double(f[1]) + m[2 * 4 + r] * double(f[2]) + m[12 + r];
      // Exporters split vertices at normal and UV seams: equal positions are one vertex of the surface.
      std::string key(reinterpret_cast<const char*>(q), sizeof q);
      auto [it, inserted] = seen.emplace(std::move(key), static_cast<int64_t>(out.xyz.size() / 3));
      if (inserted) out.xyz.insert(out.xyz.end(), q, q + 3);
      vid[i] = it->second;
    }
    std::vector<uint64_t> idx;
    if (p.indices >= 0) {
      if (static_cast<size_t>(p.indices) >= model.accessors.size())
        fail(fmt::format("mesh {}: indices refer to accessor {}, but there are {}", mesh_index, p.indices,
                         model.accessors.size()));
      const tinygltf::Accessor& ia = model.accessors[p.indices];
      const size_t es = ia.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                        : ia.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                        : ia.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4 : 0;
      if (es == 0 || ia.type != TINYGLTF_TYPE_SCALAR)
        fail(fmt::format("mesh {}: indices are not unsigned byte, short or int scalars", mesh_index));
      const View iv = view(p.indices, es, fmt::format("mesh {} indices", mesh_index));
      idx.resize(iv.count);
      for (size_t i = 0; i < iv.count; ++i) {
        const unsigned char* e = iv.data + i * iv.stride;
        if (es == 1) idx[i] = e[0];
        else if (es == 2) { uint16_t v; std::memcpy(&v, e, 2); idx[i] = v; }
        else { uint32_t v; std::memcpy(&v, e, 4); idx[i] = v; }
        if (idx[i] >= pv.count)
          fail(fmt::format("mesh {}: index {} at position {} refers past the primitive's {} vertices", mesh_index,
                           idx[i], i, pv.count));
      }
    } else {
      idx.resize(pv.count);
      for (size_t i = 0; i < pv.count; ++i) idx[i] = i;
    }
    // A transform that mirrors turns the front face round (glTF 2.0, 3.7.4 "Meshes": a negative
    // determinant reverses the winding order): swap two corners to keep the faces outward.
    const bool mirror = det3(m) < 0;
    auto add = [&](uint64_t a, uint64_t b, uint64_t c) {
      if (mirror) std::swap(a, b);
      out.triangles.insert(out.triangles.end(), {vid[a], vid[b], vid[c]});
    };
    const size_t n = idx.size();
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      for (size_t t = 0; t + 2 < n; t += 3) add(idx[t], idx[t + 1], idx[t + 2]);
      if (n % 3) out.warnings.push_back(fmt::format("mesh {}: {} trailing index(es) form no triangle (ignored)", mesh_index, n % 3));
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {  // odd triangles swap their first two corners
      for (size_t t = 0; t + 2 < n; ++t)
        if (t % 2 == 0) add(idx[t], idx[t + 1], idx[t + 2]);
        else add(idx[t + 1], idx[t], idx[t + 2]);
    } else {  // fan: triangle t is (t+1, t+2, 0)
      for (size_t t = 0; t + 2 < n; ++t) add(idx[t + 1], idx[t + 2], idx[0]);
    }
    if (mode != TINYGLTF_MODE_TRIANGLES) ++strips_or_fans;
    ++primitives;
  }

  void visit(int node, const Mat4& parent, int depth) {
    if (node < 0 || static_cast<size_t>(node) >= model.nodes.size())
      fail(fmt::format("the scene refers to node {}, but there are {}", node, model.nodes.size()));
    // glTF forbids cycles; a file with one would recurse forever.
    if (depth > 1000) fail("the node tree is deeper than 1000 levels (a cycle?)");
    const tinygltf::Node& n = model.nodes[node];
    const Mat4 m = multiply(parent, local_transform(n));
    if (n.mesh >= 0) {
      if (static_cast<size_t>(n.mesh) >= model.meshes.size())
        fail(fmt::format("node {} refers to mesh {}, but there are {}", node, n.mesh, model.meshes.size()));
      ++instances;
      for (const auto& p : model.meshes[n.mesh].primitives) add_primitive(p, m, static_cast<size_t>(n.mesh));
    }
    for (int c : n.children) visit(c, m, depth + 1);
  }
};

}  // namespace

GltfSoup read_gltf(std::string_view data, bool binary, const fs::path& name) {
  const std::string shown = name.string();
  if (data.size() > std::numeric_limits<unsigned int>::max())
    throw IoError(fmt::format("{}: larger than 4 GiB, more than a glTF reader takes", shown));
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader([](tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*,
                           int, void*) { return true; },
                        nullptr);
  // External buffers are read like every other input: regular files only, by their path beside the
  // .gltf, as they were when opened.
  tinygltf::FsCallbacks fs_callbacks{};
  fs_callbacks.FileExists = [](const std::string& path, void*) {
    std::error_code ec;
    return fs::exists(path, ec);
  };
  fs_callbacks.ExpandFilePath = [](const std::string& path, void*) { return path; };
  fs_callbacks.ReadWholeFile = [](std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
    try {
      const std::string bytes = read_regular_file(path, kMaxStreamBytes, "a glTF buffer");
      out->assign(bytes.begin(), bytes.end());
      return true;
    } catch (const IoError& e) {
      if (err) *err += e.what();
      return false;
    }
  };
  fs_callbacks.WriteWholeFile = [](std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "geotex does not write from its glTF reader";
    return false;
  };
  loader.SetFsCallbacks(fs_callbacks);
  tinygltf::Model model;
  std::string err, warn;
  const std::string base = name.has_parent_path() ? name.parent_path().string() : std::string(".");
  const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(data.data()),
                                                       static_cast<unsigned int>(data.size()), base)
                         : loader.LoadASCIIFromString(&model, &err, &warn, data.data(),
                                                      static_cast<unsigned int>(data.size()), base);
  auto first_line = [](std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
    const size_t nl = s.find('\n');
    return nl == std::string::npos ? s : s.substr(0, nl) + " (...)";
  };
  if (!ok) throw IoError(fmt::format("{}: not a readable glTF 2.0 file: {}", shown, first_line(err.empty() ? warn : err)));
  Reader r{model, shown, {}};
  r.out.format = binary ? "gltf (.glb)" : "gltf (.gltf)";
  const Mat4 id = identity();
  if (!model.scenes.empty()) {
    const size_t scene = model.defaultScene >= 0 ? static_cast<size_t>(model.defaultScene) : 0;
    if (scene >= model.scenes.size())
      throw IoError(fmt::format("{}: the default scene is {}, but there are {}", shown, scene, model.scenes.size()));
    for (int n : model.scenes[scene].nodes) r.visit(n, id, 0);
    if (model.scenes.size() > 1)
      r.out.notes.push_back(fmt::format("read scene {} of {} (the default one)", scene, model.scenes.size()));
  } else {
    // No scene: the file says nothing about placement; every mesh is read once, untransformed.
    for (size_t m = 0; m < model.meshes.size(); ++m)
      for (const auto& p : model.meshes[m].primitives) r.add_primitive(p, id, m);
    r.out.notes.push_back("the file has no scene: read every mesh once, without node transforms");
  }
  if (r.dropped_points) r.out.warnings.push_back(fmt::format("dropped {} point primitive(s) (geotex reads triangles)", r.dropped_points));
  if (r.dropped_lines) r.out.warnings.push_back(fmt::format("dropped {} line primitive(s) (geotex reads triangles)", r.dropped_lines));
  if (r.strips_or_fans) r.out.notes.push_back(fmt::format("decoded {} triangle strip/fan primitive(s)", r.strips_or_fans));
  if (r.primitives > 1 || r.instances > 1)
    r.out.notes.push_back(fmt::format("merged {} triangle primitive(s) of {} mesh instance(s) into one mesh",
                                      r.primitives, r.instances));
  return std::move(r.out);
}

std::string gltf_bytes(const Mesh& mesh, bool binary, const fs::path& path) {
  const MatrixX3d V = positions(mesh);
  const MatrixX3i F = faces(mesh);
  // glTF positions are 32-bit floats (accessor componentType 5126).
  constexpr double kFloatMax = std::numeric_limits<float>::max();
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (V.row(i).cwiseAbs().maxCoeff() > kFloatMax)
      throw InvalidInput(fmt::format("{}: not written: vertex {} has a coordinate beyond the range of glTF's "
                                     "32-bit floats ({}, {}, {})", path.string(), i, V(i, 0), V(i, 1), V(i, 2)));
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "geotex";
  tinygltf::Buffer buffer;
  const size_t nv = static_cast<size_t>(V.rows()), nf = static_cast<size_t>(F.rows());
  buffer.data.resize(nv * 12 + nf * 12);
  std::vector<double> lo(3, std::numeric_limits<double>::infinity()), hi(3, -std::numeric_limits<double>::infinity());
  for (size_t i = 0; i < nv; ++i)
    for (int k = 0; k < 3; ++k) {
      const float f = static_cast<float>(V(i, k));
      std::memcpy(buffer.data.data() + 12 * i + 4 * k, &f, 4);
      lo[k] = std::min(lo[k], double(f));  // min/max of the stored floats, as the spec requires
      hi[k] = std::max(hi[k], double(f));
    }
  for (size_t t = 0; t < nf; ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = static_cast<uint32_t>(F(t, k));
      std::memcpy(buffer.data.data() + nv * 12 + 12 * t + 4 * k, &v, 4);
    }
  model.buffers.push_back(std::move(buffer));
  tinygltf::BufferView pv, iv;
  pv.buffer = 0, pv.byteOffset = 0, pv.byteLength = nv * 12, pv.target = TINYGLTF_TARGET_ARRAY_BUFFER;
  iv.buffer = 0, iv.byteOffset = nv * 12, iv.byteLength = nf * 12, iv.target = TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;
  model.bufferViews = {pv, iv};
  tinygltf::Accessor pa, ia;
  pa.bufferView = 0, pa.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT, pa.count = nv, pa.type = TINYGLTF_TYPE_VEC3;
  pa.minValues = lo, pa.maxValues = hi;
  ia.bufferView = 1, ia.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, ia.count = 3 * nf, ia.type = TINYGLTF_TYPE_SCALAR;
  model.accessors = {pa, ia};
  tinygltf::Primitive prim;
  prim.attributes["POSITION"] = 0;
  prim.indices = 1;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  tinygltf::Mesh m;
  m.primitives.push_back(prim);
  model.meshes.push_back(m);
  tinygltf::Node node;
  node.mesh = 0;
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  tinygltf::TinyGLTF writer;
  std::ostringstream os;
  // A stream: the buffer goes into the .glb's BIN chunk, or into the .gltf as a base64 data URI.
  if (!writer.WriteGltfSceneToStream(&model, os, /*prettyPrint=*/!binary, /*writeBinary=*/binary))
    throw IoError(fmt::format("{}: the glTF writer failed", path.string()));
  return std::move(os).str();
}

}  // namespace geotex::detail
