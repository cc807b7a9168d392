// surfcap-align: capture folder → aligned database. Steps (docs/cli.md): histograms,
// similarity (optionally one row block), merge, tree.
#include <spdlog/spdlog.h>

#include "surfcap/core/cli.hpp"
#include "surfcap/core/database.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/npy.hpp"
#include "surfcap/core/progress.hpp"
#include "surfcap/core/report.hpp"
#include "surfcap/similarity/preview.hpp"
#include "surfcap/similarity/similarity_files.hpp"
#include "surfcap/similarity/tree_quality.hpp"
#include "import_command.hpp"
#include "register_command.hpp"

namespace {

using namespace surfcap;

struct Arguments {
  std::string capture;
  std::string out;
  similarity::ShapeHistogramOptions histogram;
  similarity::SimilarityOptions similarity;
  std::string rows;
  std::string search = "fft";
  std::string root;
  double root_candidates = 0.25;
  std::string ground_truth;
};

void write_matrix_outputs(const std::filesystem::path& out, const similarity::FloatRows& matrix,
                          const similarity::FrameList& frames) {
  core::write_npy(similarity::matrix_path(out), matrix.data(),
                  {static_cast<std::size_t>(matrix.rows()), static_cast<std::size_t>(matrix.cols())});
  similarity::write_similarity_png(out / "similarity" / "matrix.png", matrix, frames.index());
}

void run_histograms(const Arguments& args, const core::ToolApp& app) {
  core::StageReport report("align.histograms");
  const core::Capture capture = core::read_capture(args.capture);
  {
    auto timer = report.time("check_capture");
    core::check_capture_files(capture);
  }
  similarity::HistogramSet set;
  {
    auto timer = report.time("histograms");
    core::ProgressReporter progress("histograms", static_cast<std::size_t>(capture.total_frames()));
    set = similarity::compute_histograms(capture, args.histogram, app.common().threads, progress.callback());
  }
  similarity::write_histograms(args.out, set);
  report.figures()["frames"] = set.histograms.rows();
  report.figures()["histogram_bins"] = set.histograms.cols();
  report.figures()["surfaces"] = similarity::surfaces_report(set);
  report.figures()["options"] = app.options_json();
  report.write(std::filesystem::path(args.out) / "report" / "histograms.json");
  spdlog::info("histograms of {} frames → {}/similarity/histograms.npy", set.histograms.rows(), args.out);
}

void run_similarity(const Arguments& args, const core::ToolApp& app) {
  core::StageReport report("align.similarity");
  const similarity::HistogramSet set = similarity::read_histograms(args.out);
  const similarity::FrameIndex index = set.frames.index();
  auto options = args.similarity;
  options.threads = app.common().threads;
  options.rotation_search =
      args.search == "exhaustive" ? similarity::RotationSearch::exhaustive : similarity::RotationSearch::fft;
  const auto [begin, end] =
      args.rows.empty() ? std::pair<long, long>{0, index.frames()} : similarity::parse_row_range(args.rows, index.frames());
  similarity::FloatRows rows;
  {
    auto timer = report.time("matrix_rows");
    core::ProgressReporter progress("similarity", static_cast<std::size_t>(end - begin));
    rows = similarity::similarity_rows(set.histograms, set.options, index, begin, end, options, progress.callback());
  }
  if (args.rows.empty()) {
    write_matrix_outputs(args.out, rows, set.frames);
    spdlog::info("similarity matrix {}×{} → {}", rows.rows(), rows.cols(), similarity::matrix_path(args.out).string());
  } else {
    const auto path = similarity::row_block_path(args.out, begin, end);
    core::write_npy(path, rows.data(), {static_cast<std::size_t>(rows.rows()), static_cast<std::size_t>(rows.cols())});
    spdlog::info("similarity rows {}:{} → {}", begin, end, path.string());
  }
  report.figures()["rows"] = {begin, end};
  report.figures()["frames"] = index.frames();
  report.figures()["options"] = app.options_json();
  const std::string name = args.rows.empty() ? "similarity-matrix.json" : "similarity-rows-" + std::to_string(begin) + "-" +
                                                                       std::to_string(end) + ".json";
  report.write(std::filesystem::path(args.out) / "report" / name);
}

void run_merge(const Arguments& args) {
  const similarity::HistogramSet set = similarity::read_histograms(args.out);
  const similarity::FloatRows matrix = similarity::merge_row_blocks(args.out, set.histograms.rows());
  write_matrix_outputs(args.out, matrix, set.frames);
  spdlog::info("merged row blocks → {}", similarity::matrix_path(args.out).string());
}

void run_tree(const Arguments& args, const core::ToolApp& app) {
  core::StageReport report("align.tree");
  const similarity::HistogramSet set = similarity::read_histograms(args.out);
  const long n = set.histograms.rows();
  const similarity::FloatRows matrix = similarity::read_matrix(args.out, n);
  std::optional<int> root;
  if (!args.root.empty()) root = static_cast<int>(set.frames.node(args.root));
  similarity::SimilarityTree tree;
  {
    auto timer = report.time("spanning_tree");
    tree = similarity::similarity_tree(matrix.cast<double>(), root, std::nullopt,
                                       similarity::wide_stance_roots(set.stance, args.root_candidates));
  }
  similarity::write_tree(args.out, tree, set.frames);
  similarity::write_similarity_png(std::filesystem::path(args.out) / "similarity" / "tree.png", matrix,
                                   set.frames.index(), &tree);
  auto& figures = report.figures();
  figures["frames"] = n;
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
  if (!args.ground_truth.empty()) {
    auto timer = report.time("ground_truth_quality");
    const core::AlignedDatabase truth = core::read_database(args.ground_truth);
    const Eigen::MatrixXd distances = similarity::ground_truth_distances(truth, set.frames, app.common().threads);
    const similarity::TreeQuality quality = similarity::tree_quality(tree, distances);
    figures["quality"] = {{"tree_deformation_m", quality.tree_deformation},
                          {"optimal_deformation_m", quality.optimal_deformation},
                          {"ratio", quality.ratio},
                          {"ground_truth", args.ground_truth}};
    spdlog::info("tree quality ratio {:.3f} (true deformation along the tree {:.3f} m, optimal {:.3f} m)",
                 quality.ratio, quality.tree_deformation, quality.optimal_deformation);
  }
  figures["options"] = app.options_json();
  report.write(std::filesystem::path(args.out) / "report" / "similarity.json");
  spdlog::info("tree of {} frames rooted at {} → {}/similarity/tree.json", n, set.frames.label(tree.root), args.out);
}

}  // namespace

int main(int argc, char** argv) {
  core::ToolApp app("surfcap-align", "surfcap-align: capture folder → aligned database (shape similarity tree, "
                                     "non-rigid alignment)");
  Arguments args;
  auto& cli = app.cli();
  cli.require_subcommand(1);

  auto* histograms = cli.add_subcommand("histograms", "Volumetric shape histogram of every captured frame");
  histograms->add_option("--capture", args.capture, "Capture folder (or its capture.json)")->required();
  histograms->add_option("--out", args.out, "Database folder to write into")->required();
  histograms->add_option("--voxel-size", args.histogram.voxel_size, "Volume sampling grid spacing (m)");
  histograms->add_option("--max-radius", args.histogram.max_radius, "Outer radius of the last shell (m)");
  histograms->add_option("--shells", args.histogram.shells, "Radial shells");
  histograms->add_option("--elevation-bins", args.histogram.elevation_bins, "Elevation sectors");
  histograms->add_option("--azimuth-order", args.histogram.azimuth_order, "Highest azimuth harmonic");

  auto* similarity_cmd = cli.add_subcommand("similarity", "Temporally filtered similarity matrix (or one row block)");
  similarity_cmd->add_option("--out", args.out, "Database folder holding similarity/histograms.npy")->required();
  similarity_cmd->add_option("--rows", args.rows, "Compute only rows a:b into similarity/rows/ (for farms)");
  similarity_cmd->add_option("--window", args.similarity.temporal_window, "Temporal filter half-width k (frames)")
      ->check(CLI::Range(0, 50));
  similarity_cmd->add_option("--search", args.search, "Rotation search: fft or exhaustive")
      ->check(CLI::IsMember({"fft", "exhaustive"}));

  auto* merge = cli.add_subcommand("merge", "Join similarity/rows/*.npy into similarity/matrix.npy");
  merge->add_option("--out", args.out, "Database folder")->required();

  auto* tree = cli.add_subcommand("tree", "Shape similarity tree (pruned minimum spanning tree)");
  tree->add_option("--out", args.out, "Database folder holding similarity/matrix.npy")->required();
  tools::add_root_options(tree, args.root, args.root_candidates);
  tree->add_option("--ground-truth", args.ground_truth,
                   "Ground-truth aligned database.json: report the tree's quality ratio");

  const tools::RegisterCommands registration(app);  // register, run
  const tools::ImportCommands imports(app);          // import-cameras, import-capture

  return app.run(argc, argv, [&] {
    if (*histograms) run_histograms(args, app);
    if (*similarity_cmd) run_similarity(args, app);
    if (*merge) run_merge(args);
    if (*tree) run_tree(args, app);
    registration.run();
    imports.run();
  });
}
