#include "surfcap/similarity/similarity_files.hpp"

#include <Eigen/Eigenvalues>
#include <spdlog/spdlog.h>
#include <atomic>
#include <limits>
#include <map>
#include <regex>

#include "surfcap/core/input_policy.hpp"
#include "surfcap/core/json_integer.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/mesh_io.hpp"
#include "surfcap/core/mesh_repair.hpp"
#include "surfcap/core/npy.hpp"
#include "surfcap/core/parallel.hpp"

namespace surfcap::similarity {

FrameIndex FrameList::index() const {
  std::vector<int> lengths;
  for (const auto& sequence : sequences) lengths.push_back(sequence.count);
  return FrameIndex(lengths);
}

std::string FrameList::label(long node) const {
  for (const auto& sequence : sequences) {
    if (node < sequence.count) return sequence.name + ":" + std::to_string(sequence.first + node);
    node -= sequence.count;
  }
  throw core::internal_error("node out of range");
}

long FrameList::node(const std::string& label) const {
  const std::size_t colon = label.rfind(':');
  long offset = 0;
  if (colon != std::string::npos) {
    const std::string name = label.substr(0, colon);
    int frame = -1;
    try {
      frame = std::stoi(label.substr(colon + 1));
    } catch (const std::exception&) {
    }
    for (const auto& sequence : sequences) {
      if (sequence.name == name && frame >= sequence.first && frame < sequence.first + sequence.count)
        return offset + frame - sequence.first;
      offset += sequence.count;
    }
  }
  throw core::bad_arguments("--root '" + label + "': expected <sequence>:<frame> of a captured frame");
}

double stance_width(const core::Mesh& mesh) {
  const long n = mesh.vertex_count();
  if (n == 0) return 0;
  const double low = mesh.V.col(1).minCoeff(), height = mesh.V.col(1).maxCoeff() - low;
  if (!(height > 0)) return 0;
  std::vector<Eigen::Vector2d> feet;
  for (long v = 0; v < n; ++v)
    if (mesh.V(v, 1) <= low + 0.15 * height) feet.emplace_back(mesh.V(v, 0), mesh.V(v, 2));
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : feet) mean += p;
  mean /= static_cast<double>(feet.size());
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  for (const auto& p : feet) covariance += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(covariance);
  const Eigen::Vector2d axis = eigen.eigenvectors().col(1);  // largest eigenvalue last
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& p : feet) {
    const double t = (p - mean).dot(axis);
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  return (hi - lo) / height;
}

HistogramSet compute_histograms(const core::Capture& capture, const ShapeHistogramOptions& options, int threads,
                                const core::ProgressCallback& progress) {
  options.validate();
  HistogramSet set;
  set.options = options;
  set.capture = capture.folder.string();
  std::vector<std::pair<int, int>> jobs;  // (sequence, frame number)
  for (std::size_t s = 0; s < capture.sequences.size(); ++s) {
    const auto& sequence = capture.sequences[s];
    set.frames.sequences.push_back({sequence.name, sequence.first, sequence.count});
    for (int frame = sequence.first; frame < sequence.first + sequence.count; ++frame)
      jobs.emplace_back(static_cast<int>(s), frame);
  }
  set.histograms.resize(static_cast<long>(jobs.size()), options.size());
  set.stance.assign(jobs.size(), 0.0);
  set.surfaces.assign(jobs.size(), {});
  core::RepairLimits limits;
  limits.keep_large_holes_open = true;
  std::atomic<std::size_t> done{0};
  core::parallel_for(static_cast<long>(jobs.size()), threads, [&](long job) {
    const auto [sequence, frame] = jobs[static_cast<std::size_t>(job)];
    const auto path = capture.mesh_path(sequence, frame);
    core::RepairReport repair;
    const core::Mesh mesh = core::read_reconstruction(path, frame, limits, &repair);
    set.surfaces[static_cast<std::size_t>(job)] = {mesh.vertex_count(), mesh.face_count(), repair.holes_filled,
                                                   core::surface_topology(mesh)};
    try {
      set.histograms.row(job) = shape_histogram(mesh, options).cast<float>().transpose();
      set.stance[static_cast<std::size_t>(job)] = stance_width(mesh);
    } catch (const core::Error& e) {
      throw core::bad_input(path, e.what(), frame);
    }
    if (progress) progress(++done, jobs.size());
  });
  long open = 0, pieces = 0, genus = 0, largest = 0;
  for (const FrameSurface& surface : set.surfaces) {
    open += surface.topology.holes > 0;
    pieces += surface.topology.components > 1;
    genus += surface.topology.genus != 0;
    largest = std::max(largest, surface.topology.largest_hole_edges);
  }
  if (open + pieces + genus > 0)
    spdlog::info("of {} frames, {} are open (largest hole left open: {} edges), {} have several pieces, {} have "
                 "genus > 0 (report/histograms.json \"surfaces\")", jobs.size(), open, largest, pieces, genus);
  return set;
}

core::Json surfaces_report(const HistogramSet& set) {
  long open = 0, pieces = 0, genus = 0, changes = 0;
  core::Json frames = core::Json::array();
  std::size_t node = 0;
  for (const auto& sequence : set.frames.sequences) {
    for (int offset = 0; offset < sequence.count && node < set.surfaces.size(); ++offset, ++node) {
      const FrameSurface& surface = set.surfaces[node];
      const core::SurfaceTopology& topology = surface.topology;
      open += topology.holes > 0;
      pieces += topology.components > 1;
      genus += topology.genus != 0;
      if (offset > 0 && topology.genus != set.surfaces[node - 1].topology.genus) ++changes;
      frames.push_back({{"frame", sequence.name + ":" + std::to_string(sequence.first + offset)},
                        {"vertices", surface.vertices}, {"faces", surface.faces}, {"holes", topology.holes},
                        {"largest_hole_edges", topology.largest_hole_edges},
                        {"largest_hole_perimeter_m", topology.largest_hole_perimeter},
                        {"holes_filled", surface.holes_filled}, {"components", topology.components},
                        {"genus", topology.genus}});
    }
  }
  return {{"open_frames", open}, {"multi_component_frames", pieces}, {"nonzero_genus_frames", genus},
          {"genus_changes_between_consecutive_frames", changes}, {"frames", frames}};
}

void write_histograms(const std::filesystem::path& database, const HistogramSet& set) {
  core::write_npy(database / "similarity" / "histograms.npy", set.histograms.data(),
                  {static_cast<std::size_t>(set.histograms.rows()), static_cast<std::size_t>(set.histograms.cols())});
  core::Json sequences = core::Json::array();
  for (const auto& sequence : set.frames.sequences)
    sequences.push_back({{"name", sequence.name}, {"first", sequence.first}, {"count", sequence.count}});
  core::write_json_file(database / "similarity" / "histograms.json",
                        {{"format", core::format_tag("histograms", 1)},
                         {"histograms", "histograms.npy"},
                         {"options", set.options.to_json()},
                         {"sequences", sequences},
                         {"stance", set.stance},
                         {"capture", set.capture}});
}

HistogramSet read_histograms(const std::filesystem::path& database) {
  const auto json_path = database / "similarity" / "histograms.json";
  const core::Json document = core::read_json_document(json_path, "histograms", 1);
  HistogramSet set;
  set.options = ShapeHistogramOptions::from_json(core::get_field<core::Json>(document, "options", json_path));
  set.capture = document.value("capture", std::string());
  long total = 0;
  for (const auto& entry : core::get_field<core::Json>(document, "sequences", json_path)) {
    FrameList::Sequence sequence{core::name_field(entry, "name", json_path),
                                 static_cast<int>(core::integer_field(entry, "first", json_path, 0, 1'000'000'000)),
                                 static_cast<int>(core::integer_field(entry, "count", json_path, 1, core::kMaxFrames))};
    if (sequence.count <= 0) throw core::bad_input(json_path, "sequence '" + sequence.name + "' has no frames");
    total += sequence.count;
    set.frames.sequences.push_back(sequence);
  }
  const auto npy_path = core::path_field(document, "histograms", json_path);
  const core::NpyArray array = core::read_npy(npy_path, core::DType::float32, {total, set.options.size()});
  set.histograms = Eigen::Map<const FloatRows>(array.data<float>(), total, set.options.size());
  if (document.contains("stance")) {
    set.stance = core::get_field<std::vector<double>>(document, "stance", json_path);
    if (static_cast<long>(set.stance.size()) != total)
      throw core::bad_input(json_path, "'stance' has " + std::to_string(set.stance.size()) + " entries for " +
                                           std::to_string(total) + " frames");
  }
  return set;
}

std::pair<long, long> parse_row_range(const std::string& text, long n) {
  static const std::regex range(R"((\d+):(\d+))");
  std::smatch m;
  if (!std::regex_match(text, m, range)) throw core::bad_arguments("--rows '" + text + "': expected a:b");
  const long begin = std::stol(m[1]), end = std::stol(m[2]);
  if (begin >= end || end > n)
    throw core::bad_arguments("--rows " + text + ": need 0 ≤ a < b ≤ " + std::to_string(n) + " (frames)");
  return {begin, end};
}

std::filesystem::path row_block_path(const std::filesystem::path& database, long begin, long end) {
  return database / "similarity" / "rows" / ("rows-" + std::to_string(begin) + "-" + std::to_string(end) + ".npy");
}

FloatRows merge_row_blocks(const std::filesystem::path& database, long n) {
  const auto folder = database / "similarity" / "rows";
  std::map<long, std::pair<long, std::filesystem::path>> blocks;
  static const std::regex name(R"(rows-(\d+)-(\d+)\.npy)");
  if (std::filesystem::is_directory(folder))
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
      std::smatch m;
      const std::string file = entry.path().filename().string();
      if (std::regex_match(file, m, name)) blocks[std::stol(m[1])] = {std::stol(m[2]), entry.path()};
    }
  FloatRows matrix(n, n);
  long next = 0;
  for (const auto& [begin, block] : blocks) {
    const auto& [end, path] = block;
    if (begin != next)
      throw core::bad_input(path, begin > next ? "rows " + std::to_string(next) + ":" + std::to_string(begin) +
                                                     " are missing"
                                               : "overlaps the previous block");
    const core::NpyArray array = core::read_npy(path, core::DType::float32, {end - begin, n});
    matrix.middleRows(begin, end - begin) = Eigen::Map<const FloatRows>(array.data<float>(), end - begin, n);
    next = end;
  }
  if (next != n)
    throw core::bad_input(folder, "row blocks cover 0:" + std::to_string(next) + " of " + std::to_string(n) + " rows");
  return matrix;
}

std::filesystem::path matrix_path(const std::filesystem::path& database) {
  return database / "similarity" / "matrix.npy";
}

FloatRows read_matrix(const std::filesystem::path& database, long n) {
  const core::NpyArray array = core::read_npy(matrix_path(database), core::DType::float32, {n, n});
  return Eigen::Map<const FloatRows>(array.data<float>(), n, n);
}

void write_tree(const std::filesystem::path& database, const SimilarityTree& tree, const FrameList& frames) {
  auto node_json = [&](int node) {
    const std::string label = frames.label(node);
    const std::size_t colon = label.rfind(':');
    return core::Json{{"node", node}, {"sequence", label.substr(0, colon)}, {"frame", std::stoi(label.substr(colon + 1))}};
  };
  core::Json edges = core::Json::array();
  for (const auto& edge : tree.edges)
    edges.push_back({{"parent", edge.parent}, {"child", edge.child}, {"cost", edge.cost},
                     {"depth", tree.depth[static_cast<std::size_t>(edge.child)]}});
  core::Json nodes = core::Json::array();
  for (long i = 0; i < static_cast<long>(tree.depth.size()); ++i) nodes.push_back(frames.label(i));
  core::write_json_file(database / "similarity" / "tree.json",
                        {{"format", core::format_tag("tree", 1)},
                         {"root", node_json(tree.root)},
                         {"threshold", tree.threshold},
                         {"components_after_pruning", tree.components_after_pruning},
                         {"joining_edges", tree.joining_edges},
                         {"total_cost", tree.total_cost},
                         {"weighted_depth", tree.weighted_depth},
                         {"nodes", nodes},
                         {"edges", edges}});
}

}  // namespace surfcap::similarity
