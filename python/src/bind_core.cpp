// Python bindings of the foundation: I/O, shapes, noise, geometry, Laplacians, smoothing, metrics.

#include "common.h"

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/toolkit/laplace.h"
#include "geotex/tools/metrics.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/shapes.h"
#include "geotex/toolkit/smoothing.h"

namespace geotex::python {

namespace {

LaplacianType laplacian_type(const std::string& s) {
  if (s == "cotan" || s == "cotangent") return LaplacianType::Cotangent;
  if (s == "umbrella") return LaplacianType::Umbrella;
  throw InvalidInput("laplacian must be 'cotan' or 'umbrella', not '" + s + "'");
}

MassType mass_type(const std::string& s) {
  if (s == "voronoi") return MassType::Voronoi;
  if (s == "barycentric") return MassType::Barycentric;
  if (s == "thesis") return MassType::Thesis;
  throw InvalidInput("mass must be 'voronoi', 'barycentric' or 'thesis', not '" + s + "'");
}

py::dict summary_dict(const Mesh& m) {
  const MeshSummary s = summarize(m);
  py::dict d;
  d["vertices"] = s.vertices;
  d["edges"] = s.edges;
  d["faces"] = s.faces;
  d["components"] = s.components;
  d["boundary_loops"] = s.boundary_loops;
  d["closed"] = s.closed;
  d["euler_characteristic"] = s.euler;
  d["genus"] = s.genus >= 0 ? py::object(py::int_(s.genus)) : py::object(py::none());
  d["mean_edge_length"] = s.mean_edge;
  d["area"] = s.area;
  d["volume"] = s.closed ? py::object(py::float_(s.volume)) : py::object(py::none());
  d["isolated_vertices"] = s.isolated_vertices;
  d["zero_area_faces"] = s.zero_area_faces;
  d["bbox_min"] = py::make_tuple(s.box.min[0], s.box.min[1], s.box.min[2]);
  d["bbox_max"] = py::make_tuple(s.box.max[0], s.box.max[1], s.box.max[2]);
  return d;
}

}  // namespace

void bind_core(py::module_& m) {
  using V3 = Eigen::Ref<const MatrixX3d>;
  using F3 = Eigen::Ref<const MatrixX3i>;

  m.def("read_mesh", [](const std::string& path, bool strict) {
        ReadOptions o;
        o.strict = strict;
        ReadReport rep;
        const Mesh mesh = read_mesh(path, o, &rep);
        for (const auto& w : rep.warnings) {
          const std::string msg = path + ": " + w;
          if (PyErr_WarnEx(PyExc_UserWarning, msg.c_str(), 1) != 0) throw py::error_already_set();
        }
        return from_mesh(mesh);
      },
      py::arg("path"), py::arg("strict") = false,
      R"doc(Read a mesh file (.obj, .ply, .off, .stl).

Returns (V, F): V float64 #V×3 positions, F int32 #F×3 triangles. Polygons are split into fans,
PLY triangle strips decoded. Faces that are degenerate, duplicated or non-manifold are dropped with
a UserWarning (strict=True raises InvalidInput instead). Raises IoError for missing, malformed or
truncated files and InvalidInput for NaN/inf coordinates or out-of-range indices.)doc");

  m.def("write_mesh", [](const std::string& path, V3 V, F3 F, bool binary) {
        WriteOptions o;
        o.binary = binary;
        write_mesh(to_mesh(V, F), path, o);
      },
      py::arg("path"), py::arg("V"), py::arg("F"), py::arg("binary") = true,
      "Write a mesh atomically (format from the extension; binary PLY/STL unless binary=False).");

  m.def("info", [](V3 V, F3 F) { return summary_dict(to_mesh(V, F)); }, py::arg("V"), py::arg("F"),
        "Counts, boundary loops, components, Euler characteristic, genus, mean edge length, area, volume, bbox.");

  m.def("shape_names", &shape_names, "Names accepted by generate().");
  m.def("generate", [](const std::string& name, int level, uint64_t seed, bool with_base) -> py::object {
        const TexturedShape s = make_shape(name, level, seed);
        if (!with_base) return from_mesh(s.textured);
        return py::make_tuple(from_mesh(s.textured), from_mesh(s.base));
      },
      py::arg("name"), py::arg("level") = 1, py::arg("seed") = 1, py::arg("with_base") = false,
      R"doc(Procedural test shape: cube, cylinder, sphere, torus, plane, spiky-sphere, spiky-plane.

Returns (V, F), or ((V, F), (Vbase, Fbase)) with with_base=True (the spiky shapes' untextured base).)doc");

  m.def("add_noise", [](V3 V, F3 F, double sigma, bool along_normal, double impulsive_fraction, uint64_t seed) {
        NoiseOptions o;
        o.sigma = sigma;
        o.along_normal = along_normal;
        o.impulsive_fraction = impulsive_fraction;
        o.seed = seed;
        return VArray(add_noise(to_mesh(V, F), o));
      },
      py::arg("V"), py::arg("F"), py::arg("sigma") = 0.3, py::arg("along_normal") = false,
      py::arg("impulsive_fraction") = 0.0, py::arg("seed") = 1,
      "Seeded Gaussian noise, sigma in mean edge lengths. Returns the noisy #V×3 positions.");

  m.def("smooth", [](V3 V, F3 F, const std::string& laplacian, bool implicit, double lambda_, int steps,
                     const std::string& mass, bool fix_boundary, bool rescale, bool update_weights) {
        SmoothingOptions o;
        o.laplacian = laplacian_type(laplacian);
        o.implicit = implicit;
        o.lambda = lambda_;
        o.steps = steps;
        o.mass = mass_type(mass);
        o.fix_boundary = fix_boundary;
        o.rescale = rescale;
        o.update_weights = update_weights;
        py::gil_scoped_release release;
        return VArray(smooth(to_mesh(V, F), o));
      },
      py::arg("V"), py::arg("F"), py::arg("laplacian") = "cotan", py::arg("implicit") = true,
      py::arg("lambda_") = 1.0, py::arg("steps") = 1, py::arg("mass") = "voronoi", py::arg("fix_boundary") = true,
      py::arg("rescale") = false, py::arg("update_weights") = true,
      R"doc(Laplacian smoothing, thesis Eq. (5.12) explicit or (5.14) implicit. Same defaults as `geotex smooth`.

lambda_ is dimensionless for 'umbrella' and in squared mean edge lengths for 'cotan'.
Returns the new #V×3 positions (same connectivity).)doc");

  m.def("compare", [](V3 V, F3 F, V3 Vt, F3 Ft) {
        const Comparison c = compare_meshes(to_mesh(V, F), to_mesh(Vt, Ft));
        py::dict d;
        d["mean_normal_error_deg"] = c.mean_normal_error_deg;
        d["max_normal_error_deg"] = c.max_normal_error_deg;
        d["faces_matched_by"] = c.faces_by_index ? "index" : "closest-face";
        d["ev"] = c.ev;
        d["ev_relative"] = c.ev_relative;
        d["hausdorff"] = c.hausdorff;
        d["hausdorff_relative"] = c.hausdorff_relative;
        d["mean_distance"] = c.mean_distance;
        d["bbox_diagonal"] = c.diagonal;
        return d;
      },
      py::arg("V"), py::arg("F"), py::arg("V_truth"), py::arg("F_truth"),
      "Mean face-normal error (degrees), Ev and Hausdorff distance of a result against the truth.");

  m.def("score_edge_labels", [](const MatrixX2i& labelled, const MatrixX2i& truth) {
        const LabelScore s = score_edge_labels(labelled, truth);
        return py::dict(py::arg("precision") = s.precision, py::arg("recall") = s.recall, py::arg("f1") = s.f1);
      },
      py::arg("labelled"), py::arg("truth"), "Precision/recall/F1 of labelled edges (#×2 vertex pairs).");

  m.def("face_normals", [](V3 V, F3 F) { return VArray(face_normals(to_mesh(V, F))); }, py::arg("V"), py::arg("F"));
  m.def("vertex_normals", [](V3 V, F3 F, const std::string& weighting) {
        const NormalWeighting w = weighting == "angle" ? NormalWeighting::Angle
                                  : weighting == "uniform" ? NormalWeighting::Uniform : NormalWeighting::Area;
        if (weighting != "angle" && weighting != "uniform" && weighting != "area")
          throw InvalidInput("weighting must be 'area', 'angle' or 'uniform'");
        return VArray(vertex_normals(to_mesh(V, F), w));
      },
      py::arg("V"), py::arg("F"), py::arg("weighting") = "area");
  m.def("face_areas", [](V3 V, F3 F) { return Eigen::VectorXd(face_areas(to_mesh(V, F))); }, py::arg("V"), py::arg("F"));
  m.def("edges", [](V3 V, F3 F) { return MatrixX2i(edges(to_mesh(V, F))); }, py::arg("V"), py::arg("F"),
        "#E×2 vertex indices of the edges, in the order used by every per-edge array.");
  m.def("dihedral_angles", [](V3 V, F3 F) { return Eigen::VectorXd(dihedral_angles(to_mesh(V, F))); },
        py::arg("V"), py::arg("F"), "Signed dihedral angle per edge (radians; convex > 0), edges() order.");
  m.def("mean_edge_length", [](V3 V, F3 F) { return mean_edge_length(to_mesh(V, F)); }, py::arg("V"), py::arg("F"));
  m.def("boundary_loops", [](V3 V, F3 F) { return boundary_loops(to_mesh(V, F)); }, py::arg("V"), py::arg("F"));
  m.def("connected_components", [](V3 V, F3 F) { return Eigen::VectorXi(connected_components(to_mesh(V, F))); },
        py::arg("V"), py::arg("F"), "Component id per vertex.");

  m.def("umbrella_laplacian", [](V3 V, F3 F) { return umbrella_laplacian(to_mesh(V, F)); }, py::arg("V"), py::arg("F"),
        "Umbrella operator, Eq. (5.8), as a scipy.sparse matrix.");
  m.def("cotan_matrix", [](V3 V, F3 F) { return cotan_matrix(to_mesh(V, F)); }, py::arg("V"), py::arg("F"),
        "Symmetric cotangent matrix C (C_ij = ½(cot α + cot β)), scipy.sparse.");
  m.def("mass_matrix", [](V3 V, F3 F, const std::string& mass) { return mass_matrix(to_mesh(V, F), mass_type(mass)); },
        py::arg("V"), py::arg("F"), py::arg("mass") = "voronoi", "Diagonal mass matrix, scipy.sparse.");
  m.def("cotan_laplacian", [](V3 V, F3 F, const std::string& mass) {
        return cotan_laplacian(to_mesh(V, F), mass_type(mass));
      },
      py::arg("V"), py::arg("F"), py::arg("mass") = "voronoi", "L = M⁻¹C, Eq. (5.11) with mass='thesis'.");
  m.def("mean_curvature_normals", [](V3 V, F3 F) { return VArray(mean_curvature_normals(to_mesh(V, F))); },
        py::arg("V"), py::arg("F"), "H n per vertex (n/r on a sphere of radius r), Eq. (5.10).");
}

}  // namespace geotex::python
