#pragma once
// Alignment error against a synthetic capture's ground truth (docs/synth.md). The template is the
// root frame's reconstruction, so each template vertex v has a true location on the true surface:
// the root reconstruction's correspondence (true face + barycentric). In every frame f the aligned
// v should lie at Σ_k b_vk · X_f[F[face_v, k]], X_f the true world positions of frame f.

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "surfcap/align/tree_alignment.hpp"
#include "surfcap/core/capture.hpp"
#include "surfcap/core/json_document.hpp"

namespace surfcap::align {

struct FrameTruthError {
  double rms = 0;  ///< metres, over the template vertices
  double max = 0;
};

struct TruthEvaluation {
  double height = 0;                    ///< character height: the true root frame's y extent (m)
  double rms = 0;                       ///< over all frames and vertices (m)
  double worst_frame_rms = 0;
  long worst_node = 0;
  std::vector<FrameTruthError> frames;  ///< per node
  std::map<int, double> rms_by_depth;   ///< tree depth → RMS over its frames and vertices
  core::Json to_json(const Registration& registration) const;  ///< figures in metres and % of height
};

/// <capture>/ground_truth/truth.json if the capture has ground truth.
std::optional<std::filesystem::path> ground_truth_file(const core::Capture& capture);

/// Compares every aligned frame with the truth; bad_input if the ground truth is incomplete.
TruthEvaluation evaluate_against_truth(const core::Capture& capture, const Registration& registration);

}  // namespace surfcap::align
