#include "surfcap/align/tree_alignment.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <numeric>
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

/// An entry parent replaces the kept one when it leaves more of the reconstruction covered by over
/// the uncovered limit divided by this (or, within that margin, a lower mean residual): a tenth
/// of the limit is above the noise of the uncovered measure and below what a wrong entry leaves.
constexpr double kEntryMarginDivisor = 10;

/// A frame's reconstruction: small holes filled, large ones (a floor cut, an unseen region) left
/// open; the correspondence sources use only its observed part (observed_surface.hpp).
core::Mesh read_reconstruction(const core::Capture& capture, const NodeFrame& node) {
  core::RepairLimits limits;
  limits.keep_large_holes_open = true;
  return core::read_reconstruction(capture.mesh_path(node.sequence, node.frame), node.frame, limits);
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
/// writes (aligned positions, image features, record); an edge reads only aligned nodes (of its
/// unit at a lower depth, or of the trunk).
struct TreeState {
  const core::Capture& capture;
  const std::vector<NodeFrame>& nodes;
  const AlignmentTree& tree;
  const TreePartition& partition;
  const RegisterOptions& options;
  const AlignmentTemplate& model;
  const MotionPredictor& predictor;
  Registration& registration;
  const TemplateAppearance* appearance = nullptr;
  const std::vector<render::Camera> cameras;  ///< the capture's calibration (empty: none)
  bool use_features = false;
  std::vector<int> node_depth;
  std::vector<Eigen::MatrixXd> positions;
  std::vector<char> aligned;         ///< per node: positions and record are final
  std::vector<FrameFeatures> features;
  std::vector<char> features_ready;  ///< per node: features holds its detection
  std::atomic<std::size_t> done{0};
  const core::ProgressCallback* progress = nullptr;

  TreeState(const core::Capture& c, const std::vector<NodeFrame>& n, const AlignmentTree& t, const TreePartition& p,
            const RegisterOptions& o, const AlignmentTemplate& m, const MotionPredictor& predict, Registration& r)
      : capture(c), nodes(n), tree(t), partition(p), options(o), model(m), predictor(predict), registration(r),
        cameras(capture_cameras(c)), node_depth(n.size(), 0), positions(n.size()), aligned(n.size(), 0), features(n.size()),
        features_ready(n.size(), 0) {
    for (const auto& edge : t.edges) node_depth[static_cast<std::size_t>(edge.child)] = edge.depth;
  }

  FrameFeatures detect_features(const NodeFrame& node, const geometry::SurfaceQuery& reconstruction) const {
    return detect_frame_features(capture, node.sequence, node.frame, reconstruction, options.pairwise.feature);
  }

  /// The image features of `node` as an alternative parent (its own were released with its
  /// depth): detected once and shared by the edges that try it. A frame's features are the same
  /// whenever they are detected, so which ones are kept (at most 16; the lowest node leaves
  /// first) does not change the result.
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
    if (state.use_features) {
      state.features[static_cast<std::size_t>(edge.child)] = state.detect_features(child_, query_);
      state.features_ready[static_cast<std::size_t>(edge.child)] = 1;
    }
    if (state.appearance) child_views_.emplace(query_, read_grey_images(state.capture, child_.sequence, child_.frame));
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
    // A fold of the template onto itself is first aligned again from the same parent with the
    // coarsest patches searched about their joints (patch_targets.hpp), from the trunk's rigid
    // motion and then, if still folded, from the whole body's (rigid_initialisation.hpp).
    const auto folded = [&] {
      return kept.result && kept.verdict == Verdict::failed &&
             kept.result->stacked_fraction > state_.options.failure.max_stacked;
    };
    for (const Start start : {Start::unfold, Start::unfold_whole_body})
      if (folded()) keep_better(kept, attempt(edge_.parent, start), edge_.parent, verdict_from);
    if (kept.verdict != Verdict::pass && !record_.failed_attempts.empty() && costs != nullptr)
      retry_parents(kept, candidate_parents(*costs, edge_.child, edge_.parent, state_.nodes, usable, false),
                    state_.options.recovery, attempt_from, verdict_from);
    if (kept.result && record_.failed_attempts.empty() && state_.options.recovery.entry_candidates > 0 &&
        costs != nullptr && state_.nodes[static_cast<std::size_t>(edge_.parent)].sequence != child_.sequence)
      try_entry_candidates(kept,
                           entry_parents(*costs, edge_.child, edge_.parent, state_.tree.root, state_.nodes, usable,
                                         state_.options.recovery.entry_candidates),
                           state_.options.failure.max_uncovered / kEntryMarginDivisor, attempt_from, verdict_from,
                           record_);
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

  /// A frame another parent can be: a trunk frame (for a trunk child, of a lower depth) or a frame
  /// of the child's unit of a lower depth — aligned before the child whatever the jobs — and not
  /// failed itself. Membership is tested first: other records may still be being written.
  bool usable_parent(long other) const {
    const long unit = state_.partition.unit_of[static_cast<std::size_t>(edge_.child)];
    const long other_unit = state_.partition.unit_of[static_cast<std::size_t>(other)];
    const bool lower = state_.node_depth[static_cast<std::size_t>(other)] < edge_.depth;
    const bool member = other_unit < 0 ? unit >= 0 || lower : other_unit == unit && lower;
    return member && other != edge_.child && !state_.registration.frames[static_cast<std::size_t>(other)].unrecovered;
  }

  /// The image features of parent and child; an alternative parent's were released with its depth
  /// and come from TreeState::alternative_features (held by `other`).
  FeaturePair feature_pair(long from, std::shared_ptr<const FrameFeatures>& other) const {
    FeaturePair pair;
    pair.cameras = &state_.cameras;
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
      pair.child_views = &*child_views_;
    }
    return pair;
  }

  /// How an attempt starts: as configured, or a folded frame's joint search from the trunk's or
  /// the whole body's rigid motion.
  enum class Start { plain, unfold, unfold_whole_body };

  /// One attempt from `from`; nullopt (and a record of why) if it throws, recorded if it fits badly.
  std::optional<PairwiseResult> attempt(long from, Start start = Start::plain) {
    std::shared_ptr<const FrameFeatures> other;
    const FeaturePair pair = feature_pair(from, other);
    try {
      const Eigen::MatrixXd& parent = state_.positions[static_cast<std::size_t>(from)];
      const long grand = state_.registration.frames[static_cast<std::size_t>(from)].parent;
      const Eigen::MatrixXd predicted = state_.predictor.predict(
          edge_.child, from, grand, parent, grand >= 0 ? state_.positions[static_cast<std::size_t>(grand)] : parent,
          state_.model, query_, state_.options.pairwise);
      PairwiseOptions options = state_.options.pairwise;
      options.unfold = start != Start::plain;
      options.whole_body_start = start == Start::unfold_whole_body;
      PairwiseResult result = align_pair(state_.model, parent, query_, options,
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
      spdlog::info("{}:{}: aligned from node {} (a better entry into its sequence than from its tree parent)",
                   record_.sequence, record_.frame, kept.parent);
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
    state_.aligned[static_cast<std::size_t>(edge_.child)] = 1;
    const std::size_t finished = ++state_.done;
    if (*state_.progress) (*state_.progress)(finished, state_.nodes.size());
  }

  TreeState& state_;
  const AlignmentTree::Edge& edge_;
  const Clock::time_point start_;
  const NodeFrame child_;
  const core::Mesh target_;
  const geometry::SurfaceQuery query_;
  std::optional<ChildViews> child_views_;
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
                   long root, const TemplateSurface& template_surface) {
  const core::Mesh& template_mesh = template_surface.mesh;
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
  record.alignment.holes = template_surface.holes;
  record.alignment.largest_hole_perimeter = template_surface.largest_hole_perimeter;
  record.alignment.unobserved_fraction =
      1.0 - static_cast<double>(template_surface.observed_vertices) / static_cast<double>(template_mesh.vertex_count());
}

/// The image features of the parents of `edges` that are not at hand (released, or aligned by
/// another job), detected again: the detection depends on the frame alone.
void detect_parent_features(TreeState& state, const std::vector<AlignmentTree::Edge>& edges, int threads) {
  if (!state.use_features) return;
  std::vector<long> missing;
  for (const auto& edge : edges)
    if (!state.features_ready[static_cast<std::size_t>(edge.parent)]) missing.push_back(edge.parent);
  std::sort(missing.begin(), missing.end());
  missing.erase(std::unique(missing.begin(), missing.end()), missing.end());
  core::parallel_for(static_cast<long>(missing.size()), threads, [&](long i) {
    const auto node = static_cast<std::size_t>(missing[static_cast<std::size_t>(i)]);
    const core::Mesh mesh = read_reconstruction(state.capture, state.nodes[node]);
    state.features[node] = state.detect_features(state.nodes[node], geometry::SurfaceQuery(mesh.V, mesh.F));
    state.features_ready[node] = 1;
  });
}

/// Depth by depth: the edges of one depth only read positions of aligned nodes (the trunk, lower
/// depths). Image features of a node are released once the next depth (its children) is done.
void align_depths(TreeState& state, const std::vector<AlignmentTree::Edge>& edges_to_align, int threads) {
  std::map<int, std::vector<AlignmentTree::Edge>> by_depth;
  for (const auto& edge : edges_to_align) by_depth[edge.depth].push_back(edge);
  for (const auto& level : by_depth) {
    const auto& edges = level.second;  // not a structured binding: clang 14 cannot capture those
    for (const auto& edge : edges)
      if (!state.aligned[static_cast<std::size_t>(edge.parent)])
        throw core::internal_error("tree registration: edge from a node not aligned");
    detect_parent_features(state, edges, threads);
    core::parallel_for(static_cast<long>(edges.size()), threads, [&](long i) {
      EdgeAlignment(state, edges[static_cast<std::size_t>(i)]).run();
    });
    for (const auto& edge : edges) {
      state.features[static_cast<std::size_t>(edge.parent)] = FrameFeatures{};
      state.features_ready[static_cast<std::size_t>(edge.parent)] = 0;
    }
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

struct TreeRegistration::Impl {
  const core::Capture& capture;
  const similarity::FrameList& frames;
  const AlignmentTree& tree;
  const RegisterOptions& options;
  const core::ProgressCallback progress;
  const std::vector<NodeFrame> nodes;
  const TreePartition partition;
  const NodeFrame root;
  Registration registration;  ///< the template's figures and the records
  TemplateSurface template_surface;
  std::unique_ptr<AlignmentTemplate> model;
  std::unique_ptr<MotionPredictor> predictor;
  std::unique_ptr<TemplateAppearance> appearance;
  std::unique_ptr<TreeState> state;

  Impl(const core::Capture& c, const similarity::FrameList& f, const AlignmentTree& t, const RegisterOptions& o,
       core::ProgressCallback p)
      : capture(c), frames(f), tree(t), options(o), progress(std::move(p)), nodes(node_frames(c, f)),
        partition(partition_tree(t)), root(nodes.at(static_cast<std::size_t>(t.root))) {}

  /// The edges into the given nodes, in tree order.
  std::vector<AlignmentTree::Edge> edges_into(const std::vector<long>& children) const {
    std::vector<char> wanted(nodes.size(), 0);
    for (const long node : children) wanted[static_cast<std::size_t>(node)] = 1;
    std::vector<AlignmentTree::Edge> edges;
    for (const auto& edge : tree.edges)
      if (wanted[static_cast<std::size_t>(edge.child)]) edges.push_back(edge);
    return edges;
  }
};

TreeRegistration::TreeRegistration(const core::Capture& capture, const similarity::FrameList& frames,
                                   const AlignmentTree& tree, const RegisterOptions& options,
                                   const core::ProgressCallback& progress)
    : impl_(std::make_unique<Impl>(capture, frames, tree, options, progress)) {
  options.validate();
  Impl& m = *impl_;
  const auto template_start = Clock::now();
  m.template_surface = close_template(read_reconstruction(capture, m.root));
  m.model = std::make_unique<AlignmentTemplate>(m.template_surface, options.pairwise, options.deformer,
                                                capture_cameras(capture));
  const core::Mesh& template_mesh = m.model->mesh();
  Registration& registration = m.registration;
  registration.seconds_template = std::chrono::duration<double>(Clock::now() - template_start).count();
  registration.deformer_model = m.model->deformer().model();
  registration.volume_vertices = m.model->deformer().vertex_count();
  registration.elements = m.model->deformer().element_count();
  registration.template_unseen_vertices = m.model->unseen_vertex_count();
  registration.softened_elements = m.model->deformer().softened_elements();
  registration.cut_elements = m.model->deformer().cut_elements();
  registration.template_cut_vertices = m.model->deformer().cut_vertices();
  registration.template_observed_vertices = m.template_surface.observed_vertices;
  registration.template_dropped_vertices = m.template_surface.dropped_vertices;
  spdlog::info("template {}:{} — {} vertices, {} model with {} vertices and {} elements",
               capture.sequences[static_cast<std::size_t>(m.root.sequence)].name, m.root.frame,
               template_mesh.vertex_count(), registration.deformer_model, registration.volume_vertices,
               registration.elements);
  if (m.template_surface.loose_pieces > 0)
    spdlog::info("template: {} loose pieces of the root reconstruction left out ({} vertices)",
                 m.template_surface.loose_pieces, m.template_surface.dropped_vertices.size());
  if (m.template_surface.holes > 0)
    spdlog::info("template: {} holes of the root reconstruction closed; {:.1f} % of the template is unobserved",
                 m.template_surface.holes, 100 * m.model->unobserved_fraction());
  if (registration.softened_elements > 0)
    spdlog::info("template: {} vertices no camera sees; {} tets under them softened", registration.template_unseen_vertices,
                 registration.softened_elements);
  if (registration.cut_elements > 0)
    spdlog::info("template: {} tets join parts that touch but lie far apart along the surface; cut",
                 registration.cut_elements);
  spdlog::info("tree partition: a trunk of {} frames and {} units of at most {} frames", m.partition.trunk_size,
               m.partition.units(), m.partition.bound);
  start_records(registration, capture, m.nodes, tree.root, m.template_surface);

  m.predictor = std::make_unique<MotionPredictor>(m.nodes, options.costs, options.motion);
  m.state = std::make_unique<TreeState>(capture, m.nodes, tree, m.partition, options, *m.model, *m.predictor,
                                        registration);
  TreeState& state = *m.state;
  state.use_features = options.images && options.pairwise.feature.weight.has_value();
  m.appearance = root_appearance(capture, m.root, *m.model, options);
  if (m.appearance) registration.appearance_coverage = m.appearance->coverage();
  state.appearance = m.appearance.get();
  state.progress = &m.progress;
}

TreeRegistration::~TreeRegistration() = default;

const TreePartition& TreeRegistration::partition() const { return impl_->partition; }

const Registration& TreeRegistration::summary() const { return impl_->registration; }

void TreeRegistration::align_trunk() {
  Impl& m = *impl_;
  TreeState& state = *m.state;
  const auto root = static_cast<std::size_t>(m.tree.root);
  state.positions[root] = m.model->deformer().rest();
  state.aligned[root] = 1;
  if (state.use_features) {
    const core::Mesh& template_mesh = m.model->mesh();
    state.features[root] = state.detect_features(m.root, geometry::SurfaceQuery(template_mesh.V, template_mesh.F));
    state.features_ready[root] = 1;
    m.registration.frames[root].features = state.features[root].size();
  }
  if (m.progress) m.progress(++state.done, m.nodes.size());
  align_depths(state, m.edges_into(partition_nodes(m.partition, {}, true)), m.options.threads);
}

void TreeRegistration::load(const RegistrationPart& part) {
  TreeState& state = *impl_->state;
  for (std::size_t k = 0; k < part.nodes.size(); ++k) {
    const auto node = static_cast<std::size_t>(part.nodes[k]);
    state.positions[node] = part.positions[k];
    impl_->registration.frames[node] = part.records[k];
    state.aligned[node] = 1;
  }
}

void TreeRegistration::align_units(const std::vector<long>& units) {
  Impl& m = *impl_;
  for (const long node : partition_nodes(m.partition, {}, true))
    if (!m.state->aligned[static_cast<std::size_t>(node)])
      throw core::internal_error("tree registration: units aligned before the trunk");
  align_depths(*m.state, m.edges_into(partition_nodes(m.partition, units, false)), m.options.threads);
}

RegistrationPart TreeRegistration::part(const std::vector<long>& nodes) const {
  RegistrationPart part;
  part.nodes = nodes;
  for (const long node : nodes) {
    if (!impl_->state->aligned[static_cast<std::size_t>(node)])
      throw core::internal_error("tree registration: part with a node not aligned");
    part.records.push_back(impl_->registration.frames[static_cast<std::size_t>(node)]);
    part.positions.push_back(impl_->state->positions[static_cast<std::size_t>(node)]);
  }
  return part;
}

Registration TreeRegistration::finish() const {
  std::vector<long> all(impl_->nodes.size());
  std::iota(all.begin(), all.end(), 0L);
  const RegistrationPart whole = part(all);
  return assemble_registration(impl_->capture, impl_->frames, impl_->tree, {&whole}, impl_->registration);
}

std::vector<long> partition_nodes(const TreePartition& partition, const std::vector<long>& units, bool trunk) {
  std::vector<char> chosen(static_cast<std::size_t>(partition.units()), 0);
  for (const long unit : units) chosen.at(static_cast<std::size_t>(unit)) = 1;
  std::vector<long> nodes;
  for (std::size_t node = 0; node < partition.unit_of.size(); ++node) {
    const long unit = partition.unit_of[node];
    if (unit < 0 ? trunk : chosen[static_cast<std::size_t>(unit)] != 0) nodes.push_back(static_cast<long>(node));
  }
  return nodes;
}

Registration assemble_registration(const core::Capture& capture, const similarity::FrameList& frames,
                                   const AlignmentTree& tree, const std::vector<const RegistrationPart*>& parts,
                                   const Registration& summary) {
  const std::vector<NodeFrame> nodes = node_frames(capture, frames);
  const NodeFrame root = nodes.at(static_cast<std::size_t>(tree.root));
  const TemplateSurface template_surface = close_template(read_reconstruction(capture, root));
  const core::Mesh& template_mesh = template_surface.mesh;
  Registration registration = summary;  // the template's figures; frames and positions from the parts
  registration.template_dropped_vertices = template_surface.dropped_vertices;
  registration.frames.assign(nodes.size(), FrameRecord{});
  registration.world_positions.assign(nodes.size(), Eigen::MatrixXd{});
  std::vector<char> seen(nodes.size(), 0);
  for (const RegistrationPart* part : parts)
    for (std::size_t k = 0; k < part->nodes.size(); ++k) {
      const auto node = static_cast<std::size_t>(part->nodes[k]);
      if (node >= nodes.size() || seen[node] || part->positions[k].rows() < template_mesh.vertex_count())
        throw core::internal_error("assemble_registration: parts do not hold every node once");
      seen[node] = 1;
      registration.frames[node] = part->records[k];
      registration.world_positions[node] = part->positions[k].topRows(template_mesh.vertex_count());
    }
  if (std::find(seen.begin(), seen.end(), 0) != seen.end())
    throw core::internal_error("assemble_registration: a node is in no part");
  registration.database =
      aligned_database(capture, frames, template_mesh, root.sequence, root.frame, registration.world_positions);
  return registration;
}

Registration register_capture(const core::Capture& capture, const similarity::FrameList& frames,
                              const AlignmentTree& tree, const RegisterOptions& options,
                              const core::ProgressCallback& progress) {
  TreeRegistration registration(capture, frames, tree, options, progress);
  registration.align_trunk();
  std::vector<long> units(static_cast<std::size_t>(registration.partition().units()));
  std::iota(units.begin(), units.end(), 0L);
  registration.align_units(units);
  return registration.finish();
}

}  // namespace surfcap::align
