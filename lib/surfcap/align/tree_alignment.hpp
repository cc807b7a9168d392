#pragma once
// Alignment of every captured frame along the shape similarity tree (casas2011 §3.2): the
// template (the root frame's reconstruction) is deformed parent → child from the root outwards,
// the trunk of the tree first, then its units (tree_partition.hpp); within each, the edges of one
// depth run in parallel, each reading only aligned frames, so results depend neither on the thread
// count nor on how the units are spread over jobs. Around each edge: motion prediction
// (motion_prediction.hpp) and parent recovery (parent_recovery.hpp), whose candidate parents are
// the frames of the child's own unit and the trunk. The result is the aligned database
// (aligned_database.hpp) plus per-frame records for the report.

#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "surfcap/align/aligned_database.hpp"
#include "surfcap/align/motion_prediction.hpp"
#include "surfcap/align/pairwise_alignment.hpp"
#include "surfcap/align/parent_recovery.hpp"
#include "surfcap/align/tree_partition.hpp"
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
  core::AlignedDatabase database;  ///< empty in a job that aligns part of the tree
  std::vector<FrameRecord> frames;                 ///< per node
  std::vector<Eigen::MatrixXd> world_positions;    ///< per node: template surface vertices (world, metres)
  std::string deformer_model;
  long volume_vertices = 0, elements = 0;
  /// Template vertices no root camera sees, and the tets under them softened (VolumeDeformer);
  /// the tets cut because they join parts of the template far apart along its surface.
  long template_unseen_vertices = 0, softened_elements = 0, cut_elements = 0;
  double seconds_template = 0;
  double appearance_coverage = 0;  ///< template faces seen by a root camera (0: no appearance flow)
  /// The first this many template vertices are the root reconstruction's, the rest close its holes
  /// (template_closing.hpp).
  long template_observed_vertices = 0;
  /// The root reconstruction's vertices not in the template (its loose pieces; TemplateSurface).
  std::vector<long> template_dropped_vertices;
  /// The template vertices where cut tets joined parts far apart along its surface (VolumeDeformer).
  std::vector<long> template_cut_vertices;
};

/// All deformer vertices (surface + interior) for a posed template surface (n×3): the rest volume
/// rigidly fitted to it, then deformed onto it (rotation updates), surface rows set exactly.
Eigen::MatrixXd pose_volume(const AlignmentTemplate& model, const Eigen::MatrixXd& surface);

/// What a registration job hands on (registration_parts.hpp writes it): the nodes it aligned
/// (ascending), their records (positions cleared) and their deformer vertices (all, surface first).
struct RegistrationPart {
  std::vector<long> nodes;
  std::vector<FrameRecord> records;
  std::vector<Eigen::MatrixXd> positions;
};

/// The alignment of one capture along its tree, in the jobs' steps: the trunk, then units (all, or
/// a job's share once the trunk's part is loaded). The template, the root's appearance and the
/// image features are computed by each instance from the capture; they depend on nothing else.
class TreeRegistration {
 public:
  /// `options` (and its costs), `capture`, `frames` and `tree` must outlive this object.
  TreeRegistration(const core::Capture& capture, const similarity::FrameList& frames, const AlignmentTree& tree,
                   const RegisterOptions& options, const core::ProgressCallback& progress = {});
  ~TreeRegistration();
  TreeRegistration(const TreeRegistration&) = delete;
  TreeRegistration& operator=(const TreeRegistration&) = delete;

  const TreePartition& partition() const;
  /// The template's figures (deformer, volume size, set-up time, appearance coverage); no frames.
  const Registration& summary() const;

  void align_trunk();
  /// Takes another job's aligned nodes (the trunk's part before align_units in a shard job).
  void load(const RegistrationPart& part);
  /// Aligns the given units (indices into partition()); the trunk must be aligned or loaded.
  void align_units(const std::vector<long>& units);
  /// The records and positions of `nodes` (all aligned).
  RegistrationPart part(const std::vector<long>& nodes) const;
  /// Every node aligned: the registration with its database.
  Registration finish() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The nodes of the trunk, or of the given units, ascending.
std::vector<long> partition_nodes(const TreePartition& partition, const std::vector<long>& units, bool trunk);

/// The registration of the whole tree from parts that hold every node once; `summary` gives the
/// template's figures. Reads the root's reconstruction (the template mesh).
Registration assemble_registration(const core::Capture& capture, const similarity::FrameList& frames,
                                   const AlignmentTree& tree, const std::vector<const RegistrationPart*>& parts,
                                   const Registration& summary);

/// Aligns all frames of `capture` listed in `frames` along `tree` (trunk, then every unit).
/// Reconstructions are read (and checked) as needed; errors name the file and frame.
Registration register_capture(const core::Capture& capture, const similarity::FrameList& frames,
                              const AlignmentTree& tree, const RegisterOptions& options,
                              const core::ProgressCallback& progress = {});

}  // namespace surfcap::align
