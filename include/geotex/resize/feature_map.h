#pragma once
//! \file feature_map.h Feature maps for feature-aware resizing (thesis Sec. 9.4): per-vertex weights
//! f_i ∈ [0, 1] marking the parts of a model that must keep their shape.
//!
//! A continuous importance map (the default, FeatureMapMethod::Importance): f_i ∈ [0, 1] says how much
//! the surface around vertex i shows a stretch. It is high where the surface has detail: relief over
//! a smoothed copy of itself at three scales (implicit cotangent smoothing, times (c h)² for c = s/2,
//! s, 2s, h the mean edge length; each relief in units of its own area-weighted 90th percentile), and
//! where that relief varies (eyes, lips, ornaments: the relief minus its own smoothed copy, zero on
//! flat, spherical and cylindrical stretches of surface, where a stretch is hard to see); protrusions
//! (the height map below) count fully. The raw value passes a smoothstep between importance_low and
//! importance_high and a few Laplacian diffusion steps, so that it has no edge of its own (a binary
//! map's rim becomes the resize's crease).
//!
//! Two binary detectors, both grown to whole features by the same rule, and their combination:
//!  - height: each vertex's height over a smoothed base (the base of ch. 8, implicit cotangent
//!    smoothing at a scale tied to the model's size);
//!  - adf: the auto diffusion function (Gębal et al. 2009), which the thesis thresholds for the tentacle
//!    stick of Fig. 9.5 and which peaks on protrusions (ears, horns, legs, tentacles);
//!  - auto: the ADF map, or, where the ADF finds no protrusion (less than 0.5% of the surface: a relief
//!    on an open plate, where the ADF peaks at the border instead), the height map. (Their union was
//!    tried: on closed models the height map adds partial ear rims and belts around a body, such as
//!    both of cheburashka's feet as one region, which cannot stay rigid while the body widens.)
//! A detector's field g is turned into a map without a fixed threshold: a local maximum of g is a
//! feature's peak when g exceeds the surface's median by \p significance robust standard deviations
//! (1.4826 × the median absolute deviation, both area-weighted), and the feature is the peak's
//! watershed basin: every vertex whose steepest ascent on g ends at that peak. The basin stops where g
//! turns up again, which is the protrusion's base (the valley of g around its foot), not a level set.
//! A protrusion with two tips (a hair bun, a forked horn) has two maxima, often only one of them
//! significant: basins joined by a pass (the highest edge between them) higher than \p merge_pass
//! robust deviations are one feature, the way persistence merges maxima separated by a shallow saddle.

#include <limits>
#include <string>

#include "geotex/core/mesh.h"
#include "geotex/core/options.h"
#include "geotex/core/progress.h"

namespace geotex {

enum class FeatureMapMethod {
  Height,  //!< height over a smoothed base
  Adf,     //!< auto diffusion function (Sec. 9.4)
  Auto,    //!< Adf, or Height where the ADF finds no protrusion (binary)
  None,    //!< no features (every f_i = 0: the plain space map)
  Importance  //!< continuous importance in [0, 1] (default; see the file comment)
};
//! "importance", "auto", "height", "adf", "none".
const EnumNames<FeatureMapMethod>& feature_map_names();

struct FeatureMapOptions {
  FeatureMapMethod method = FeatureMapMethod::Importance;
  //! Importance: the middle smoothing scale s of the relief, in mean edge lengths (scales s/2, s, 2s).
  double detail_scale = 4.0;
  //! Importance: the raw value (mean of the normalised reliefs and their variation, ≈ 1 at the
  //! 90th percentile) maps to 0 below importance_low and to 1 above importance_high (smoothstep).
  double importance_low = 0.1;
  double importance_high = 0.6;
  //! Importance: share of the raw value from the relief's variation (the rest from the relief itself).
  double variation_share = 0.5;
  //! Importance: Laplacian diffusion steps (½ f + ½ neighbour mean) smoothing the map.
  int importance_smoothing = 6;
  //! Importance: protrusions (the height map's significant basins, dropped when larger than
  //! max_extent) count as fully important; "adf" uses the ADF map instead (seconds on large meshes).
  bool protrusions = true;
  bool importance_adf = false;
  //! Importance: a boundary vertex's relief is at least its distance from its boundary loop smoothed along
  //! itself (at the same three scales): the outline of an open or flat model (a cut-out figure's hands and
  //! feet, a shell's rims), which the surface's smoothing does not see.
  bool importance_outline = true;
  //! Height: the base is one implicit cotangent smoothing step of time (s R)², R = √(area / 4π) the
  //! radius of the sphere of the same area, s this scale; closed bases are rescaled to the input's
  //! volume. Features narrower than about s R are flattened away, so they stand out as height.
  double smoothing_scale = 0.1;
  //! ADF: diffusion time in units of 1/λ_1 (Gębal et al.); small t shows small features.
  double adf_t = 0.05;
  int eigenpairs = 100;  //!< ADF: Laplace eigenpairs summed
  //! ADF on a mesh with more than adf_full_vertices vertices: the spectrum of a simplification to
  //! adf_vertices vertices (simplify.h), the ADF extended back harmonically. The eigenpairs'
  //! wavelengths are far longer than such a mesh's edges, but the watershed map reacts to small changes
  //! of the field (igea's moves with it, bench/resize.md), so meshes whose full spectrum costs seconds
  //! keep it; at 10^6 faces the simplification brings `--features auto` from 83 s to about 35 s CPU.
  int adf_full_vertices = 150000;
  int adf_vertices = 50000;
  //! A maximum is a feature's peak when its value exceeds the area-weighted median by this many robust
  //! standard deviations (1.4826 × median absolute deviation) of the field over the surface.
  double significance = 3.0;
  //! Neighbouring basins whose pass (the highest min(g_a, g_b) over edges between them) stands this many
  //! robust standard deviations above the median belong to one feature; a pass that high lies inside a
  //! protrusion, while the pass between a feature and the surface around it lies at its foot.
  double merge_pass = 1.5;
  //! A connected region spanning more than this share of the model's extent along some axis (of those
  //! along which the model extends at least a quarter of its largest extent) is a part
  //! of the model (a head, a body), not a detail on it: height regions that large are dropped; inside
  //! ADF regions that large, the ADF at half the diffusion time is searched again, up to \ref adf_levels
  //! times (a cow's head gives way to its horns and ears).
  double max_extent = 0.5;
  int adf_levels = 4;  //!< ADF: diffusion times tried (adf_t, adf_t/2, …)
  int dilate = 0;  //!< grow the map by this many vertex rings afterwards
  //! Importance: a morphological closing of the map over this many vertex rings (each vertex the
  //! largest weight within k rings, then of that the smallest within k rings, never below its own): the
  //! thin low-importance gaps between important regions (igea's face: between the eyes, the nose, the
  //! lips, the curls) take their neighbours' weight and grow with them instead of being squeezed
  //! between them; wide unimportant regions (a cow's legs) keep theirs. 0: off (bench/resize.md, eighth
  //! session: 8 rings lower the detail ratio on every model measured, but igea's render keeps its lumps).
  int close_gaps = 0;
  ProgressFn progress;
  static const OptionTable<FeatureMapOptions>& table();
};

//! Share of the surface a map marks, and a warning when that makes feature-aware resizing pointless.
struct FeatureSummary {
  double marked_fraction = 0;  //!< area of the marked vertices' (f > ½) Voronoi cells over the total area
  int marked_vertices = 0;     //!< vertices with f > ½
  int regions = 0;             //!< connected regions of marked vertices
  //! Empty, or a message for the user when more than half or less than 0.5% of the surface is marked.
  std::string warning;
  std::string describe() const;  //!< "features: marked fraction 0.123, marked vertices 1234, regions 9"
};

//! The summary of weights \p f on \p mesh. \throw InvalidInput on a size mismatch.
FeatureSummary summarize_features(const Mesh& mesh, const Eigen::VectorXd& f);

struct FeatureMap {
  Eigen::VectorXd weights;  //!< #V weights f_i: in [0, 1] for Importance, else in {0, 1}
  //! #V values of the field the map was grown on (height, the ADF at adf_t, or the raw importance)
  Eigen::VectorXd field;
  //! The detector used (Importance, Height or Adf; for Auto, the one chosen)
  FeatureMapMethod method = FeatureMapMethod::None;
  FeatureSummary summary;
};

//! The feature map of \p mesh by options.method. The one definition of "auto" for every front end.
//! \throw InvalidInput for an empty mesh or bad options; SolverError if the ADF's eigenproblem fails.
FeatureMap feature_map(const Mesh& mesh, const FeatureMapOptions& options = {});

//! The continuous importance map (FeatureMapMethod::Importance; see the file comment). \param raw if
//! given, receives the raw value before the smoothstep and the diffusion. \throw InvalidInput.
Eigen::VectorXd importance_map(const Mesh& mesh, const FeatureMapOptions& options = {}, Eigen::VectorXd* raw = nullptr);

//! Height of each vertex over the smoothed base of FeatureMapOptions::smoothing_scale, along the
//! base's normal, in units of R = √(area / 4π). #V values.
Eigen::VectorXd height_over_base(const Mesh& mesh, double smoothing_scale = 0.1);

//! Watershed basins of the significant maxima of \p field (see the file comment): 1 for vertices whose
//! steepest ascent ends at a maximum exceeding median + significance · 1.4826 MAD, or at a maximum
//! whose basin is joined to such a basin through passes above median + merge_pass · 1.4826 MAD; else 0.
//! Maxima on the mesh boundary are ignored (a border's artefact, not a feature). Isolated vertices get 0.
//! merge_pass = +inf keeps every basin apart.
Eigen::VectorXd significant_basins(const Mesh& mesh, const Eigen::VectorXd& field, double significance,
                                   double merge_pass = std::numeric_limits<double>::infinity());

//! The ADF map (see FeatureMapOptions::max_extent): significant basins of the ADF at adf_t, and inside
//! regions too large to be features, of the ADF at adf_t/2, adf_t/4, … \param field if given, receives
//! the ADF at adf_t.
Eigen::VectorXd adf_features(const Mesh& mesh, const FeatureMapOptions& options, Eigen::VectorXd* field = nullptr);

//! Features from the height over a smoothed base: feature_map() with method Height.
Eigen::VectorXd features_from_height(const Mesh& mesh, const FeatureMapOptions& options = {});

//! Features from a height field (e.g. a texture PLY's "height"): |h_i| > threshold, dilated by \p dilate rings.
Eigen::VectorXd features_from_values(const Mesh& mesh, const Eigen::VectorXd& height, double threshold, int dilate);

//! Grow a 0/1 feature map by \p rings vertex rings.
Eigen::VectorXd dilate_features(const Mesh& mesh, const Eigen::VectorXd& f, int rings);
//! The largest weight within \p rings vertex rings (dilate_features), then the smallest within as many,
//! never below \p f: a morphological closing that fills gaps narrower than about 2 \p rings rings.
Eigen::VectorXd close_features(const Mesh& mesh, const Eigen::VectorXd& f, int rings);

}  // namespace geotex
