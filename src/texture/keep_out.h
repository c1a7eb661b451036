#pragma once
// Automatic keep-out for texture synthesis (issue 27): where a person would not cover a target with
// texture by default — along its sharp creases and on parts smaller than the texture's features
// — as a weight in [0, 1] that multiplies the user's growth weight (SynthesisGuides::weight). Each reason is
// one continuous map, so a region is kept out by degree, not by a yes/no test, and each can be switched off
// (SynthesisOptions::keep_out_*). A face's eyes, nostrils and mouth are kept out by their creases on the shared
// characters (bench/synthesis.md); eyes with no crease around them are not found.

#include <Eigen/Core>

#include "geotex/core/mesh.h"

namespace geotex::detail {

struct KeepOut {
  Eigen::VectorXd weight;   //!< #V in [0, 1]: the product of the two below (1: free)
  Eigen::VectorXd creases;  //!< #V: 0 near a crease (a quarter of `span`), rising to 1 at `span` from it
  Eigen::VectorXd area;     //!< #V: a third of the area of the faces at each vertex (for shares)
  Eigen::VectorXd thin;     //!< #V: 0 where the surface within span is under a quarter of a disk's area, 1 from half
};

//! \param span the texture's scale on the target: the smaller of its feature length (largest displacement)
//! and its patch radius. \param crease_angle_deg dihedral angle from which an edge is a crease (0: none).
KeepOut keep_out(const Mesh& target, double span, double crease_angle_deg, bool thin);

}  // namespace geotex::detail
