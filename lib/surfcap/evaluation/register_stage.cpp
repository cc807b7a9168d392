#include "surfcap/evaluation/register_stage.hpp"

#include <spdlog/spdlog.h>

#include "surfcap/core/database.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/progress.hpp"
#include "surfcap/core/report.hpp"
#include "surfcap/core/version.hpp"
#include "surfcap/evaluation/alignment_report.hpp"
#include "surfcap/evaluation/ground_truth_error.hpp"
#include "surfcap/evaluation/truth_outputs.hpp"
#include "surfcap/similarity/similarity_files.hpp"

namespace surfcap::evaluation {

namespace {

/// The aligned database with its provenance, written into `out`.
align::Registration register_and_write(const std::filesystem::path& out, const core::Capture& capture,
                                       const std::string& capture_path, const similarity::HistogramSet& set,
                                       const RegisterStageOptions& options, core::StageReport& report) {
  const align::AlignmentTree tree = align::read_alignment_tree(out, set.histograms.rows());
  align::RegisterOptions alignment = options.alignment;
  Eigen::MatrixXd costs;
  if (std::filesystem::exists(similarity::matrix_path(out))) {
    costs = similarity::read_matrix(out, set.histograms.rows()).cast<double>();
    alignment.costs = &costs;
  } else {
    spdlog::warn("{} is missing: failed alignments cannot be retried from other frames",
                 similarity::matrix_path(out).string());
  }
  align::Registration registration;
  {
    auto timer = report.time("alignment");
    core::ProgressReporter progress("align", static_cast<std::size_t>(set.histograms.rows()));
    registration = align::register_capture(capture, set.frames, tree, alignment, progress.callback());
  }
  registration.database.provenance = {{"tool", "surfcap-align register"},
                                      {"version", std::string(core::version())},
                                      {"options", options.provenance_json},
                                      {"alignment", alignment.to_json()},
                                      {"inputs", {{"capture", capture_path}, {"tree", (out / "similarity" / "tree.json").string()}}}};
  {
    auto timer = report.time("write_database");
    core::write_database(out, registration.database);
  }
  return registration;
}

/// The error against the ground truth: figures, arrays and the preview of the worst frames.
void evaluate(const std::filesystem::path& out, const core::Capture& capture, const align::Registration& registration,
              const ReportOptions& options, core::StageReport& report) {
  auto timer = report.time("ground_truth_error");
  const TruthReference truth(capture, registration.database);
  const TruthEvaluation evaluation = evaluate_against_truth(truth, registration);
  auto& figures = report.figures();
  figures["ground_truth"] = evaluation.to_json(registration);
  core::Json per_frame = core::Json::array();
  for (const auto& frame : evaluation.frames)
    per_frame.push_back({{"rms_m", frame.rms}, {"max_m", frame.max}, {"normal_rms_m", frame.normal_rms},
                         {"tangential_rms_m", frame.tangential_rms}, {"observed_fraction", frame.observed_fraction}});
  figures["ground_truth"]["frames"] = per_frame;
  if (options.truth_arrays) write_truth_arrays(out / "report", truth, registration, evaluation);
  if (options.preview_frames > 0)
    write_truth_preview(out / "report" / "truth_error.png", truth, registration, evaluation, options.preview_frames,
                        5 * options.preview_scale_mm / 1000);
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

}  // namespace

void run_register_stage(const std::filesystem::path& out, const RegisterStageOptions& options) {
  options.alignment.validate();
  core::StageReport report(options.stage);
  const similarity::HistogramSet set = similarity::read_histograms(out);
  const std::string capture_path = options.capture.empty() ? set.capture : options.capture;
  if (capture_path.empty()) throw core::bad_arguments("register: --capture is required (histograms.json names none)");
  const core::Capture capture = core::read_capture(capture_path);
  const align::Registration registration = register_and_write(out, capture, capture_path, set, options, report);
  auto& figures = report.figures();
  figures.update(alignment_figures(registration));
  if (options.report.evaluation && ground_truth_file(capture)) evaluate(out, capture, registration, options.report, report);
  if (options.report.preview_frames > 0) {
    auto timer = report.time("preview");
    write_residual_preview(out / "report" / "alignment.png", capture, registration,
                           preview_nodes(registration, options.report.preview_frames),
                           options.report.preview_scale_mm / 1000);
  }
  figures["options"] = options.options_json;
  report.write(out / "report" / "alignment.json");
  spdlog::info("aligned {} frames (mean residual {:.2f} mm) → {}/database.json", registration.frames.size(),
               1000 * figures["summary"]["mean_residual_m"].get<double>(), out.string());
}

}  // namespace surfcap::evaluation
