#pragma once
// Alignment of every captured frame along the shape similarity tree (casas2011 §3.2): the
// template (the root frame's reconstruction) is deformed parent → child from the root outwards;
// independent branches run in parallel, level by level, so results do not depend on the thread
// count. The result is the aligned database (DESIGN §3.2) plus per-frame records for the report.

#include <Eigen/Core>
#include <filesystem>
#include <functional>
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

struct RegisterOptions {
  PairwiseOptions pairwise;
  DeformerOptions deformer;
  int threads = 0;  ///< ≤ 0: all hardware threads
  bool images = true;  ///< use camera-image features when the capture has images
  /// Recoverable failures (issue 10): a child whose alignment throws (solver failure), ends with a
  /// mean residual above `failure_residual` (m), leaves more than `max_uncovered` of its
  /// reconstruction's vertices uncovered (PairwiseResult::uncovered_fraction) or stacks more than
  /// `max_stacked` (below) has failed; one whose residual grew beyond `residual_growth` × its
  /// parent's is retried too. It is aligned again from the next most similar frames already aligned
  /// (a lower depth, by `costs`), up to `retries` times; of the attempts that did not fail the lowest
  /// mean residual is kept, and if all failed the tree parent's.
  double failure_residual = 0.004;
  double max_uncovered = 0.01;  ///< or more than this fraction of the reconstruction is not covered (1: off)
  /// … or more than this fraction of the template's vertices lie in stacked layers
  /// (PairwiseResult::stacked_fraction: a hand pushed up its forearm; 1: off) …
  double max_stacked = 0.005;
  /// … or its mean residual is more than this many times its parent's (an edge that fits clearly
  /// worse than the one before it; not from the root; ≤ 0: off).
  double residual_growth = 1.3;
  int retries = 2;
  const Eigen::MatrixXd* costs = nullptr;  ///< N×N similarity costs (similarity/matrix.npy); null: no retries
  /// Motion prediction along the tree: when a child's parent and grandparent are its next two
  /// frames of the same sequence (frames f+1, f+2 → f, or f−1, f−2 → f), the child is predicted at
  /// parent + `motion_prediction` × (parent − grandparent), per vertex, and the coarsest patch
  /// levels also try that start (PairwiseOptions::prediction_levels; ≤ 0: off). A limb that moves
  /// farther in a frame than the patch gate (a running stride) is matched where it went.
  double motion_prediction = 1.0;
  /// … and also when the child is not the frame after parent and grandparent but costs (by `costs`)
  /// at most this fraction of its cost to the parent from that frame: a twin a cycle apart of a
  /// cyclic motion (0: next frames only).
  double twin_prediction = 0.25;
  /// An edge whose parent is in another sequence than its child is also aligned from the most
  /// similar already aligned frame of up to this many other sequences (by `costs`); the attempt
  /// with the lowest mean residual is kept (0: the tree parent only).
  int entry_candidates = 2;
  /// Diagnostics: when set, every child is aligned from the template surface this returns for its
  /// parent node (e.g. the ground truth) instead of from the aligned parent — each edge's own error.
  std::function<Eigen::MatrixXd(long node)> parent_surface;
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
