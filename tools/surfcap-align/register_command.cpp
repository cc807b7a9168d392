#include "register_command.hpp"

#include <spdlog/spdlog.h>

#include <cmath>
#include <memory>
#include <numeric>

#include "surfcap/align/alignment_report.hpp"
#include "surfcap/align/ground_truth_error.hpp"
#include "surfcap/align/tree_alignment.hpp"
#include "surfcap/core/database.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/npy.hpp"
#include "surfcap/core/option_table.hpp"
#include "surfcap/core/progress.hpp"
#include "surfcap/core/report.hpp"
#include "surfcap/core/version.hpp"
#include "surfcap/similarity/preview.hpp"
#include "surfcap/similarity/similarity_files.hpp"

namespace surfcap::tools {

struct RegisterCommands::State {
  CLI::App* register_cmd = nullptr;
  CLI::App* run_cmd = nullptr;
  std::string capture;
  std::string out;
  std::string root;
  double root_candidates = 0.25;
  align::RegisterOptions options;
  bool no_evaluation = false;
  bool truth_arrays = false;
  int preview_frames = 4;
  double preview_scale_mm = 10;
  similarity::ShapeHistogramOptions histogram;
  similarity::SimilarityOptions similarity;
};

namespace {

void add_alignment_options(CLI::App* cmd, RegisterCommands::State& state) {
  core::add_options(cmd, state.options);
  cmd->add_flag("--no-evaluation", state.no_evaluation, "Do not compare with ground_truth/ even if the capture has it");
  cmd->add_flag("--truth-arrays", state.truth_arrays,
                "With ground truth: also write report/truth_errors.npy and report/truth_observed.npy (per vertex)");
  cmd->add_option("--preview-frames", state.preview_frames, "Frames in report/alignment.png (0: none)")
      ->check(CLI::Range(0, 8));
  cmd->add_option("--preview-scale-mm", state.preview_scale_mm, "Residual mapped to red in the preview (mm)")
      ->check(CLI::PositiveNumber);
}

/// Per node (report order) and template vertex: aligned − true world position, float32 [nodes, n, 3].
void write_truth_errors(const std::filesystem::path& path, const align::TruthReference& truth,
                        const align::Registration& registration) {
  const std::size_t nodes = registration.frames.size();
  const auto n = static_cast<std::size_t>(registration.database.template_mesh.vertex_count());
  std::vector<float> errors;
  errors.reserve(nodes * n * 3);
  for (std::size_t node = 0; node < nodes; ++node) {
    const auto& record = registration.frames[node];
    const Eigen::MatrixXd error = registration.world_positions[node] - truth.positions(record.sequence, record.frame);
    for (std::size_t v = 0; v < n; ++v)
      for (int k = 0; k < 3; ++k) errors.push_back(static_cast<float>(error(static_cast<Eigen::Index>(v), k)));
  }
  core::write_npy(path, errors.data(), {nodes, n, 3});
}

/// truth_errors.npy (above) and whether a camera sees the true location, truth_observed.npy
/// (uint8 [nodes, n]).
void write_truth_arrays(const std::filesystem::path& folder, const align::TruthReference& truth,
                        const align::Registration& registration, const align::TruthEvaluation& evaluation) {
  const std::size_t nodes = registration.frames.size();
  const auto n = static_cast<std::size_t>(registration.database.template_mesh.vertex_count());
  write_truth_errors(folder / "truth_errors.npy", truth, registration);
  std::vector<std::uint8_t> observed;
  observed.reserve(nodes * n);
  for (std::size_t node = 0; node < nodes; ++node)
    for (std::size_t v = 0; v < n; ++v) observed.push_back(evaluation.frames[node].observed[v] ? 1 : 0);
  core::write_npy(folder / "truth_observed.npy", observed.data(), {nodes, n});
}

void register_frames(const RegisterCommands::State& state, const core::ToolApp& app, core::StageReport& report) {
  const std::filesystem::path out = state.out;
  const similarity::HistogramSet set = similarity::read_histograms(out);
  const std::string capture_path = state.capture.empty() ? set.capture : state.capture;
  if (capture_path.empty()) throw core::bad_arguments("register: --capture is required (histograms.json names none)");
  const core::Capture capture = core::read_capture(capture_path);
  const align::AlignmentTree tree = align::read_alignment_tree(out, set.histograms.rows());
  align::RegisterOptions options = state.options;
  options.threads = app.common().threads;
  Eigen::MatrixXd costs;
  if (std::filesystem::exists(similarity::matrix_path(out))) {
    costs = similarity::read_matrix(out, set.histograms.rows()).cast<double>();
    options.costs = &costs;
  } else {
    spdlog::warn("{} is missing: failed alignments cannot be retried from other frames",
                 similarity::matrix_path(out).string());
  }
  align::Registration registration;
  {
    auto timer = report.time("alignment");
    core::ProgressReporter progress("align", static_cast<std::size_t>(set.histograms.rows()));
    registration = align::register_capture(capture, set.frames, tree, options, progress.callback());
  }
  registration.database.provenance = {{"tool", "surfcap-align register"},
                                      {"version", std::string(core::version())},
                                      {"options", app.provenance_json()},
                                      {"alignment", options.to_json()},
                                      {"inputs", {{"capture", capture_path}, {"tree", (out / "similarity" / "tree.json").string()}}}};
  {
    auto timer = report.time("write_database");
    core::write_database(out, registration.database);
  }
  auto& figures = report.figures();
  figures.update(align::alignment_figures(registration));
  if (!state.no_evaluation && align::ground_truth_file(capture)) {
    auto timer = report.time("ground_truth_error");
    const align::TruthReference truth(capture, registration.database);
    const align::TruthEvaluation evaluation = align::evaluate_against_truth(truth, registration);
    figures["ground_truth"] = evaluation.to_json(registration);
    core::Json per_frame = core::Json::array();
    for (const auto& frame : evaluation.frames)
      per_frame.push_back({{"rms_m", frame.rms}, {"max_m", frame.max}, {"normal_rms_m", frame.normal_rms},
                           {"tangential_rms_m", frame.tangential_rms}, {"observed_fraction", frame.observed_fraction}});
    figures["ground_truth"]["frames"] = per_frame;
    if (state.truth_arrays) write_truth_arrays(out / "report", truth, registration, evaluation);
    if (state.preview_frames > 0) {
      // The frames worst against the truth, coloured by each vertex's true error.
      std::vector<long> order(evaluation.frames.size());
      std::iota(order.begin(), order.end(), 0L);
      std::stable_sort(order.begin(), order.end(), [&](long a, long b) {
        return evaluation.frames[static_cast<std::size_t>(a)].rms > evaluation.frames[static_cast<std::size_t>(b)].rms;
      });
      order.resize(std::min<std::size_t>(order.size(), static_cast<std::size_t>(state.preview_frames)));
      std::vector<Eigen::VectorXd> errors;
      for (const long node : order) {
        const auto& record = registration.frames[static_cast<std::size_t>(node)];
        errors.push_back((registration.world_positions[static_cast<std::size_t>(node)] -
                          truth.positions(record.sequence, record.frame))
                             .rowwise()
                             .norm());
      }
      align::write_value_preview(out / "report" / "truth_error.png", registration, order, errors,
                                 5 * state.preview_scale_mm / 1000, "from the true position");
    }
    spdlog::info("error against ground truth: RMS {:.2f} mm ({:.3f}% of {:.2f} m; normal {:.2f}, tangential {:.2f} mm), "
                 "worst frame {} {:.2f} mm ({:.3f}%)",
                 1000 * evaluation.rms, 100 * evaluation.rms / evaluation.height, evaluation.height,
                 1000 * evaluation.normal_rms, 1000 * evaluation.tangential_rms,
                 figures["ground_truth"]["worst_frame"].get<std::string>(), 1000 * evaluation.worst_frame_rms,
                 100 * evaluation.worst_frame_rms / evaluation.height);
    if (evaluation.observed_fraction > 0)
      spdlog::info("  seen by a camera ({:.1f}% of the vertex-frames) {:.2f} mm RMS, unseen {:.2f} mm RMS",
                   100 * evaluation.observed_fraction, 1000 * evaluation.observed_rms, 1000 * evaluation.unobserved_rms);
  }
  if (state.preview_frames > 0) {
    auto timer = report.time("preview");
    align::write_residual_preview(out / "report" / "alignment.png", capture, registration,
                                  align::preview_nodes(registration, state.preview_frames),
                                  state.preview_scale_mm / 1000);
  }
  figures["options"] = app.options_json();
  spdlog::info("aligned {} frames (mean residual {:.2f} mm) → {}/database.json", registration.frames.size(),
               1000 * figures["summary"]["mean_residual_m"].get<double>(), out.string());
}

void run_similarity_chain(const RegisterCommands::State& state, const core::ToolApp& app, core::StageReport& report) {
  const std::filesystem::path out = state.out;
  const core::Capture capture = core::read_capture(state.capture);
  core::check_capture_files(capture);
  similarity::HistogramSet set;
  {
    auto timer = report.time("histograms");
    core::ProgressReporter progress("histograms", static_cast<std::size_t>(capture.total_frames()));
    set = similarity::compute_histograms(capture, state.histogram, app.common().threads, progress.callback());
  }
  similarity::write_histograms(out, set);
  const similarity::FrameIndex index = set.frames.index();
  similarity::FloatRows matrix;
  {
    auto timer = report.time("similarity");
    auto options = state.similarity;
    options.threads = app.common().threads;
    core::ProgressReporter progress("similarity", static_cast<std::size_t>(index.frames()));
    matrix = similarity::similarity_rows(set.histograms, set.options, index, 0, index.frames(), options,
                                         progress.callback());
  }
  core::write_npy(similarity::matrix_path(out), matrix.data(),
                  {static_cast<std::size_t>(matrix.rows()), static_cast<std::size_t>(matrix.cols())});
  similarity::write_similarity_png(out / "similarity" / "matrix.png", matrix, index);
  similarity::SimilarityTree tree;
  {
    auto timer = report.time("tree");
    std::optional<int> root;
    if (!state.root.empty()) root = static_cast<int>(set.frames.node(state.root));
    tree = similarity::similarity_tree(matrix.cast<double>(), root, std::nullopt,
                                       similarity::wide_stance_roots(set.stance, state.root_candidates));
  }
  similarity::write_tree(out, tree, set.frames);
  similarity::write_similarity_png(out / "similarity" / "tree.png", matrix, index, &tree);
  report.figures()["tree"] = {{"root", set.frames.label(tree.root)},
                              {"root_stance", set.stance[static_cast<std::size_t>(tree.root)]},
                              {"threshold", tree.threshold},
                              {"components_after_pruning", tree.components_after_pruning},
                              {"max_depth", *std::max_element(tree.depth.begin(), tree.depth.end())}};
}

}  // namespace

void add_root_options(CLI::App* command, std::string& root, double& root_candidates) {
  command->add_option("--root", root,
                      "Root frame as <sequence>:<frame> (default: minimal weighted depth among the widest-stance frames)");
  command->add_option("--root-candidates", root_candidates,
                      "Automatic root: among this fraction of the frames with the widest stance (1: every frame)")
      ->check(CLI::PositiveNumber & CLI::Range(0.0, 1.0));
}

RegisterCommands::RegisterCommands(core::ToolApp& app) : app_(app), state_(std::make_unique<State>()) {
  auto& cli = app.cli();
  State& s = *state_;
  s.register_cmd = cli.add_subcommand("register", "Non-rigid alignment along similarity/tree.json → database.json");
  s.register_cmd->add_option("--out", s.out, "Database folder holding similarity/ (written into)")->required();
  s.register_cmd->add_option("--capture", s.capture, "Capture folder (default: the one histograms.json names)");
  add_alignment_options(s.register_cmd, s);

  s.run_cmd = cli.add_subcommand("run", "histograms → similarity → tree → register in one go");
  s.run_cmd->add_option("--capture", s.capture, "Capture folder (or its capture.json)")->required();
  s.run_cmd->add_option("--out", s.out, "Database folder to write")->required();
  add_root_options(s.run_cmd, s.root, s.root_candidates);
  s.run_cmd->add_option("--voxel-size", s.histogram.voxel_size, "Volume sampling grid spacing (m)");
  s.run_cmd->add_option("--window", s.similarity.temporal_window, "Temporal filter half-width k (frames)")
      ->check(CLI::Range(0, 50));
  add_alignment_options(s.run_cmd, s);
}

RegisterCommands::~RegisterCommands() = default;

void RegisterCommands::run() const {
  const State& s = *state_;
  if (*s.run_cmd) {
    core::StageReport report("align.run");
    run_similarity_chain(s, app_, report);
    register_frames(s, app_, report);
    report.write(std::filesystem::path(s.out) / "report" / "alignment.json");
  } else if (*s.register_cmd) {
    core::StageReport report("align.register");
    register_frames(s, app_, report);
    report.write(std::filesystem::path(s.out) / "report" / "alignment.json");
  }
}

}  // namespace surfcap::tools
