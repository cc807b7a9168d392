#pragma once
// Choosing the template frame (the root of the similarity tree): its reconstruction becomes the
// template and its volume is tetrahedralised once, so where body parts touch in that frame (arms
// against the torso in a crouch) the tet volume glues them for every alignment. The automatic root
// is therefore the frame of minimal weighted tree depth among the frames whose parts are most
// separated: the mean number of connected components of horizontal cross-sections (two legs, two
// arms beside the torso) is within `tolerance` of the capture's largest.

#include <vector>

#include "surfcap/core/capture.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/core/mesh.hpp"
#include "surfcap/similarity/similarity_files.hpp"

namespace surfcap::align {

/// Mean over `slices` horizontal planes (evenly between 3 % and 97 % of the height) of the number
/// of connected components of the surface's cross-section.
double part_separation(const core::Mesh& mesh, int slices = 40);

struct RootCandidates {
  std::vector<double> separation;  ///< per node (FrameList order)
  std::vector<char> candidates;    ///< per node: 1 if within `tolerance` of the largest separation
};

/// Part separation of every listed frame's reconstruction (in parallel; errors name file and frame).
RootCandidates root_candidates(const core::Capture& capture, const similarity::FrameList& frames, double tolerance,
                               int threads);

/// For reports: {"separation": per node, "candidates": count, "best": largest separation}.
core::Json root_choice_json(const RootCandidates& choice);

}  // namespace surfcap::align
