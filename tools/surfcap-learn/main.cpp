// surfcap-learn: learnt part-based models from an aligned database (tejera2013 §IV-A).
// Glue only: options → lib/surfcap/learn → files + report.
#include <spdlog/spdlog.h>

#include <filesystem>

#include "surfcap/core/cli.hpp"
#include "surfcap/core/database.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/progress.hpp"
#include "surfcap/core/report.hpp"
#include "surfcap/core/version.hpp"
#include "surfcap/learn/array_database.hpp"
#include "surfcap/learn/automatic_parts.hpp"
#include "surfcap/learn/example_selection.hpp"
#include "surfcap/learn/leave_out.hpp"
#include "surfcap/learn/part_model.hpp"
#include "surfcap/learn/parts_preview.hpp"

namespace fs = std::filesystem;
using namespace surfcap;

namespace {

struct Input {
  std::string database, template_mesh, positions;
  std::string parts_config;
  int auto_parts = 0;
  learn::AutomaticPartsOptions automatic;
};

void add_input_options(CLI::App* app, Input& in) {
  app->add_option("--database", in.database, "aligned database (database.json)");
  app->add_option("--template", in.template_mesh, "template mesh, with --positions instead of --database");
  app->add_option("--positions", in.positions, "float [T, V, 3] .npy of vertex positions (one sequence)");
  app->add_option("--parts", in.parts_config, "parts config (e.g. configs/parts/human6.json)");
  app->add_option("--auto-parts", in.auto_parts, "decompose automatically into this many parts (no --parts)");
  app->add_option("--overlap", in.automatic.overlap, "automatic parts: overlap in metres")->capture_default_str();
}

core::AlignedDatabase load_database(const Input& in) {
  if (!in.database.empty()) return core::read_database(in.database);
  if (in.template_mesh.empty() || in.positions.empty())
    throw core::bad_arguments("give --database, or --template and --positions");
  return learn::database_from_positions(in.template_mesh, in.positions);
}

learn::PartSet load_parts(const Input& in, const core::AlignedDatabase& db, const std::vector<learn::ExampleFrame>& examples,
                          int threads) {
  if (!in.parts_config.empty() && in.auto_parts > 0) throw core::bad_arguments("--parts and --auto-parts exclude each other");
  if (!in.parts_config.empty()) return learn::read_part_config(in.parts_config, db.template_mesh);
  if (in.auto_parts <= 0) throw core::bad_arguments("give --parts config.json or --auto-parts N");
  learn::AutomaticPartsOptions options = in.automatic;
  options.parts = in.auto_parts;
  options.threads = threads;
  return learn::automatic_parts(db, examples, options);
}

}  // namespace

int main(int argc, char** argv) {
  core::ToolApp app("surfcap-learn", "Learn part-based Laplacian deformation spaces from an aligned database");
  CLI::App& cli = app.cli();
  cli.require_subcommand(1);

  Input input;
  std::string output, frames;
  int examples_count = 0, stride = 1;
  learn::LearnOptions learn_options;
  CLI::App* learn_cmd = cli.add_subcommand("learn", "learn the part models: parts.json + parts/*.npy + parts.png");
  add_input_options(learn_cmd, input);
  learn_cmd->add_option("--output", output, "output directory")->required();
  learn_cmd->add_option("--examples", examples_count, "N examples by farthest-point sampling in pose space (0: all)")
      ->capture_default_str();
  learn_cmd->add_option("--frames", frames, "explicit examples: sequence:frame,sequence:frame,...");
  learn_cmd->add_option("--stride", stride, "use every stride-th frame (before --examples)")->capture_default_str();
  learn_cmd->add_option("--energy", learn_options.energy, "share of the energy the kept basis vectors hold")
      ->capture_default_str();
  learn_cmd->add_option("--max-vectors", learn_options.max_vectors, "cap on basis vectors per part (0: none)")
      ->capture_default_str();

  std::string config_out, preview;
  CLI::App* parts_cmd = cli.add_subcommand("parts", "evaluate a parts config (or decompose automatically) and write "
                                                    "an editable config with explicit vertex lists");
  add_input_options(parts_cmd, input);
  parts_cmd->add_option("--output", config_out, "parts config to write (JSON)")->required();
  parts_cmd->add_option("--preview", preview, "PNG of the parts on the template");

  learn::LeaveOutOptions leave_out;
  std::string report_path;
  CLI::App* evaluate_cmd = cli.add_subcommand("evaluate", "leave-out evaluation: learn from every stride-th frame, "
                                                          "reconstruct held-out frames from head/hands/feet");
  add_input_options(evaluate_cmd, input);
  evaluate_cmd->add_option("--stride", leave_out.stride, "learn from every stride-th frame")->capture_default_str();
  evaluate_cmd->add_option("--max-frames", leave_out.max_evaluated, "held-out frames evaluated (0: all)")
      ->capture_default_str();
  evaluate_cmd->add_option("--energy", leave_out.learn.energy, "basis energy")->capture_default_str();
  evaluate_cmd->add_option("--iterations", leave_out.editor.rotation_iterations, "rotation updates")->capture_default_str();
  evaluate_cmd->add_option("--report", report_path, "report JSON")->required();

  return app.run(argc, argv, [&] {
    const int threads = app.common().threads;
    core::StageReport report("learn");
    core::AlignedDatabase db = [&] {
      auto timer = report.time("read");
      return load_database(input);
    }();
    report.figures()["vertices"] = db.template_mesh.vertex_count();
    report.figures()["frames"] = db.total_frames();
    const core::Json provenance = {{"tool", "surfcap-learn"}, {"version", core::version()}, {"options", app.provenance_options()}};

    if (evaluate_cmd->parsed()) {
      leave_out.editor.method = learn::EditMethod::learnt;
      learn::PartSet parts = load_parts(input, db, learn::strided_frames(db, leave_out.stride), threads);
      leave_out.learn.threads = threads;
      auto timer = report.time("evaluate");
      const learn::LeaveOutResult result = learn::leave_out_evaluation(db, parts, leave_out);
      timer.stop();
      report.figures()["training_frames"] = result.training_frames;
      report.figures()["evaluated_frames"] = result.evaluated_frames;
      report.figures()["constrained_vertices"] = result.constrained_vertices;
      for (const auto& m : result.methods)
        report.figures()["methods"][m.method] = {{"mean_error_mm", 1e3 * m.mean_error}, {"max_error_mm", 1e3 * m.max_error},
                                                 {"ms_per_edit", 1e3 * m.seconds_per_edit}, {"basis_size", m.basis_size}};
      report.figures()["provenance"] = provenance;
      report.write(report_path);
      return;
    }

    std::vector<learn::ExampleFrame> examples =
        frames.empty() ? learn::strided_frames(db, stride) : learn::parse_frame_list(db, frames);
    if (examples_count > 0) examples = learn::farthest_pose_frames(db, examples_count, examples);
    learn::PartSet parts = [&] {
      auto timer = report.time("parts");
      return load_parts(input, db, examples, threads);
    }();

    if (parts_cmd->parsed()) {
      core::write_json_file(config_out, learn::part_config_with_vertex_lists(parts));
      if (!preview.empty()) learn::write_parts_preview(preview, db.template_mesh, parts);
      return;
    }

    const fs::path out(output);
    learn_options.threads = threads;
    core::ProgressReporter progress("learn", parts.parts.size() + 1);
    const learn::LearntModel model = [&] {
      auto timer = report.time("learn");
      return learn::learn_part_models(db, parts, examples, learn_options, progress.callback());
    }();
    const learn::LearntModel global =
        learn::learn_part_models(db, learn::whole_mesh_part(db.template_mesh.vertex_count()), examples, learn_options);
    progress.advance();
    progress.finish();
    {
      auto timer = report.time("write");
      learn::write_learnt_model(out / "global", global, provenance);
      learn::write_parts_preview(out / "parts.png", db.template_mesh, parts);
      learn::write_learnt_model(out, model, provenance);
    }
    report.figures()["examples"] = examples.size();
    for (const auto& p : model.parts)
      report.figures()["parts"][p.part.name] = {{"vertices", p.part.vertices.size()}, {"frontier", p.part.frontier.size()},
                                                {"kept", p.basis.cols()}, {"energy", p.energy}};
    report.figures()["global"] = {{"kept", global.parts[0].basis.cols()}, {"energy", global.parts[0].energy}};
    report.write(out / "report" / "learn.json");
    spdlog::info("learnt {} parts from {} examples into {}", model.parts.size(), examples.size(), out.string());
  });
}
