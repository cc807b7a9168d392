#include "surfcap/similarity/similarity_stages.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "surfcap/core/capture.hpp"
#include "surfcap/core/database.hpp"
#include "surfcap/core/npy.hpp"
#include "surfcap/core/progress.hpp"
#include "surfcap/core/report.hpp"
#include "surfcap/similarity/preview.hpp"
#include "surfcap/similarity/similarity_files.hpp"
#include "surfcap/similarity/spanning_tree.hpp"
#include "surfcap/similarity/tree_quality.hpp"

namespace surfcap::similarity {

namespace {

void write_matrix_outputs(const std::filesystem::path& out, const FloatRows& matrix, const FrameList& frames) {
  core::write_npy(matrix_path(out), matrix.data(),
                  {static_cast<std::size_t>(matrix.rows()), static_cast<std::size_t>(matrix.cols())});
  write_similarity_png(out / "similarity" / "matrix.png", matrix, frames.index());
}

/// The tree's figures; the true deformation along it when a ground truth is given.
void tree_figures(core::StageReport& report, const SimilarityTree& tree, const HistogramSet& set,
                  const SimilarityStageOptions& options) {
  auto& figures = report.figures();
  figures["frames"] = set.histograms.rows();
  figures["root"] = set.frames.label(tree.root);
  if (!set.stance.empty()) figures["root_stance"] = set.stance[static_cast<std::size_t>(tree.root)];
  figures["threshold"] = tree.threshold;
  figures["components_after_pruning"] = tree.components_after_pruning;
  figures["joining_edges"] = tree.joining_edges;
  figures["total_cost"] = tree.total_cost;
  figures["weighted_depth"] = tree.weighted_depth;
  figures["max_depth"] = *std::max_element(tree.depth.begin(), tree.depth.end());
  if (tree.components_after_pruning > 1)
    spdlog::warn("pruning at threshold {:.4g} split the frames into {} groups; joined them with {} cheapest edges",
                 tree.threshold, tree.components_after_pruning, tree.joining_edges);
  if (options.ground_truth.empty()) return;
  auto timer = report.time("ground_truth_quality");
  const core::AlignedDatabase truth = core::read_database(options.ground_truth);
  const Eigen::MatrixXd distances = ground_truth_distances(truth, set.frames, options.threads);
  const TreeQuality quality = tree_quality(tree, distances);
  figures["quality"] = {{"tree_deformation_m", quality.tree_deformation},
                        {"optimal_deformation_m", quality.optimal_deformation},
                        {"ratio", quality.ratio},
                        {"ground_truth", options.ground_truth}};
  spdlog::info("tree quality ratio {:.3f} (true deformation along the tree {:.3f} m, optimal {:.3f} m)", quality.ratio,
               quality.tree_deformation, quality.optimal_deformation);
}

}  // namespace

void run_histograms_stage(const std::filesystem::path& capture_path, const std::filesystem::path& out,
                          const SimilarityStageOptions& options) {
  core::StageReport report("align.histograms");
  const core::Capture capture = core::read_capture(capture_path);
  {
    auto timer = report.time("check_capture");
    core::check_capture_files(capture);
  }
  HistogramSet set;
  {
    auto timer = report.time("histograms");
    core::ProgressReporter progress("histograms", static_cast<std::size_t>(capture.total_frames()));
    set = compute_histograms(capture, options.histogram, options.threads, progress.callback());
  }
  write_histograms(out, set);
  report.figures()["frames"] = set.histograms.rows();
  report.figures()["histogram_bins"] = set.histograms.cols();
  report.figures()["surfaces"] = surfaces_report(set);
  report.figures()["options"] = options.options_json;
  report.write(out / "report" / "histograms.json");
  spdlog::info("histograms of {} frames → {}/similarity/histograms.npy", set.histograms.rows(), out.string());
}

void run_similarity_stage(const std::filesystem::path& out, const SimilarityStageOptions& options) {
  core::StageReport report("align.similarity");
  const HistogramSet set = read_histograms(out);
  const FrameIndex index = set.frames.index();
  SimilarityOptions similarity = options.similarity;
  similarity.threads = options.threads;
  similarity.rotation_search = options.search == "exhaustive" ? RotationSearch::exhaustive : RotationSearch::fft;
  const auto [begin, end] =
      options.rows.empty() ? std::pair<long, long>{0, index.frames()} : parse_row_range(options.rows, index.frames());
  FloatRows rows;
  {
    auto timer = report.time("matrix_rows");
    core::ProgressReporter progress("similarity", static_cast<std::size_t>(end - begin));
    rows = similarity_rows(set.histograms, set.options, index, begin, end, similarity, progress.callback());
  }
  if (options.rows.empty()) {
    write_matrix_outputs(out, rows, set.frames);
    spdlog::info("similarity matrix {}×{} → {}", rows.rows(), rows.cols(), matrix_path(out).string());
  } else {
    const auto path = row_block_path(out, begin, end);
    core::write_npy(path, rows.data(), {static_cast<std::size_t>(rows.rows()), static_cast<std::size_t>(rows.cols())});
    spdlog::info("similarity rows {}:{} → {}", begin, end, path.string());
  }
  report.figures()["rows"] = {begin, end};
  report.figures()["frames"] = index.frames();
  report.figures()["options"] = options.options_json;
  const std::string name = options.rows.empty() ? "similarity-matrix.json"
                                                : "similarity-rows-" + std::to_string(begin) + "-" +
                                                      std::to_string(end) + ".json";
  report.write(out / "report" / name);
}

void run_merge_stage(const std::filesystem::path& out) {
  core::StageReport report("align.merge");
  const HistogramSet set = read_histograms(out);
  FloatRows matrix;
  {
    auto timer = report.time("merge");
    matrix = merge_row_blocks(out, set.histograms.rows());
  }
  write_matrix_outputs(out, matrix, set.frames);
  report.figures()["frames"] = set.histograms.rows();
  report.write(out / "report" / "similarity-merge.json");
  spdlog::info("merged row blocks → {}", matrix_path(out).string());
}

void run_tree_stage(const std::filesystem::path& out, const SimilarityStageOptions& options) {
  core::StageReport report("align.tree");
  const HistogramSet set = read_histograms(out);
  const long n = set.histograms.rows();
  const FloatRows matrix = read_matrix(out, n);
  std::optional<int> root;
  if (!options.root.empty()) root = static_cast<int>(set.frames.node(options.root));
  SimilarityTree tree;
  {
    auto timer = report.time("spanning_tree");
    tree = similarity_tree(matrix, root, std::nullopt,
                           wide_stance_roots(set.stance, options.root_candidates));
  }
  write_tree(out, tree, set.frames);
  write_similarity_png(out / "similarity" / "tree.png", matrix, set.frames.index(), &tree);
  tree_figures(report, tree, set, options);
  report.figures()["options"] = options.options_json;
  report.write(out / "report" / "similarity.json");
  spdlog::info("tree of {} frames rooted at {} → {}/similarity/tree.json", n, set.frames.label(tree.root), out.string());
}

void run_similarity_chain(const std::filesystem::path& capture, const std::filesystem::path& out,
                          const SimilarityStageOptions& options) {
  SimilarityStageOptions whole = options;
  whole.rows.clear();
  run_histograms_stage(capture, out, whole);
  run_similarity_stage(out, whole);
  run_tree_stage(out, whole);
}

}  // namespace surfcap::similarity
