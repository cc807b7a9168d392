#pragma once
// Alignment of every captured frame along the shape similarity tree (casas2011 §3.2): the
// template (the root frame's reconstruction) is deformed parent → child from the root outwards;
// independent branches run in parallel, level by level, so results do not depend on the thread
// count. The result is the aligned database (DESIGN §3.2) plus per-frame records for the report.

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "surfcap/align/pairwise_alignment.hpp"
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

/// When an aligned child has failed (FailureOptions) and what is tried then (RecoveryOptions).
/// A child whose alignment throws (solver failure), ends with a mean residual above
/// `failure_residual_mm`, leaves more than `max_uncovered` of its reconstruction's vertices
/// uncovered (PairwiseResult::uncovered_fraction) or more than `max_stacked` of the template's in
/// stacked layers (PairwiseResult::stacked_fraction: a hand pushed up its forearm) has failed; one
/// whose mean residual grew beyond `residual_growth` × its parent's (not from the root) is retried
/// too.
struct FailureOptions {
  double failure_residual_mm = 4;
  double max_uncovered = 0.01;
  double max_stacked = 0.005;
  std::optional<double> residual_growth = 1.3;

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    using core::Range;
    t.field("failure_residual_mm", self.failure_residual_mm,
            "Mean residual above which a frame is re-aligned from its next most similar aligned frame", Range::above(0));
    t.field("max_uncovered", self.max_uncovered,
            "Fraction of a reconstruction left uncovered by the aligned template above which a frame failed",
            Range::closed(0, 1));
    t.field("max_stacked", self.max_stacked,
            "Fraction of the template's vertices in stacked layers above which a frame failed", Range::above_to(0, 1));
    t.field("residual_growth", self.residual_growth,
            "A frame whose mean residual exceeds this many times its parent's is retried", Range::above(0));
  }
};

/// A failed child is aligned again from the next most similar frames already aligned (a lower
/// depth, by RegisterOptions::costs), up to `retries` times; of the attempts that did not fail the
/// lowest mean residual is kept, and if all failed the tree parent's. An edge whose parent is in
/// another sequence than its child is also aligned from the most similar already aligned frame of
/// up to `entry_candidates` other sequences; the attempt with the lowest mean residual is kept.
struct RecoveryOptions {
  int retries = 2;
  int entry_candidates = 2;

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    t.field("retries", self.retries, "Alternative parents tried for a failed frame", core::Range::closed(0, 10));
    t.field("entry_candidates", self.entry_candidates,
            "An edge from another sequence is also aligned from the most similar frame of up to N other sequences",
            core::Range::closed(0, 10));
  }
};

/// Motion prediction along the tree: when a child's parent and grandparent are its next two frames
/// of the same sequence (frames f+1, f+2 → f, or f−1, f−2 → f), the child is predicted at parent +
/// `motion_prediction` × (parent − grandparent), per vertex, and the coarsest patch levels also try
/// that start (PredictionOptions::levels). A limb that moves farther in a frame than the patch gate
/// (a running stride) is matched where it went. With `twin_prediction`, also when the child is not
/// the frame after parent and grandparent but costs (by RegisterOptions::costs) at most this
/// fraction of its cost to the parent from that frame: a twin a cycle apart of a cyclic motion.
struct MotionPredictionOptions {
  std::optional<double> motion_prediction = 1.0;
  std::optional<double> twin_prediction = 0.25;

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    t.field("motion_prediction", self.motion_prediction,
            "Predict a child from its next two aligned frames: parent + this x (parent - grandparent)",
            core::Range::above_to(0, 2));
    t.field("twin_prediction", self.twin_prediction,
            "Also predict a child whose similarity cost to its parent's next frame is at most this fraction of its "
            "cost to the parent (a cycle's twin)",
            core::Range::above_to(0, 1));
  }
};

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

/// Root motion of an aligned frame relative to the template at rest: centroid (x, y, z) and the
/// heading of the best rotation about +y taking the centred template onto the centred frame.
core::RootMotion root_motion(const Eigen::MatrixXd& template_rest, const Eigen::MatrixXd& world);

/// All deformer vertices (surface + interior) for a posed template surface (n×3): the rest volume
/// rigidly fitted to it, then deformed onto it (rotation updates), surface rows set exactly.
Eigen::MatrixXd pose_volume(const AlignmentTemplate& model, const Eigen::MatrixXd& surface);

/// Aligns all frames of `capture` listed in `frames` along `tree`. Reconstructions are read (and
/// checked) as needed; errors name the file and frame.
Registration register_capture(const core::Capture& capture, const similarity::FrameList& frames,
                              const AlignmentTree& tree, const RegisterOptions& options,
                              const core::ProgressCallback& progress = {});

}  // namespace surfcap::align
