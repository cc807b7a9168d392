#include "surfcap/evaluation/register_stage.hpp"

#include <spdlog/spdlog.h>

#include <optional>

#include "surfcap/align/registration_parts.hpp"
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

/// What every registration job reads: the frames, the capture, the tree and the similarity costs.
struct RegisterInputs {
  similarity::HistogramSet set;
  std::string capture_path;
  core::Capture capture;
  align::AlignmentTree tree;
  Eigen::MatrixXd costs;
  align::RegisterOptions alignment;  ///< the options, pointing at `costs` when there is a matrix

  RegisterInputs(const std::filesystem::path& out, const RegisterStageOptions& options)
      : set(similarity::read_histograms(out)),
        capture_path(options.capture.empty() ? set.capture : options.capture),
        alignment(options.alignment) {
    if (capture_path.empty()) throw core::bad_arguments("register: --capture is required (histograms.json names none)");
    capture = core::read_capture(capture_path);
    tree = align::read_alignment_tree(out, set.histograms.rows());
    if (std::filesystem::exists(similarity::matrix_path(out))) {
      costs = similarity::read_matrix(out, set.histograms.rows()).cast<double>();
      alignment.costs = &costs;
    } else {
      spdlog::warn("{} is missing: failed alignments cannot be retried from other frames",
                   similarity::matrix_path(out).string());
    }
  }
  RegisterInputs(const RegisterInputs&) = delete;
  RegisterInputs& operator=(const RegisterInputs&) = delete;
};

/// The aligned database with its provenance, written into `out`.
void write_registration(const std::filesystem::path& out, const RegisterInputs& inputs,
                        align::Registration& registration, const RegisterStageOptions& options,
                        core::StageReport& report) {
  registration.database.provenance = {{"tool", "surfcap-align register"},
                                      {"version", std::string(core::version())},
                                      {"options", options.provenance_json},
                                      {"alignment", inputs.alignment.to_json()},
                                      {"inputs", {{"capture", inputs.capture_path}, {"tree", (out / "similarity" / "tree.json").string()}}}};
  auto timer = report.time("write_database");
  core::write_database(out, registration.database);
}

/// The error against the ground truth: figures, arrays and the preview of the worst frames.
void evaluate(const std::filesystem::path& out, const core::Capture& capture, const align::Registration& registration,
              const ReportOptions& options, core::StageReport& report) {
  auto timer = report.time("ground_truth_error");
  const TruthReference truth(capture, registration.database, registration.template_observed_vertices,
                             registration.template_dropped_vertices);
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

namespace {

core::Json partition_figures(const align::TreePartition& partition) {
  return {{"trunk_frames", partition.trunk_size}, {"units", partition.units()}, {"unit_bound", partition.bound},
          {"unit_frames", partition.unit_sizes}};
}

/// The whole registration's outputs from the registration: database, figures, ground truth, previews.
void finish_stage(const std::filesystem::path& out, const RegisterInputs& inputs, align::Registration& registration,
                  const RegisterStageOptions& options, core::StageReport& report) {
  write_registration(out, inputs, registration, options, report);
  auto& figures = report.figures();
  figures.update(alignment_figures(registration));
  figures["partition"] = partition_figures(align::partition_tree(inputs.tree));
  if (options.report.evaluation && ground_truth_file(inputs.capture))
    evaluate(out, inputs.capture, registration, options.report, report);
  if (options.report.preview_frames > 0) {
    auto timer = report.time("preview");
    const std::vector<long> nodes = preview_nodes(registration, options.report.preview_frames);
    write_residual_preview(out / "report" / "alignment.png", inputs.capture, registration, nodes,
                           options.report.preview_scale_mm / 1000);
    if (has_observation_figures(registration))
      write_observation_preview(out / "report" / "observation.png", inputs.capture, registration, nodes);
  }
  figures["options"] = options.options_json;
  report.write(out / "report" / "alignment.json");
  spdlog::info("aligned {} frames (mean residual {:.2f} mm) → {}/database.json", registration.frames.size(),
               1000 * figures["summary"]["mean_residual_m"].get<double>(), out.string());
}

/// A trunk or shard job: aligns its nodes and writes its part and its report.
void run_part_job(const std::filesystem::path& out, const RegisterInputs& inputs, const RegisterStageOptions& options) {
  const bool trunk = options.job.kind == RegisterJob::Kind::trunk;
  const std::string name =
      trunk ? "trunk" : "shard-" + std::to_string(options.job.shard) + "-of-" + std::to_string(options.job.shards);
  core::StageReport report(options.stage + "." + (trunk ? "trunk" : "shard"));
  const align::TreePartition partition = align::partition_tree(inputs.tree);
  align::PartLabel label;
  if (!trunk) {
    label = {options.job.shard, options.job.shards,
             align::group_units(partition, options.job.shards)[static_cast<std::size_t>(options.job.shard - 1)]};
  }
  const std::vector<long> nodes = align::partition_nodes(partition, label.units, trunk);
  const core::Json context = align::part_context(out, inputs.capture_path, inputs.alignment, partition);
  core::ProgressReporter progress("align " + name, nodes.size());
  std::optional<align::TreeRegistration> registration;
  {
    auto timer = report.time("template");
    registration.emplace(inputs.capture, inputs.set.frames, inputs.tree, inputs.alignment, progress.callback());
  }
  if (trunk) {
    auto timer = report.time("alignment");
    registration->align_trunk();
  } else {
    {
      auto timer = report.time("read_trunk");
      registration->load(align::read_registration_part(align::trunk_part_path(out), {}, context,
                                                       align::partition_nodes(partition, {}, true),
                                                       registration->summary().volume_vertices));
    }
    auto timer = report.time("alignment");
    registration->align_units(label.units);
  }
  progress.finish();
  const align::RegistrationPart part = registration->part(nodes);
  const auto path = trunk ? align::trunk_part_path(out) : align::shard_part_path(out, label.shard, label.shards);
  {
    auto timer = report.time("write_part");
    align::write_registration_part(path, label, context, part, registration->summary());
  }
  auto& figures = report.figures();
  figures["partition"] = partition_figures(partition);
  figures["job"] = {{"part", path.filename().string()}, {"units", label.units}, {"frames", nodes.size()}};
  double residual = 0;
  for (const auto& record : part.records) residual += record.alignment.mean_residual;
  figures["job"]["mean_residual_m"] = nodes.empty() ? 0.0 : residual / static_cast<double>(nodes.size());
  figures["options"] = options.options_json;
  report.write(out / "report" / ("register-" + name + ".json"));
  spdlog::info("aligned {} frames ({}) → {}", nodes.size(), name, path.string());
}

/// The merge: the trunk's and the shards' parts → what the whole registration writes.
void run_merge_job(const std::filesystem::path& out, const RegisterInputs& inputs, const RegisterStageOptions& options) {
  core::StageReport report(options.stage);
  const align::TreePartition partition = align::partition_tree(inputs.tree);
  const core::Json context = align::part_context(out, inputs.capture_path, inputs.alignment, partition);
  const int shards = options.job.shards;
  const auto groups = align::group_units(partition, shards);
  align::Registration summary;
  std::vector<align::RegistrationPart> parts;
  {
    auto timer = report.time("read_parts");
    parts.push_back(align::read_registration_part(align::trunk_part_path(out), {}, context,
                                                  align::partition_nodes(partition, {}, true), 0, &summary));
    for (int shard = 1; shard <= shards; ++shard) {
      const align::PartLabel label{shard, shards, groups[static_cast<std::size_t>(shard - 1)]};
      parts.push_back(align::read_registration_part(align::shard_part_path(out, shard, shards), label, context,
                                                    align::partition_nodes(partition, label.units, false),
                                                    summary.volume_vertices));
    }
  }
  std::vector<const align::RegistrationPart*> pointers;
  for (const auto& part : parts) pointers.push_back(&part);
  align::Registration registration;
  {
    auto timer = report.time("assemble");
    registration = align::assemble_registration(inputs.capture, inputs.set.frames, inputs.tree, pointers, summary);
  }
  report.figures()["registration_jobs"] = {{"shards", shards}};
  finish_stage(out, inputs, registration, options, report);
}

}  // namespace

void run_register_stage(const std::filesystem::path& out, const RegisterStageOptions& options) {
  options.alignment.validate();
  const RegisterInputs inputs(out, options);
  switch (options.job.kind) {
    case RegisterJob::Kind::trunk:
    case RegisterJob::Kind::shard:
      run_part_job(out, inputs, options);
      return;
    case RegisterJob::Kind::merge:
      run_merge_job(out, inputs, options);
      return;
    case RegisterJob::Kind::whole:
      break;
  }
  core::StageReport report(options.stage);
  align::Registration registration;
  {
    auto timer = report.time("alignment");
    core::ProgressReporter progress("align", static_cast<std::size_t>(inputs.set.histograms.rows()));
    registration = align::register_capture(inputs.capture, inputs.set.frames, inputs.tree, inputs.alignment,
                                           progress.callback());
  }
  finish_stage(out, inputs, registration, options, report);
}

}  // namespace surfcap::evaluation
