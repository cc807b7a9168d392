#pragma once
// Alignment of every captured frame along the shape similarity tree (casas2011 §3.2): the
// template (the root frame's reconstruction) is deformed parent → child from the root outwards;
// the edges of one depth run in parallel, each reading only its parent, so results do not depend
// on the thread count. Around each edge: motion prediction (motion_prediction.hpp) and parent
// recovery (parent_recovery.hpp). The result is the aligned database (aligned_database.hpp) plus
// per-frame records for the report.

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "surfcap/align/aligned_database.hpp"
#include "surfcap/align/motion_prediction.hpp"
#include "surfcap/align/pairwise_alignment.hpp"
#include "surfcap/align/parent_recovery.hpp"
#include "surfcap/core/capture.hpp"
#include "surfcap/core/database.hpp"
#include "surfcap/core/progress.hpp"
#include "surfcap/similarity/similarity_files.hpp"

namespace surfcap::align {

/// similarity/tree.json as the aligner needs it.
struct AlignmentTree {
  long root = 0;
  std::vector<std::string> nodes;  ///< "walk:12" per node (the FrameList order)
  struct Edge {
    long parent = 0, child = 0;
    double cost = 0;
    int depth = 0;  ///< of the child
  };
  std::vector<Edge> edges;  ///< breadth first: every parent precedes its children
};

/// Reads <database>/similarity/tree.json (surfcap.tree/1), checking that it spans `node_count`
/// nodes with parents before children; bad_input names the file.
AlignmentTree read_alignment_tree(const std::filesystem::path& database, long node_count);

/// Every option of the alignment that can change its output (its table is the provenance written
/// into database.json).
struct RegisterOptions {
  PairwiseOptions pairwise;
  DeformerOptions deformer;
  bool images = true;  ///< use camera-image features and appearance flow when the capture has images
  FailureOptions failure;
  RecoveryOptions recovery;
  MotionPredictionOptions motion;
  int threads = 0;  ///< ≤ 0: all hardware threads (no effect on the output; not in the table)
  const Eigen::MatrixXd* costs = nullptr;  ///< N×N similarity costs (similarity/matrix.npy); null: no retries

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    t.inline_group(self.pairwise);
    t.inline_group(self.deformer);
    t.field("images", self.images, "Use the capture's camera images (SIFT features, appearance flow)");
    t.inline_group(self.failure);
    t.inline_group(self.recovery);
    t.inline_group(self.motion);
  }
  void validate() const { core::validate_options(*this); }
  core::Json to_json() const { return core::options_to_json(*this); }
};

/// One aligned frame, as the report lists it.
struct FrameRecord {
  std::string sequence;
  int frame = 0;        ///< frame number
  long node = 0;
  long parent = -1;     ///< −1 for the root
  int depth = 0;
  PairwiseResult alignment;  ///< positions cleared after use; residuals, counts, timings
  double seconds = 0;
  long features = 0;    ///< image features of this frame on its reconstruction (0: no images)
  struct Attempt {
    long parent = -1;
    double mean_residual = 0;  ///< < 0: the attempt threw
    double uncovered_fraction = 0;
    double stacked_fraction = 0;
    std::string failure;       ///< why it was not good enough
  };
  std::vector<Attempt> failed_attempts;  ///< every attempt that failed (`parent` is the one kept)
  bool unrecovered = false;              ///< even the kept attempt is above the failure threshold
  int entry_attempts = 0;                ///< alternative parents tried for an edge entering the sequence
};

struct Registration {
  core::AlignedDatabase database;
  std::vector<FrameRecord> frames;                 ///< per node
  std::vector<Eigen::MatrixXd> world_positions;    ///< per node: template surface vertices (world, metres)
  std::string deformer_model;
  long volume_vertices = 0, elements = 0;
  double seconds_template = 0;
  double appearance_coverage = 0;  ///< template faces seen by a root camera (0: no appearance flow)
};

/// All deformer vertices (surface + interior) for a posed template surface (n×3): the rest volume
/// rigidly fitted to it, then deformed onto it (rotation updates), surface rows set exactly.
Eigen::MatrixXd pose_volume(const AlignmentTemplate& model, const Eigen::MatrixXd& surface);

/// Aligns all frames of `capture` listed in `frames` along `tree`. Reconstructions are read (and
/// checked) as needed; errors name the file and frame.
Registration register_capture(const core::Capture& capture, const similarity::FrameList& frames,
                              const AlignmentTree& tree, const RegisterOptions& options,
                              const core::ProgressCallback& progress = {});

}  // namespace surfcap::align
