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
  bool surface_model = false;
  bool no_evaluation = false;
  bool edge_diagnostics = false;
  bool truth_arrays = false;
  double failure_residual_mm = 4;
  int preview_frames = 4;
  double preview_scale_mm = 10;
  similarity::ShapeHistogramOptions histogram;
  similarity::SimilarityOptions similarity;
};

namespace {

void add_alignment_options(CLI::App* cmd, RegisterCommands::State& state) {
  auto& options = state.options;
  auto& surface_model = state.surface_model;
  auto& no_evaluation = state.no_evaluation;
  auto& preview_frames = state.preview_frames;
  auto& preview_scale_mm = state.preview_scale_mm;
  auto& p = options.pairwise;
  cmd->add_option("--patches", p.initial_patches, "Rigid patches at the coarsest level (doubling per level)");
  cmd->add_option("--levels", p.levels, "Coarse-to-fine patch levels");
  cmd->add_option("--patch-icp-iterations", p.patch_icp_iterations, "ICP iterations per patch fit");
  cmd->add_option("--rotation-iterations", p.rotation_iterations, "Rotation updates (solves) per level");
  cmd->add_option("--patch-weight", p.patch_weight, "Soft-constraint weight of patch targets");
  cmd->add_option("--dense-iterations", p.dense_iterations, "Dense closest-point fitting iterations");
  cmd->add_option("--dense-weight", p.dense_weight, "Soft-constraint weight of dense targets");
  cmd->add_option("--normal-compatibility", p.normal_compatibility, "Minimum cosine between matched normals");
  cmd->add_option("--coarse-distance", p.coarse_distance,
                  "Correspondence gate at the coarsest level, fraction of the template height");
  cmd->add_option("--dense-distance", p.dense_distance_edges, "Dense-fit gate in template mean edge lengths");
  cmd->add_option("--color-sigma", p.color_sigma, "Photometric dense fit: colour σ (RGB 0..1; 0: geometry only)");
  cmd->add_option("--patch-color-scale", p.patch_color_scale,
                  "Colour-aware patch matching: metres per unit of RGB in the joint space (0: closest points)");
  cmd->add_option("--patch-color-levels", p.patch_color_levels, "Colour-aware matching at the coarsest N patch levels");
  cmd->add_option("--patch-color-gain", p.patch_color_gain,
                  "Colour-aware patch fit used when its colour disagreement is below this fraction of the closest-point fit's");
  cmd->add_option("--color-smoothing", p.color_smoothing, "Rings of vertex-colour smoothing for patch matching");
  cmd->add_option("--motion-prediction", options.motion_prediction,
                  "Predict a child from its next two aligned frames: parent + this × (parent − grandparent) (0: off)")
      ->check(CLI::Range(0.0, 2.0));
  cmd->add_option("--twin-prediction", options.twin_prediction,
                  "Also predict a child whose similarity cost to its parent's next frame is at most this fraction of "
                  "its cost to the parent (a cycle's twin; 0: next frames only)")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--prediction-levels", p.prediction_levels, "Patch levels that also try the motion-predicted start");
  cmd->add_option("--prediction-gain", p.prediction_gain,
                  "Predicted patch fit used when its mean distance is below this fraction of the other fit's");
  cmd->add_option("--feature-weight", p.feature_weight, "Weight of image feature matches (0: geometry only)");
  cmd->add_option("--coverage-weight", p.coverage_weight, "Weight of the coverage (reconstruction → template) pulls (0: off)");
  cmd->add_option("--flow-weight", p.flow.weight, "Weight of the appearance-flow targets (0: off)");
  cmd->add_option("--flow-same-camera", p.flow.same_camera,
                  "Render each camera's flow prediction from the same root camera where it sees the point");
  cmd->add_option("--flow-iterations", p.flow.iterations, "Appearance-flow iterations after the dense fit");
  cmd->add_option("--flow-patch-levels", p.flow.patch_levels, "Appearance flow also at the last N patch levels");
  cmd->add_option("--flow-stride", p.flow.stride, "Pixel step of the appearance-flow constraints");
  cmd->add_option("--flow-max-offset", p.flow.max_offset_edges,
                  "Appearance-flow targets farther than this from their template point are dropped (mean edges)");
  cmd->add_option("--features-per-image", p.features.max_per_image, "Strongest SIFT keypoints kept per image");
  cmd->add_option("--feature-ratio", p.features.ratio, "Ratio test of the feature matching");
  cmd->add_flag("!--no-images", options.images, "Geometry only: ignore the capture's camera images");
  cmd->add_option("--crease-weight", p.crease_weight,
                  "Weight of crease matching: rest-template rim vertices to the reconstruction's convex creases (0: off)");
  cmd->add_option("--crease-angle", p.crease_angle_deg, "Dihedral angle (degrees) above which a convex edge is a crease");
  cmd->add_option("--crease-distance", p.crease_distance_edges, "Crease matching gate in template mean edge lengths");
  cmd->add_option("--crease-straightness", p.crease_straightness,
                  "Match only straight crease stretches of the template: max sqrt(l2/l1) of nearby crease vertices (>= 1: all)");
  cmd->add_option("--crease-target-straightness", p.crease_target_straightness,
                  "The same filter on the reconstruction's creases (>= 1: all)");
  cmd->add_option("--crease-straight-radius", p.crease_straight_radius,
                  "Neighbourhood of the straightness test, fraction of the template height");
  cmd->add_option("--crease-patch-levels", p.crease_patch_levels, "Crease matching also at the last N patch levels");
  cmd->add_option("--heading-samples", p.heading_samples, "Headings tried when frames do not overlap rigidly");
  cmd->add_option("--interior-spacing", options.deformer.tetrahedra.interior_spacing_edges,
                  "Interior points of the tet mesh: grid spacing in template mean edges (≤ 0: none)");
  cmd->add_option("--failure-residual-mm", state.failure_residual_mm,
                  "Mean residual above which a frame is re-aligned from its next most similar aligned frame")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--max-uncovered", options.max_uncovered,
                  "Fraction of a reconstruction left uncovered by the aligned template above which a frame failed")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--max-stacked", options.max_stacked,
                  "Fraction of the template's vertices in stacked layers (laid onto a far part of itself) above which a frame failed")
      ->check(CLI::Range(1e-9, 1.0));
  cmd->add_option("--residual-growth", options.residual_growth,
                  "A frame whose mean residual exceeds this many times its parent's failed (0: off)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--retries", options.retries, "Alternative parents tried for a failed frame")->check(CLI::Range(0, 10));
  cmd->add_option("--entry-candidates", options.entry_candidates,
                  "An edge from another sequence is also aligned from the most similar frame of up to N other sequences")
      ->check(CLI::Range(0, 10));
  cmd->add_flag("--surface-model", surface_model, "Deform with a surface Laplacian instead of the tet volume");
  cmd->add_flag("--no-evaluation", no_evaluation, "Do not compare with ground_truth/ even if the capture has it");
  cmd->add_flag("--edge-diagnostics", state.edge_diagnostics,
                "With ground truth: also align every child from its TRUE parent (each edge's own error)");
  cmd->add_flag("--truth-arrays", state.truth_arrays,
                "With ground truth: also write report/truth_errors.npy and report/truth_observed.npy (per vertex; "
                "with --edge-diagnostics also report/edge_truth_errors.npy)");
  cmd->add_option("--preview-frames", preview_frames, "Frames in report/alignment.png (0: none)")
      ->check(CLI::Range(0, 8));
  cmd->add_option("--preview-scale-mm", preview_scale_mm, "Residual mapped to red in the preview (mm)")
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

/// Every child aligned again from its true parent: the error each edge introduces on its own,
/// beside the accumulated one (per frame, by depth, and the worst edges in the log).
void add_edge_diagnostics(const core::Capture& capture, const similarity::HistogramSet& set,
                          const align::AlignmentTree& tree, align::RegisterOptions options,
                          const align::TruthReference& truth, const align::TruthEvaluation& accumulated,
                          core::Json& per_frame, core::Json& figures, const std::filesystem::path& arrays) {
  const std::vector<std::string>& labels = tree.nodes;
  options.parent_surface = [&](long node) {
    const std::string& label = labels[static_cast<std::size_t>(node)];
    const auto colon = label.rfind(':');
    return truth.positions(label.substr(0, colon), std::stoi(label.substr(colon + 1)));
  };
  const align::Registration isolated = align::register_capture(capture, set.frames, tree, options);
  const align::TruthEvaluation own = align::evaluate_against_truth(truth, isolated);
  if (!arrays.empty()) write_truth_errors(arrays / "edge_truth_errors.npy", truth, isolated);
  std::vector<long> order;
  for (std::size_t node = 0; node < own.frames.size(); ++node) {
    per_frame[node]["edge_rms_m"] = own.frames[node].rms;
    per_frame[node]["edge_tangential_rms_m"] = own.frames[node].tangential_rms;
    order.push_back(static_cast<long>(node));
  }
  core::Json depth = core::Json::array();
  for (const auto& [d, rms_at] : own.rms_by_depth) depth.push_back({{"depth", d}, {"edge_rms_m", rms_at}});
  figures["ground_truth"]["edge_rms_m"] = own.rms;
  figures["ground_truth"]["edge_by_depth"] = depth;
  std::sort(order.begin(), order.end(), [&](long a, long b) {
    return own.frames[static_cast<std::size_t>(a)].rms > own.frames[static_cast<std::size_t>(b)].rms;
  });
  spdlog::info("edges aligned from the true parent: RMS {:.2f} mm (accumulated {:.2f} mm); worst edges:",
               1000 * own.rms, 1000 * accumulated.rms);
  for (std::size_t k = 0; k < std::min<std::size_t>(20, order.size()); ++k) {
    const long node = order[k];
    const auto& record = isolated.frames[static_cast<std::size_t>(node)];
    const auto true_at = [&](long n) { return options.parent_surface(n); };
    const double motion = record.parent < 0 ? 0.0 : std::sqrt((true_at(node) - true_at(record.parent)).rowwise().squaredNorm().mean());
    spdlog::info("  {} ← {} depth {}: edge {:.1f} mm (tangential {:.1f}; true motion {:.1f}), accumulated {:.1f} mm, heading {:.2f} rad",
                 labels[static_cast<std::size_t>(node)],
                 record.parent >= 0 ? labels[static_cast<std::size_t>(record.parent)] : std::string("-"), record.depth,
                 1000 * own.frames[static_cast<std::size_t>(node)].rms,
                 1000 * own.frames[static_cast<std::size_t>(node)].tangential_rms, 1000 * motion,
                 1000 * accumulated.frames[static_cast<std::size_t>(node)].rms, record.alignment.heading_change);
  }
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
  options.deformer.volumetric = !state.surface_model;
  options.failure_residual = state.failure_residual_mm / 1000;
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
                                      {"alignment", options.pairwise.to_json()},
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
    if (state.edge_diagnostics)
      add_edge_diagnostics(capture, set, tree, options, truth, evaluation, per_frame, figures,
                           state.truth_arrays ? out / "report" : std::filesystem::path());
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
