#pragma once
// Leave-out evaluation: learn from a subset of frames, then for held-out frames
// constrain only some regions (hands, feet, head) to their true positions and reconstruct the
// rest with plain Laplacian editing, the global learnt basis and the part-based basis.
#include <string>
#include <vector>

#include "surfcap/core/database.hpp"
#include "surfcap/learn/part_editor.hpp"
#include "surfcap/learn/part_model.hpp"

namespace surfcap::learn {

struct LeaveOutOptions {
  int stride = 4;          ///< learn from every stride-th frame of every sequence
  int max_evaluated = 0;   ///< held-out frames evaluated (evenly spaced); 0: all
  std::vector<std::string> regions = {"head", "hand_l", "hand_r", "foot_l", "foot_r"};
  LearnOptions learn;
  EditorOptions editor = {.keep_detail = false};  ///< the rest pose is only the start
  void validate() const;
};

struct MethodError {
  std::string method;        ///< "laplacian", "global", "parts"
  double mean_error = 0;     ///< metres, over every vertex of every evaluated frame
  double max_error = 0;      ///< metres
  double seconds_per_edit = 0;
  long basis_size = 0;       ///< Σ l_j
};

struct LeaveOutResult {
  int training_frames = 0;
  int evaluated_frames = 0;
  long constrained_vertices = 0;
  std::vector<MethodError> methods;  ///< laplacian, global, parts
  const MethodError& method(const std::string& name) const;
};

/// Runs the evaluation; the edits start from the template (rest pose).
LeaveOutResult leave_out_evaluation(const core::AlignedDatabase& database, const PartSet& parts,
                                    const LeaveOutOptions& options);

}  // namespace surfcap::learn
