#pragma once
// Automatic keep-out for texture synthesis (issue 27): where a person would not cover a target with
// texture by default — along its sharp creases and on parts smaller than the texture's features
// — as a weight in [0, 1] that multiplies the user's growth weight (SynthesisGuides::weight). Each reason is
// one continuous map, so a region is kept out by degree, not by a yes/no test, and each can be switched off
// (SynthesisOptions::keep_out_*). A face's eyes, nostrils and mouth are kept out by their creases on the shared
// characters (bench/synthesis.md); eye sockets with no crease around them by the closed-pit rule (pit_weight()),
// eyeballs with none by the dome rule (dome_weight()).

#include <Eigen/Core>

#include "geotex/core/mesh.h"

namespace geotex::detail {

struct KeepOut {
  Eigen::VectorXd weight;   //!< #V in [0, 1]: creases × thin × pits × domes (1: free)
  Eigen::VectorXd creases;  //!< #V: 0 near a crease (a quarter of `span`), rising to 1 at `span` from it
  Eigen::VectorXd area;     //!< #V: a third of the area of the faces at each vertex (for shares)
  Eigen::VectorXd thin;     //!< #V: 0 where the surface within span is under a quarter of a disk's area, 1 from half
  //! #V: 0 in closed pits smaller than the span (the ring round a vertex above it on every side by at least
  //! pit_depth × the ring's radius; rings of span / 4, / 2 and 1) and a quarter of the span round them, 1 at the span
  Eigen::VectorXd pits;
  //! #V: 0 on domes smaller than the span (an eyeball: an island closed round by a ridge or a valley, convex,
  //! standing above the surface round it and alone on it; dome_weight()) and a quarter of the span round them, 1 at the span
  Eigen::VectorXd domes;
};

//! \param span the texture's scale on the target: the smaller of its feature length (largest displacement)
//! and its patch radius. \param crease_angle_deg dihedral angle from which an edge is a crease (0: none).
//! \param pit_depth a closed pit's depth over its radius from which it is kept out (0: none).
//! \param dome_ridge the mean curvature × span of the ridge that closes a dome round (0: no dome keep-out).
KeepOut keep_out(const Mesh& target, double span, double crease_angle_deg, bool thin, double pit_depth = 0,
                 double dome_ridge = 0);

}  // namespace geotex::detail
