#include "surfcap/align/tree_alignment.hpp"

#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <map>

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

Registration register_capture(const core::Capture& capture, const similarity::FrameList& frames,
                              const AlignmentTree& tree, const RegisterOptions& options,
                              const core::ProgressCallback& progress) {
  options.pairwise.validate();
  const std::vector<NodeFrame> nodes = node_frames(capture, frames);
  const long node_count = static_cast<long>(nodes.size());
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
  std::atomic<std::size_t> done{1};
  if (progress) progress(done, static_cast<std::size_t>(node_count));

  // Level by level: the edges of one depth only read positions of the previous depth.
  std::map<int, std::vector<AlignmentTree::Edge>> by_depth;
  for (const auto& edge : tree.edges) by_depth[edge.depth].push_back(edge);
  for (const auto& level : by_depth) {
    const auto& edges = level.second;  // not a structured binding: clang 14 cannot capture those
    core::parallel_for(static_cast<long>(edges.size()), options.threads, [&](long i) {
      const auto& edge = edges[static_cast<std::size_t>(i)];
      const auto start = Clock::now();
      const NodeFrame child = nodes[static_cast<std::size_t>(edge.child)];
      const core::Mesh target = read_reconstruction(capture, child.sequence, child.frame);
      const geometry::SurfaceQuery query(target.V, target.F);
      PairwiseResult result = align_pair(model, positions[static_cast<std::size_t>(edge.parent)], query, options.pairwise,
                                         target.has_colors() ? &target.colors : nullptr);
      positions[static_cast<std::size_t>(edge.child)] = std::move(result.positions);
      result.positions.resize(0, 0);
      auto& record = registration.frames[static_cast<std::size_t>(edge.child)];
      record.parent = edge.parent;
      record.depth = edge.depth;
      record.alignment = std::move(result);
      record.seconds = std::chrono::duration<double>(Clock::now() - start).count();
      const std::size_t finished = ++done;
      if (progress) progress(finished, static_cast<std::size_t>(node_count));
    });
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
