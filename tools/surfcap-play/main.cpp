// surfcap-play: plays a packaged character from a control script (docs/runtime.md):
// DIR/animation.glb, DIR/contact_sheet.png, DIR/report.json; --study reproduces casas2013 Table 2.
#include <chrono>
#include <memory>

#include "character_files.hpp"
#include "surfcap/core/cli.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/report.hpp"
#include "surfcap/render/png.hpp"
#include "surfcap/runtime/control_script.hpp"
#include "surfcap/runtime/controller.hpp"
#include "surfcap/runtime/exact_blend.hpp"
#include "surfcap/runtime/play_preview.hpp"
#include "surfcap/runtime/transition_study.hpp"

#include <spdlog/spdlog.h>

namespace {

using namespace surfcap;

struct PlayArguments {
  tools::CharacterSource source;
  std::string script;
  std::string output;
  int check_exact = 0;
  int preview_frames = 18;
  std::string name;
  int study = 0;
  std::vector<std::string> study_edges;
  int study_repeats = 100;
  double study_latency_weight = 5.0;
  bool uncompressed = false;
};

core::Json transition_json(const runtime::TransitionRecord& record) {
  return {{"frame", record.frame}, {"from", record.from}, {"to", record.to}, {"similarity", record.similarity},
          {"similarity_cost", record.similarity_cost}, {"latency_cost", record.latency_cost},
          {"latency_frames", record.frames}, {"latency_s", record.latency_s}, {"planning_s", record.planning_s},
          {"evaluated_pairs", record.evaluated_pairs}};
}

std::string frame_label(const asset::Character& character, const runtime::FrameState& frame) {
  const asset::CharacterSpace& space = character.spaces[frame.state.space];
  std::string label = std::to_string(frame.index) + " " + space.name;
  for (std::size_t a = 0; a < frame.state.parameters.size() && a < space.parameter_names.size(); ++a)
    label += " " + fmt::format("{:.2f}", frame.state.parameters[a]);
  return frame.in_transition ? label + " *" : label;
}

void run_study(const asset::Character& character, const PlayArguments& arguments, core::StageReport& report) {
  std::vector<std::pair<std::string, std::string>> edges;
  for (const std::string& edge : arguments.study_edges) {
    const auto colon = edge.find(':');
    if (colon == std::string::npos) throw core::bad_arguments("--study-edge " + edge + ": expected FROM:TO");
    edges.emplace_back(edge.substr(0, colon), edge.substr(colon + 1));
  }
  if (edges.empty())
    for (const auto& transition : character.transitions) edges.emplace_back(transition.from, transition.to);
  runtime::PlannerOptions planner;
  planner.fps = character.fps;
  planner.latency_weight = arguments.study_latency_weight;
  runtime::StudyOptions options;
  options.transitions = arguments.study;
  options.repeats = arguments.study_repeats;
  core::Json studies = core::Json::array();
  for (const auto& [from, to] : edges) {
    auto timer = report.time("study_" + from + "__" + to);
    studies.push_back(runtime::transition_study(character, from, to, planner, options));
    for (const auto& row : studies.back()["methods"])
      spdlog::info("{} → {} {:<22} E_S {:7.2f}  λE_L {:7.2f}  latency {:.3f} s  online {:.2f} µs", from, to,
                   row["method"].get<std::string>(), row["similarity_cost"].get<double>(),
                   row["latency_cost"].get<double>(), row["latency_s"].get<double>(), 1e6 * row["online_s"].get<double>());
  }
  report.figures()["study"] = studies;
  core::write_json_file(std::filesystem::path(arguments.output) / "transition_study.json",
                        {{"format", core::format_tag("transition_study", 1)}, {"studies", studies}});
}

void play(const asset::Character& character, const PlayArguments& arguments, core::StageReport& report, int threads) {
  const std::filesystem::path output(arguments.output);
  const runtime::ControlScript script = runtime::read_control_script(arguments.script, character);
  runtime::Controller controller(character, script);
  std::unique_ptr<runtime::ExactBlend> exact;
  if (arguments.check_exact > 0) {
    auto timer = report.time("exact_setup");
    exact = std::make_unique<runtime::ExactBlend>(character, threads);
  }
  std::vector<Eigen::MatrixXd> frames, centred_frames;
  std::vector<core::RootMotion> root_motion;
  std::vector<runtime::FrameState> states;
  double max_error = 0;
  long checked = 0;
  {
    auto timer = report.time("play");
    while (!controller.done()) {
      const runtime::FrameState& state = controller.step();
      const std::vector<float>& world = controller.world_positions();
      Eigen::MatrixXd mesh(static_cast<long>(world.size() / 3), 3);
      for (long v = 0; v < mesh.rows(); ++v) mesh.row(v) << world[v * 3], world[v * 3 + 1], world[v * 3 + 2];
      frames.push_back(std::move(mesh));
      const std::vector<float>& centred = controller.centred_positions();
      Eigen::MatrixXd shape(static_cast<long>(centred.size() / 3), 3);
      for (long v = 0; v < shape.rows(); ++v) shape.row(v) << centred[v * 3], centred[v * 3 + 1], centred[v * 3 + 2];
      centred_frames.push_back(std::move(shape));
      root_motion.push_back({state.root.x(), state.root.y(), state.root.z(), state.heading});
      states.push_back(state);
      if (exact && state.index % arguments.check_exact == 0) {
        const Eigen::MatrixXd reference = exact->centred(state.state.space, state.state.frame, state.weights);
        max_error = std::max(max_error, runtime::max_vertex_error(controller.centred_positions(), reference));
        ++checked;
      }
    }
  }
  const std::string name = arguments.name.empty() ? character.name : arguments.name;
  {
    auto timer = report.time("write_animation");
    tools::write_animation(output / "animation.glb", character.template_mesh, centred_frames, root_motion,
                           controller.fps(), name, !arguments.uncompressed);
  }
  {
    auto timer = report.time("contact_sheet");
    std::vector<runtime::PreviewFrame> preview;
    const long count = std::min<long>(arguments.preview_frames, static_cast<long>(frames.size()));
    for (long k = 0; k < count; ++k) {
      const long index = count == 1 ? 0 : k * (static_cast<long>(frames.size()) - 1) / (count - 1);
      preview.push_back({frames[index], states[index].state.space, states[index].weights.empty() ? 0.5 : states[index].weights[0],
                         frame_label(character, states[index])});
    }
    render::write_png(output / "contact_sheet.png", runtime::play_contact_sheet(character.template_mesh, preview));
  }
  core::Json transitions = core::Json::array();
  double planning = 0;
  for (const auto& record : controller.transitions()) {
    transitions.push_back(transition_json(record));
    planning = std::max(planning, record.planning_s);
  }
  double tolerance_mm = 0;
  for (const auto& space : character.spaces) tolerance_mm = std::max(tolerance_mm, space.tolerance_mm);
  core::Json& f = report.figures();
  f["frames"] = frames.size();
  f["fps"] = controller.fps();
  f["duration_s"] = frames.size() / controller.fps();
  f["vertices"] = character.vertex_count();
  f["transitions"] = transitions;
  f["max_planning_s"] = planning;
  f["evaluation_cpu_per_frame_s"] = controller.evaluation_seconds() / std::max<std::size_t>(1, frames.size());
  f["script"] = arguments.script;
  f["outputs"] = {{"animation", "animation.glb"}, {"contact_sheet", "contact_sheet.png"}};
  if (exact)
    f["check_exact"] = {{"every", arguments.check_exact}, {"frames_checked", checked}, {"max_error_mm", 1000 * max_error},
                        {"tolerance_mm", tolerance_mm}, {"within_tolerance", 1000 * max_error <= tolerance_mm}};
  spdlog::info("{} frames, {} transitions, {:.1f} µs CPU per frame{}", frames.size(), transitions.size(),
               1e6 * f["evaluation_cpu_per_frame_s"].get<double>(),
               exact ? fmt::format(", max error against the exact blend {:.2f} mm", 1000 * max_error) : "");
}

}  // namespace

int main(int argc, char** argv) {
  core::ToolApp app("surfcap-play", "Play a packaged 4D character from a control script");
  PlayArguments arguments;
  CLI::App& cli = app.cli();
  tools::add_character_options(cli, arguments.source);
  cli.add_option("--script", arguments.script, "Control script (surfcap.control/1, docs/runtime.md)");
  cli.add_option("--output,-o", arguments.output, "Output directory (animation.glb, contact_sheet.png, report.json)")
      ->required();
  cli.add_option("--check-exact", arguments.check_exact,
                 "Every N-th frame, compare with the exact non-linear blend (0: never)")->capture_default_str();
  cli.add_option("--preview-frames", arguments.preview_frames, "Frames on the contact sheet")->capture_default_str();
  cli.add_option("--name", arguments.name, "Animation name; default the character's");
  cli.add_flag("--uncompressed", arguments.uncompressed,
               "Write animation.glb with float32 accessors only (no KHR_mesh_quantization / EXT_meshopt_compression)");
  cli.add_option("--study", arguments.study,
                 "Instead of a script: casas2013 Table 2 over N random transitions per edge (0: off)")
      ->capture_default_str();
  cli.add_option("--study-edge", arguments.study_edges, "Edges FROM:TO of the study (repeatable); default all")
      ->take_all();
  cli.add_option("--study-repeats", arguments.study_repeats, "Timing repetitions of the study")->capture_default_str();
  cli.add_option("--study-latency-weight", arguments.study_latency_weight, "λ of E_S + λE_L in the study")
      ->capture_default_str();
  return app.run(argc, argv, [&] {
    if (arguments.study <= 0 && arguments.script.empty()) throw core::bad_arguments("--script is required (or --study N)");
    if (arguments.check_exact < 0) throw core::bad_arguments("--check-exact must be ≥ 0");
    if (arguments.preview_frames < 1 || arguments.preview_frames > 1000)
      throw core::bad_arguments("--preview-frames must be in [1, 1000]");
    if (arguments.study < 0 || arguments.study > 1'000'000) throw core::bad_arguments("--study must be in [0, 1000000]");
    if (arguments.study_repeats < 1 || arguments.study_repeats > 1'000'000)
      throw core::bad_arguments("--study-repeats must be in [1, 1000000]");
    if (!(arguments.study_latency_weight >= 0 && arguments.study_latency_weight <= 1e6))
      throw core::bad_arguments("--study-latency-weight must be in [0, 1e6]");
    core::StageReport report("play");
    asset::Character character;
    {
      auto timer = report.time("load_character");
      character = tools::load_character(arguments.source);
    }
    if (arguments.study > 0) run_study(character, arguments, report);
    else play(character, arguments, report, app.common().threads);
    report.write(std::filesystem::path(arguments.output) / "report.json");
  });
}
