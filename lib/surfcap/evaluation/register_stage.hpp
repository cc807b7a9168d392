#pragma once
// The alignment stage of surfcap-align (`register`, the end of `run`; docs/align.md): the
// registration along similarity/tree.json, the database written, the report with its previews,
// and — on a synthetic capture — the error against the ground truth.

#include <filesystem>
#include <string>

#include "surfcap/align/tree_alignment.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/core/option_table.hpp"

namespace surfcap::evaluation {

/// What the stage reports besides the alignment itself.
struct ReportOptions {
  bool evaluation = true;     ///< compare with CAPTURE/ground_truth/ when the capture has it
  bool truth_arrays = false;  ///< with ground truth: the per-vertex error arrays (truth_outputs.hpp)
  int preview_frames = 4;     ///< frames in report/alignment.png and truth_error.png (0: none)
  double preview_scale_mm = 10;  ///< residual shown as red

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    t.field("evaluation", self.evaluation, "Compare with the capture's ground_truth/ when it has one");
    t.field("truth_arrays", self.truth_arrays,
            "With ground truth: also write report/truth_errors.npy and report/truth_observed.npy (per vertex)");
    t.field("preview_frames", self.preview_frames, "Frames in report/alignment.png (0: none)", core::Range::closed(0, 8));
    t.field("preview_scale_mm", self.preview_scale_mm, "Residual mapped to red in the preview (mm)",
            core::Range::above(0));
  }
};

/// Which registration job (docs/pipelines.md "Registration jobs"): the whole registration, the
/// trunk, shard `shard` of `shards` (after the trunk), or the merge of the trunk and `shards`
/// shards into what the whole registration writes.
struct RegisterJob {
  enum class Kind { whole, trunk, shard, merge } kind = Kind::whole;
  int shard = 0;  ///< from 1
  int shards = 0;
};

struct RegisterStageOptions {
  align::RegisterOptions alignment;
  RegisterJob job;
  ReportOptions report;
  std::string capture;            ///< capture folder (empty: the one similarity/histograms.json names)
  std::string stage = "align.register";  ///< the report's stage name
  core::Json options_json;        ///< the command's options, for the report
  core::Json provenance_json;     ///< … without those that cannot change an output, for database.json
};

/// <out>/similarity/ → <out>/database.json, template.ply, sequences/, report/alignment.{json,png}
/// (and truth_error.png, truth arrays with ground truth); the trunk and shard jobs write their
/// parts (register/, registration_parts.hpp) and report/register-trunk.json or
/// register-shard-<k>-of-<K>.json instead, and the merge what the whole registration writes.
void run_register_stage(const std::filesystem::path& out, const RegisterStageOptions& options);

}  // namespace surfcap::evaluation
