#include "surfcap/align/tree_alignment.hpp"

#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <algorithm>
#include <array>
#include <map>
#include <memory>
#include <optional>
#include <Eigen/Dense>

#include "surfcap/core/error.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/mesh_repair.hpp"
#include "surfcap/core/parallel.hpp"

namespace surfcap::align {

namespace {

using Clock = std::chrono::steady_clock;

core::Mesh read_reconstruction(const core::Capture& capture, int sequence, int frame) {
  return core::read_reconstruction(capture.mesh_path(sequence, frame), frame);
}

struct NodeFrame {
  int sequence = 0;  ///< capture sequence index
  int frame = 0;     ///< frame number
};

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

}  // namespace

AlignmentTree read_alignment_tree(const std::filesystem::path& database, long node_count) {
  const auto path = database / "similarity" / "tree.json";
  const core::Json document = core::read_json_document(path, "tree", 1);
  AlignmentTree tree;
  try {
    tree.root = document.at("root").at("node").get<long>();
    tree.nodes = document.at("nodes").get<std::vector<std::string>>();
    for (const auto& entry : document.at("edges"))
      tree.edges.push_back({entry.at("parent").get<long>(), entry.at("child").get<long>(), entry.at("cost").get<double>(),
                            entry.at("depth").get<int>()});
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

core::RootMotion root_motion(const Eigen::MatrixXd& template_rest, const Eigen::MatrixXd& world) {
  const Eigen::RowVector3d rest_centre = template_rest.colwise().mean();
  const Eigen::RowVector3d centre = world.colwise().mean();
  double cosine = 0, sine = 0;
  for (long i = 0; i < world.rows(); ++i) {
    const Eigen::RowVector3d a = template_rest.row(i) - rest_centre, b = world.row(i) - centre;
    cosine += b.x() * a.x() + b.z() * a.z();
    sine += b.x() * a.z() - b.z() * a.x();
  }
  core::RootMotion root;
  root.x = centre.x();
  root.y = centre.y();
  root.z = centre.z();
  root.heading = std::atan2(sine, cosine);
  return root;
}

Eigen::MatrixXd pose_volume(const AlignmentTemplate& model, const Eigen::MatrixXd& surface) {
  const VolumeDeformer& deformer = model.deformer();
  const long n = deformer.surface_vertex_count();
  if (surface.rows() != n) throw core::internal_error("pose_volume: surface size");
  const Eigen::MatrixXd rest = deformer.rest().topRows(n);
  const Eigen::RowVector3d rest_centre = rest.colwise().mean(), centre = surface.colwise().mean();
  const Eigen::Matrix3d covariance = (rest.rowwise() - rest_centre).transpose() * (surface.rowwise() - centre);
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d flip = Eigen::Matrix3d::Identity();
  flip(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1.0 : 1.0;
  const Eigen::Matrix3d rotation = svd.matrixV() * flip * svd.matrixU().transpose();
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
  const double failure_residual = options.failure.failure_residual_mm / 1000;
  const std::vector<NodeFrame> nodes = node_frames(capture, frames);
  const long node_count = static_cast<long>(nodes.size());
  std::map<std::pair<int, int>, long> node_of;  // (capture sequence, frame) → node
  for (long node = 0; node < node_count; ++node)
    node_of[{nodes[static_cast<std::size_t>(node)].sequence, nodes[static_cast<std::size_t>(node)].frame}] = node;
  Registration registration;
  const NodeFrame root = nodes[static_cast<std::size_t>(tree.root)];
  const auto template_start = Clock::now();
  core::Mesh template_mesh = read_reconstruction(capture, root.sequence, root.frame);
  const AlignmentTemplate model(template_mesh, options.pairwise, options.deformer);
  registration.seconds_template = std::chrono::duration<double>(Clock::now() - template_start).count();
  registration.deformer_model = model.deformer().model();
  registration.volume_vertices = model.deformer().vertex_count();
  registration.elements = model.deformer().element_count();
  spdlog::info("template {}:{} — {} vertices, {} model with {} vertices and {} elements", 
               capture.sequences[static_cast<std::size_t>(root.sequence)].name, root.frame,
               template_mesh.vertex_count(), registration.deformer_model, registration.volume_vertices,
               registration.elements);

  std::vector<Eigen::MatrixXd> positions(static_cast<std::size_t>(node_count));
  registration.frames.resize(static_cast<std::size_t>(node_count));
  for (long node = 0; node < node_count; ++node) {
    auto& record = registration.frames[static_cast<std::size_t>(node)];
    record.sequence = capture.sequences[static_cast<std::size_t>(nodes[static_cast<std::size_t>(node)].sequence)].name;
    record.frame = nodes[static_cast<std::size_t>(node)].frame;
    record.node = node;
  }
  positions[static_cast<std::size_t>(tree.root)] = model.deformer().rest();
  {
    auto& record = registration.frames[static_cast<std::size_t>(tree.root)];
    const geometry::SurfaceQuery query(template_mesh.V, template_mesh.F);
    const Eigen::VectorXd distances = surface_distances(template_mesh.V, query);
    record.alignment.mean_residual = distances.mean();
    record.alignment.max_residual = distances.maxCoeff();
  }
  // Image features per node: detected when the node is aligned (the root first), released once the
  // next depth (its children) is done.
  const bool use_features = options.images && options.pairwise.feature.weight.has_value();
  std::vector<FrameFeatures> features(static_cast<std::size_t>(node_count));
  if (use_features) {
    const geometry::SurfaceQuery query(template_mesh.V, template_mesh.F);
    features[static_cast<std::size_t>(tree.root)] =
        detect_frame_features(capture, root.sequence, root.frame, query, options.pairwise.feature);
    registration.frames[static_cast<std::size_t>(tree.root)].features = features[static_cast<std::size_t>(tree.root)].size();
  }
  // The root frame's appearance of the template, for the flow iterations (undistorted images only).
  std::unique_ptr<TemplateAppearance> appearance;
  const bool root_has_images = !capture.sequences[static_cast<std::size_t>(root.sequence)].images.empty();
  if (options.images && options.pairwise.flow.weight && options.pairwise.flow.iterations > 0 && root_has_images) {
    if (has_distortion(capture)) {
      spdlog::warn("cameras.json declares lens distortion: the appearance flow needs undistorted images, not used");
    } else {
      appearance = std::make_unique<TemplateAppearance>(template_mesh, capture_cameras(capture),
                                                        read_grey_images(capture, root.sequence, root.frame),
                                                        model.mean_edge(), options.pairwise.flow);
      registration.appearance_coverage = appearance->coverage();
      spdlog::info("root appearance covers {:.1f}% of the template", 100.0 * appearance->coverage());
    }
  }
  std::atomic<std::size_t> done{1};
  if (progress) progress(done, static_cast<std::size_t>(node_count));

  // Level by level: the edges of one depth only read positions of the previous depth.
  std::map<int, std::vector<AlignmentTree::Edge>> by_depth;
  std::vector<int> node_depth(static_cast<std::size_t>(node_count), 0);
  for (const auto& edge : tree.edges) {
    by_depth[edge.depth].push_back(edge);
    node_depth[static_cast<std::size_t>(edge.child)] = edge.depth;
  }
  for (const auto& level : by_depth) {
    const auto& edges = level.second;  // not a structured binding: clang 14 cannot capture those
    core::parallel_for(static_cast<long>(edges.size()), options.threads, [&](long i) {
      const auto& edge = edges[static_cast<std::size_t>(i)];
      const auto start = Clock::now();
      const NodeFrame child = nodes[static_cast<std::size_t>(edge.child)];
      const core::Mesh target = read_reconstruction(capture, child.sequence, child.frame);
      const geometry::SurfaceQuery query(target.V, target.F);
      if (use_features)
        features[static_cast<std::size_t>(edge.child)] =
            detect_frame_features(capture, child.sequence, child.frame, query, options.pairwise.feature);
      const std::vector<GreyImage> child_images =
          appearance ? read_grey_images(capture, child.sequence, child.frame) : std::vector<GreyImage>{};
      auto& record = registration.frames[static_cast<std::size_t>(edge.child)];
      // An attempt passes, fits clearly worse than its parent did (`grown`: worth a retry, but no
      // evidence of a wrong alignment on its own) or failed: its residual, uncovered or stacked
      // fraction is above the limit (the worst relative to its limit names the failure).
      enum class Verdict { pass, grown, failed };
      const auto hard_scores = [&](const PairwiseResult& r) {
        return std::array<double, 3>{r.mean_residual / failure_residual,
                                     r.uncovered_fraction / options.failure.max_uncovered,
                                     r.stacked_fraction / options.failure.max_stacked};
      };
      const auto grown = [&](const PairwiseResult& r, long from) {
        // The root's residual is that of the template on its own reconstruction (about 0): no reference.
        const double parent_residual =
            from == tree.root ? 0.0 : registration.frames[static_cast<std::size_t>(from)].alignment.mean_residual;
        return options.failure.residual_growth && parent_residual > 0 &&
               r.mean_residual > *options.failure.residual_growth * parent_residual;
      };
      const auto verdict = [&](const PairwiseResult& r, long from) {
        const auto scores = hard_scores(r);
        if (*std::max_element(scores.begin(), scores.end()) > 1) return Verdict::failed;
        return grown(r, from) ? Verdict::grown : Verdict::pass;
      };
      const auto failure_reason = [&](const PairwiseResult& r, long from) -> std::string {
        static const char* const reasons[] = {"mean residual above the failure threshold",
                                              "reconstruction not covered by the aligned template",
                                              "aligned template stacked onto itself"};
        if (verdict(r, from) == Verdict::grown) return "mean residual grown beyond its parent's";
        const auto scores = hard_scores(r);
        return reasons[std::max_element(scores.begin(), scores.end()) - scores.begin()];
      };
      // The child's surface predicted from `from` (all deformer vertices `parent`) and from's own
      // parent, when they are consecutive frames of one sequence and the child is the frame that
      // follows them — or looks much more like that frame than like `from` (a cycle's twin, below);
      // empty otherwise.
      auto motion_prediction = [&](long from, const Eigen::MatrixXd& parent) -> Eigen::MatrixXd {
        if (!options.motion.motion_prediction) return {};
        const long grand = registration.frames[static_cast<std::size_t>(from)].parent;
        if (grand < 0) return {};
        const NodeFrame a = nodes[static_cast<std::size_t>(grand)], b = nodes[static_cast<std::size_t>(from)];
        if (a.sequence != b.sequence || std::abs(b.frame - a.frame) != 1) return {};
        const bool next_frame = child.sequence == b.sequence && child.frame - b.frame == b.frame - a.frame;
        if (!next_frame) {
          // A cyclic motion (run, walk) makes frames a cycle apart near copies of each other, and the
          // tree links such twins: demo's run:28 ← run:11, where run:28 is run:10's twin (cost 0.002
          // against 0.086 to run:11) — one running step of run:12 → run:11, with the rear foot
          // kicking up out of the patch gate.
          const auto next = node_of.find({b.sequence, 2 * b.frame - a.frame});
          if (!options.motion.twin_prediction || options.costs == nullptr || next == node_of.end() ||
              (*options.costs)(edge.child, next->second) > *options.motion.twin_prediction * (*options.costs)(edge.child, from))
            return {};
        }
        const long n = model.deformer().surface_vertex_count();
        Eigen::MatrixXd predicted =
            parent.topRows(n) +
            *options.motion.motion_prediction * (parent.topRows(n) - positions[static_cast<std::size_t>(grand)].topRows(n));
        if (!next_frame) {
          // The twin is a cycle's travel away (demo's run: 2 m): the predicted pose is moved onto the
          // child's reconstruction as a whole, as the parent is by align_pair's rigid initialisation.
          const RigidFit fit = rigid_initialisation(predicted, core::vertex_normals(predicted, model.mesh().F), query,
                                                    model, options.pairwise);
          predicted = ((predicted * fit.rotation.transpose()).rowwise() + fit.translation.transpose()).eval();
        }
        return predicted;
      };
      // One attempt from `from`; nullopt (and a record of why) if it throws or fits badly.
      auto attempt = [&](long from) -> std::optional<PairwiseResult> {
        FrameFeatures other;  // an alternative parent's features were released with its depth
        const FrameFeatures* parent_features = &features[static_cast<std::size_t>(from)];
        if (use_features && from != edge.parent) {
          const NodeFrame source = nodes[static_cast<std::size_t>(from)];
          const core::Mesh mesh = read_reconstruction(capture, source.sequence, source.frame);
          other = detect_frame_features(capture, source.sequence, source.frame,
                                        geometry::SurfaceQuery(mesh.V, mesh.F), options.pairwise.feature);
          parent_features = &other;
        }
        FeaturePair pair = use_features ? FeaturePair{parent_features, &features[static_cast<std::size_t>(edge.child)]}
                                        : FeaturePair{};
        if (appearance) {
          pair.appearance = appearance.get();
          pair.child_images = &child_images;
        }
        try {
          const Eigen::MatrixXd& parent = positions[static_cast<std::size_t>(from)];
          const Eigen::MatrixXd predicted = motion_prediction(from, parent);
          PairwiseResult result = align_pair(model, parent, query, options.pairwise,
                                             target.has_colors() ? &target.colors : nullptr, pair,
                                             predicted.rows() > 0 ? &predicted : nullptr);
          if (verdict(result, from) == Verdict::pass) return result;
          record.failed_attempts.push_back({from, result.mean_residual, result.uncovered_fraction,
                                            result.stacked_fraction, failure_reason(result, from)});
          return result;  // kept only if no retry does better
        } catch (const core::Error& error) {
          record.failed_attempts.push_back({from, -1.0, 0.0, 0.0, error.what()});
          return std::nullopt;
        }
      };
      // A frame another parent can be: aligned already (a lower depth) and not failed itself.
      const auto usable_parent = [&](long other) {
        return other != edge.child && node_depth[static_cast<std::size_t>(other)] < edge.depth &&
               !registration.frames[static_cast<std::size_t>(other)].unrecovered;
      };
      std::optional<PairwiseResult> best = attempt(edge.parent);
      long best_parent = edge.parent;
      Verdict best_verdict = best ? verdict(*best, edge.parent) : Verdict::failed;
      if (!record.failed_attempts.empty() && options.costs != nullptr) {
        // Next-best neighbours: frames of lower depth (already aligned), by similarity cost.
        std::vector<std::pair<double, long>> candidates;
        for (long other = 0; other < node_count; ++other)
          if (other != edge.parent && usable_parent(other))
            candidates.push_back({(*options.costs)(edge.child, other), other});
        std::sort(candidates.begin(), candidates.end());
        for (std::size_t k = 0; k < candidates.size() && static_cast<int>(k) < options.recovery.retries; ++k) {
          const long from = candidates[k].second;
          std::optional<PairwiseResult> retry = attempt(from);
          if (!retry) continue;
          const Verdict v = verdict(*retry, from);
          // Of the attempts that did not fail, the lowest mean residual is kept (as for entry
          // candidates, below); one that did not fail replaces one that did. When all fail, the tree
          // parent's attempt is the safer guess (a lower failure score is no evidence of a better
          // alignment: dance:5 from its tree parent 55 mm from the truth at 1.8 % uncovered, from an
          // alternative 154 mm at 1.4 %).
          const bool usable = v != Verdict::failed;
          if (!best || (usable && (best_verdict == Verdict::failed || retry->mean_residual < best->mean_residual))) {
            best = std::move(retry);
            best_parent = from;
            best_verdict = v;
          }
          if (v == Verdict::pass) break;
        }
      }
      // An edge entering the child's sequence from another: the similarity of two sequences' poses
      // can hide a limb far from where it went (tiny's run:0 ← jump_high:22 moves a foot 43 cm), so
      // the most similar aligned frame of up to `entry_candidates` other sequences is tried too;
      // the lowest mean residual wins (on tiny's run:0 it separated 80 mm from 30 mm alignments).
      if (best && record.failed_attempts.empty() && options.recovery.entry_candidates > 0 && options.costs != nullptr && nodes[static_cast<std::size_t>(edge.parent)].sequence != child.sequence) {
        std::map<int, std::pair<double, long>> by_sequence;  // most similar aligned frame per sequence
        for (long other = 0; other < node_count; ++other) {
          const int sequence = nodes[static_cast<std::size_t>(other)].sequence;
          if (sequence == nodes[static_cast<std::size_t>(edge.parent)].sequence || !usable_parent(other)) continue;
          const double cost = (*options.costs)(edge.child, other);
          const auto found = by_sequence.find(sequence);
          if (found == by_sequence.end() || cost < found->second.first) by_sequence[sequence] = {cost, other};
        }
        std::vector<std::pair<double, long>> entries;
        for (const auto& [sequence, candidate] : by_sequence) entries.push_back(candidate);
        std::sort(entries.begin(), entries.end());
        for (std::size_t k = 0; k < entries.size() && static_cast<int>(k) < options.recovery.entry_candidates; ++k) {
          const std::size_t failures = record.failed_attempts.size();
          std::optional<PairwiseResult> alternative = attempt(entries[k].second);
          record.failed_attempts.resize(failures);  // an alternative that fails is no failure of the frame
          ++record.entry_attempts;
          if (alternative && verdict(*alternative, entries[k].second) == Verdict::pass &&
              alternative->mean_residual < best->mean_residual &&
              alternative->uncovered_fraction <= best->uncovered_fraction + options.failure.max_uncovered / 4) {
            best = std::move(alternative);
            best_parent = entries[k].second;
          }
        }
      }
      if (!best)
        throw core::bad_input(capture.mesh_path(child.sequence, child.frame),
                              "alignment failed from every candidate parent: " + record.failed_attempts.front().failure,
                              child.frame);
      if (best_parent != edge.parent && record.failed_attempts.empty())
        spdlog::info("{}:{}: aligned from node {} (a lower residual than from its tree parent)", record.sequence,
                     record.frame, best_parent);
      else if (best_parent != edge.parent)
        spdlog::warn("{}:{}: alignment from its tree parent failed; aligned from node {} instead", record.sequence,
                     record.frame, best_parent);
      record.unrecovered = best_verdict == Verdict::failed;
      PairwiseResult result = std::move(*best);
      positions[static_cast<std::size_t>(edge.child)] = std::move(result.positions);
      result.positions.resize(0, 0);
      record.parent = best_parent;
      record.depth = edge.depth;
      record.alignment = std::move(result);
      record.seconds = std::chrono::duration<double>(Clock::now() - start).count();
      record.features = features[static_cast<std::size_t>(edge.child)].size();
      const std::size_t finished = ++done;
      if (progress) progress(finished, static_cast<std::size_t>(node_count));
    });
    for (const auto& edge : edges) features[static_cast<std::size_t>(edge.parent)] = FrameFeatures{};
  }

  // The database: template = the root reconstruction; frames centred with their root motion.
  const long surface = template_mesh.vertex_count();
  core::AlignedDatabase& database = registration.database;
  database.template_mesh = template_mesh;
  database.root_sequence = capture.sequences[static_cast<std::size_t>(root.sequence)].name;
  database.root_frame = root.frame;
  database.fps = capture.fps;
  database.units = capture.units;
  registration.world_positions.resize(static_cast<std::size_t>(node_count));
  long node = 0;
  for (const auto& sequence : frames.sequences) {
    core::AlignedSequence aligned;
    aligned.name = sequence.name;
    for (int k = 0; k < sequence.count; ++k, ++node) {
      Eigen::MatrixXd world = positions[static_cast<std::size_t>(node)].topRows(surface);
      const core::RootMotion motion = root_motion(template_mesh.V, world);
      aligned.frames.push_back(core::to_centred(world, motion));
      aligned.root_motion.push_back(motion);
      registration.world_positions[static_cast<std::size_t>(node)] = std::move(world);
    }
    database.sequences.push_back(std::move(aligned));
  }
  return registration;
}

}  // namespace surfcap::align
