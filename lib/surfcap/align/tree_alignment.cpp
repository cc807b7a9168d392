#include "surfcap/align/tree_alignment.hpp"

#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <optional>

#include "surfcap/core/error.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/core/json_integer.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/mesh_repair.hpp"
#include "surfcap/core/parallel.hpp"
#include "surfcap/geometry/best_rotation.hpp"

namespace surfcap::align {

namespace {

using Clock = std::chrono::steady_clock;

core::Mesh read_reconstruction(const core::Capture& capture, const NodeFrame& node) {
  return core::read_reconstruction(capture.mesh_path(node.sequence, node.frame), node.frame);
}

std::vector<NodeFrame> node_frames(const core::Capture& capture, const similarity::FrameList& frames) {
  std::vector<NodeFrame> nodes;
  for (const auto& sequence : frames.sequences) {
    const int index = capture.sequence_index(sequence.name);
    if (index < 0)
      throw core::bad_input(capture.folder / "capture.json", "has no sequence '" + sequence.name +
                                                                  "' listed by similarity/histograms.json");
    for (int k = 0; k < sequence.count; ++k) nodes.push_back({index, sequence.first + k});
  }
  return nodes;
}

/// What the edges of the tree share: the set-up (read only) and per node the slots its own edge
/// writes (aligned positions, image features, record); an edge reads only nodes of lower depth.
struct TreeState {
  const core::Capture& capture;
  const std::vector<NodeFrame>& nodes;
  const AlignmentTree& tree;
  const RegisterOptions& options;
  const AlignmentTemplate& model;
  const MotionPredictor& predictor;
  Registration& registration;
  const TemplateAppearance* appearance = nullptr;
  bool use_features = false;
  std::vector<int> node_depth;
  std::vector<Eigen::MatrixXd> positions;
  std::vector<FrameFeatures> features;
  std::atomic<std::size_t> done{1};
  const core::ProgressCallback* progress = nullptr;

  FrameFeatures detect_features(const NodeFrame& node, const geometry::SurfaceQuery& reconstruction) const {
    return detect_frame_features(capture, node.sequence, node.frame, reconstruction, options.pairwise.feature);
  }

  /// The image features of `node` as an alternative parent (its own were released with its
  /// depth): detected once and shared by the edges that try it. A frame's features are the same
  /// whenever they are detected, so which ones are kept (the last 16) does not change the result.
  std::shared_ptr<const FrameFeatures> alternative_features(long node) {
    {
      const std::lock_guard<std::mutex> lock(alternatives_mutex);
      const auto found = alternatives.find(node);
      if (found != alternatives.end()) return found->second;
    }
    const NodeFrame source = nodes[static_cast<std::size_t>(node)];
    const core::Mesh mesh = read_reconstruction(capture, source);
    auto detected = std::make_shared<const FrameFeatures>(detect_features(source, geometry::SurfaceQuery(mesh.V, mesh.F)));
    const std::lock_guard<std::mutex> lock(alternatives_mutex);
    if (alternatives.size() >= 16) alternatives.erase(alternatives.begin());
    alternatives.emplace(node, detected);
    return detected;
  }
  std::mutex alternatives_mutex;
  std::map<long, std::shared_ptr<const FrameFeatures>> alternatives;
};

/// One edge of the tree: the child aligned from its tree parent, and from other parents when that
/// failed or when the edge enters the child's sequence from another (parent_recovery.hpp).
class EdgeAlignment {
 public:
  EdgeAlignment(TreeState& state, const AlignmentTree::Edge& edge)
      : state_(state),
        edge_(edge),
        start_(Clock::now()),
        child_(state.nodes[static_cast<std::size_t>(edge.child)]),
        target_(read_reconstruction(state.capture, child_)),
        query_(target_.V, target_.F),
        record_(state.registration.frames[static_cast<std::size_t>(edge.child)]) {
    if (state.use_features) state.features[static_cast<std::size_t>(edge.child)] = state.detect_features(child_, query_);
    if (state.appearance) child_images_ = read_grey_images(state.capture, child_.sequence, child_.frame);
  }

  void run() {
    KeptAttempt kept;
    kept.result = attempt(edge_.parent);
    kept.parent = edge_.parent;
    kept.verdict = kept.result ? verdict(*kept.result, edge_.parent) : Verdict::failed;
    const Eigen::MatrixXd* costs = state_.options.costs;
    const auto usable = [this](long other) { return usable_parent(other); };
    const auto attempt_from = [this](long from) { return attempt(from); };
    const auto verdict_from = [this](const PairwiseResult& r, long from) { return verdict(r, from); };
    if (!record_.failed_attempts.empty() && costs != nullptr)
      retry_parents(kept, candidate_parents(*costs, edge_.child, edge_.parent, state_.nodes, usable, false),
                    state_.options.recovery, attempt_from, verdict_from);
    if (kept.result && record_.failed_attempts.empty() && state_.options.recovery.entry_candidates > 0 &&
        costs != nullptr && state_.nodes[static_cast<std::size_t>(edge_.parent)].sequence != child_.sequence)
      try_entry_candidates(kept, candidate_parents(*costs, edge_.child, edge_.parent, state_.nodes, usable, true),
                           state_.options.recovery, state_.options.failure.max_uncovered / 4, attempt_from,
                           verdict_from, record_);
    if (!kept.result)
      throw core::bad_input(state_.capture.mesh_path(child_.sequence, child_.frame),
                            "alignment failed from every candidate parent: " + record_.failed_attempts.front().failure,
                            child_.frame);
    keep(std::move(kept));
  }

 private:
  /// The root's residual is that of the template on its own reconstruction (about 0): no reference.
  double parent_residual(long from) const {
    return from == state_.tree.root
               ? 0.0
               : state_.registration.frames[static_cast<std::size_t>(from)].alignment.mean_residual;
  }

  Verdict verdict(const PairwiseResult& result, long from) const {
    return align::verdict(result, parent_residual(from), state_.options.failure);
  }

  /// A frame another parent can be: aligned already (a lower depth) and not failed itself.
  bool usable_parent(long other) const {
    return other != edge_.child && state_.node_depth[static_cast<std::size_t>(other)] < edge_.depth &&
           !state_.registration.frames[static_cast<std::size_t>(other)].unrecovered;
  }

  /// The image features of parent and child; an alternative parent's were released with its depth
  /// and come from TreeState::alternative_features (held by `other`).
  FeaturePair feature_pair(long from, std::shared_ptr<const FrameFeatures>& other) const {
    FeaturePair pair;
    if (state_.use_features) {
      pair.parent = &state_.features[static_cast<std::size_t>(from)];
      if (from != edge_.parent) {
        other = state_.alternative_features(from);
        pair.parent = other.get();
      }
      pair.child = &state_.features[static_cast<std::size_t>(edge_.child)];
    }
    if (state_.appearance) {
      pair.appearance = state_.appearance;
      pair.child_images = &child_images_;
    }
    return pair;
  }

  /// One attempt from `from`; nullopt (and a record of why) if it throws, recorded if it fits badly.
  std::optional<PairwiseResult> attempt(long from) {
    std::shared_ptr<const FrameFeatures> other;
    const FeaturePair pair = feature_pair(from, other);
    try {
      const Eigen::MatrixXd& parent = state_.positions[static_cast<std::size_t>(from)];
      const long grand = state_.registration.frames[static_cast<std::size_t>(from)].parent;
      const Eigen::MatrixXd predicted = state_.predictor.predict(
          edge_.child, from, grand, parent, grand >= 0 ? state_.positions[static_cast<std::size_t>(grand)] : parent,
          state_.model, query_, state_.options.pairwise);
      PairwiseResult result = align_pair(state_.model, parent, query_, state_.options.pairwise,
                                         target_.has_colors() ? &target_.colors : nullptr, pair,
                                         predicted.rows() > 0 ? &predicted : nullptr);
      if (verdict(result, from) == Verdict::pass) return result;
      record_.failed_attempts.push_back({from, result.mean_residual, result.uncovered_fraction, result.stacked_fraction,
                                         failure_reason(result, parent_residual(from), state_.options.failure)});
      return result;  // kept only if no retry does better
    } catch (const core::Error& error) {
      record_.failed_attempts.push_back({from, -1.0, 0.0, 0.0, error.what()});
      return std::nullopt;
    }
  }

  /// Stores the kept attempt as the child's alignment and reports progress.
  void keep(KeptAttempt kept) {
    if (kept.parent != edge_.parent && record_.failed_attempts.empty())
      spdlog::info("{}:{}: aligned from node {} (a lower residual than from its tree parent)", record_.sequence,
                   record_.frame, kept.parent);
    else if (kept.parent != edge_.parent)
      spdlog::warn("{}:{}: alignment from its tree parent failed; aligned from node {} instead", record_.sequence,
                   record_.frame, kept.parent);
    record_.unrecovered = kept.verdict == Verdict::failed;
    PairwiseResult result = std::move(*kept.result);
    state_.positions[static_cast<std::size_t>(edge_.child)] = std::move(result.positions);
    result.positions.resize(0, 0);
    record_.parent = kept.parent;
    record_.depth = edge_.depth;
    record_.alignment = std::move(result);
    record_.seconds = std::chrono::duration<double>(Clock::now() - start_).count();
    record_.features = state_.features[static_cast<std::size_t>(edge_.child)].size();
    const std::size_t finished = ++state_.done;
    if (*state_.progress) (*state_.progress)(finished, state_.nodes.size());
  }

  TreeState& state_;
  const AlignmentTree::Edge& edge_;
  const Clock::time_point start_;
  const NodeFrame child_;
  const core::Mesh target_;
  const geometry::SurfaceQuery query_;
  std::vector<GreyImage> child_images_;
  FrameRecord& record_;
};

/// The root frame's appearance of the template, for the flow iterations (undistorted images only).
std::unique_ptr<TemplateAppearance> root_appearance(const core::Capture& capture, const NodeFrame& root,
                                                    const AlignmentTemplate& model, const RegisterOptions& options) {
  const bool root_has_images = !capture.sequences[static_cast<std::size_t>(root.sequence)].images.empty();
  if (!options.images || !options.pairwise.flow.weight || options.pairwise.flow.iterations <= 0 || !root_has_images)
    return nullptr;
  if (has_distortion(capture)) {
    spdlog::warn("cameras.json declares lens distortion: the appearance flow needs undistorted images, not used");
    return nullptr;
  }
  auto appearance = std::make_unique<TemplateAppearance>(model.mesh(), capture_cameras(capture),
                                                         read_grey_images(capture, root.sequence, root.frame),
                                                         model.mean_edge(), options.pairwise.flow);
  spdlog::info("root appearance covers {:.1f}% of the template", 100.0 * appearance->coverage());
  return appearance;
}

/// The records of every node, the root's filled in (the template on its own reconstruction).
void start_records(Registration& registration, const core::Capture& capture, const std::vector<NodeFrame>& nodes,
                   long root, const core::Mesh& template_mesh) {
  registration.frames.resize(nodes.size());
  for (std::size_t node = 0; node < nodes.size(); ++node) {
    auto& record = registration.frames[node];
    record.sequence = capture.sequences[static_cast<std::size_t>(nodes[node].sequence)].name;
    record.frame = nodes[node].frame;
    record.node = static_cast<long>(node);
  }
  auto& record = registration.frames[static_cast<std::size_t>(root)];
  const geometry::SurfaceQuery query(template_mesh.V, template_mesh.F);
  const Eigen::VectorXd distances = surface_distances(template_mesh.V, query);
  record.alignment.mean_residual = distances.mean();
  record.alignment.max_residual = distances.maxCoeff();
}

/// Depth by depth: the edges of one depth only read positions of the previous depths. Image
/// features of a node are released once the next depth (its children) is done.
void align_depths(TreeState& state, int threads) {
  std::map<int, std::vector<AlignmentTree::Edge>> by_depth;
  for (const auto& edge : state.tree.edges) {
    by_depth[edge.depth].push_back(edge);
    state.node_depth[static_cast<std::size_t>(edge.child)] = edge.depth;
  }
  for (const auto& level : by_depth) {
    const auto& edges = level.second;  // not a structured binding: clang 14 cannot capture those
    core::parallel_for(static_cast<long>(edges.size()), threads, [&](long i) {
      EdgeAlignment(state, edges[static_cast<std::size_t>(i)]).run();
    });
    for (const auto& edge : edges) state.features[static_cast<std::size_t>(edge.parent)] = FrameFeatures{};
  }
}

}  // namespace

AlignmentTree read_alignment_tree(const std::filesystem::path& database, long node_count) {
  const auto path = database / "similarity" / "tree.json";
  const core::Json document = core::read_json_document(path, "tree", 1);
  AlignmentTree tree;
  try {
    tree.root = core::checked_integer(document.at("root").at("node"), "the root node", path);
    tree.nodes = document.at("nodes").get<std::vector<std::string>>();
    for (const auto& entry : document.at("edges"))
      tree.edges.push_back({core::checked_integer(entry.at("parent"), "an edge's parent", path),
                            core::checked_integer(entry.at("child"), "an edge's child", path), entry.at("cost").get<double>(),
                            static_cast<int>(core::checked_integer(entry.at("depth"), "an edge's depth", path))});
  } catch (const core::Json::exception& error) {
    throw core::bad_input(path, std::string("malformed tree: ") + error.what());
  }
  if (static_cast<long>(tree.nodes.size()) != node_count)
    throw core::bad_input(path, "has " + std::to_string(tree.nodes.size()) + " nodes, the histograms list " +
                                    std::to_string(node_count) + " frames");
  if (static_cast<long>(tree.edges.size()) != node_count - 1)
    throw core::bad_input(path, "does not span its nodes (" + std::to_string(tree.edges.size()) + " edges for " +
                                    std::to_string(node_count) + " nodes)");
  std::vector<char> reached(static_cast<std::size_t>(node_count), 0);
  if (tree.root < 0 || tree.root >= node_count) throw core::bad_input(path, "root node out of range");
  reached[static_cast<std::size_t>(tree.root)] = 1;
  for (const auto& edge : tree.edges) {
    if (edge.parent < 0 || edge.parent >= node_count || edge.child < 0 || edge.child >= node_count)
      throw core::bad_input(path, "edge node out of range");
    if (!reached[static_cast<std::size_t>(edge.parent)] || reached[static_cast<std::size_t>(edge.child)])
      throw core::bad_input(path, "edges are not breadth first from the root (edge " + std::to_string(edge.parent) +
                                      " → " + std::to_string(edge.child) + ")");
    reached[static_cast<std::size_t>(edge.child)] = 1;
  }
  return tree;
}

Eigen::MatrixXd pose_volume(const AlignmentTemplate& model, const Eigen::MatrixXd& surface) {
  const VolumeDeformer& deformer = model.deformer();
  const long n = deformer.surface_vertex_count();
  if (surface.rows() != n) throw core::internal_error("pose_volume: surface size");
  const Eigen::MatrixXd rest = deformer.rest().topRows(n);
  const Eigen::RowVector3d rest_centre = rest.colwise().mean(), centre = surface.colwise().mean();
  const Eigen::Matrix3d covariance = (rest.rowwise() - rest_centre).transpose() * (surface.rowwise() - centre);
  const Eigen::Matrix3d rotation = geometry::best_rotation(covariance).transpose();
  const Eigen::MatrixXd start =
      ((deformer.rest().rowwise() - rest_centre) * rotation.transpose()).rowwise() + centre;
  const Eigen::VectorXd weights = Eigen::VectorXd::Constant(n, 100.0);
  Eigen::MatrixXd positions = deformer.deform(deformer.factor(weights), start, surface, weights, 8);
  positions.topRows(n) = surface;
  return positions;
}

Registration register_capture(const core::Capture& capture, const similarity::FrameList& frames,
                              const AlignmentTree& tree, const RegisterOptions& options,
                              const core::ProgressCallback& progress) {
  options.validate();
  const std::vector<NodeFrame> nodes = node_frames(capture, frames);
  const std::size_t node_count = nodes.size();
  Registration registration;
  const NodeFrame root = nodes[static_cast<std::size_t>(tree.root)];
  const auto template_start = Clock::now();
  const core::Mesh template_mesh = read_reconstruction(capture, root);
  const AlignmentTemplate model(template_mesh, options.pairwise, options.deformer);
  registration.seconds_template = std::chrono::duration<double>(Clock::now() - template_start).count();
  registration.deformer_model = model.deformer().model();
  registration.volume_vertices = model.deformer().vertex_count();
  registration.elements = model.deformer().element_count();
  spdlog::info("template {}:{} — {} vertices, {} model with {} vertices and {} elements",
               capture.sequences[static_cast<std::size_t>(root.sequence)].name, root.frame,
               template_mesh.vertex_count(), registration.deformer_model, registration.volume_vertices,
               registration.elements);
  start_records(registration, capture, nodes, tree.root, template_mesh);

  const MotionPredictor predictor(nodes, options.costs, options.motion);
  TreeState state{capture, nodes, tree, options, model, predictor, registration};
  state.node_depth.assign(node_count, 0);
  state.positions.resize(node_count);
  state.positions[static_cast<std::size_t>(tree.root)] = model.deformer().rest();
  state.features.resize(node_count);
  state.use_features = options.images && options.pairwise.feature.weight.has_value();
  if (state.use_features) {
    auto& features = state.features[static_cast<std::size_t>(tree.root)];
    features = state.detect_features(root, geometry::SurfaceQuery(template_mesh.V, template_mesh.F));
    registration.frames[static_cast<std::size_t>(tree.root)].features = features.size();
  }
  const std::unique_ptr<TemplateAppearance> appearance = root_appearance(capture, root, model, options);
  if (appearance) registration.appearance_coverage = appearance->coverage();
  state.appearance = appearance.get();
  state.progress = &progress;
  if (progress) progress(state.done, node_count);
  align_depths(state, options.threads);

  registration.world_positions.resize(node_count);
  for (std::size_t node = 0; node < node_count; ++node)
    registration.world_positions[node] = state.positions[node].topRows(template_mesh.vertex_count());
  registration.database =
      aligned_database(capture, frames, template_mesh, root.sequence, root.frame, registration.world_positions);
  return registration;
}

}  // namespace surfcap::align
