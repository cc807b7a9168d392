// surfcap-synth: writes a synthetic multi-view capture with ground truth (docs/synth.md).
#include <spdlog/spdlog.h>

#include "surfcap/core/cli.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/progress.hpp"
#include "surfcap/core/report.hpp"
#include "surfcap/synth/capture.hpp"

int main(int argc, char** argv) {
  using namespace surfcap;
  core::ToolApp app("surfcap-synth",
                    "Writes a synthetic multi-view performance capture (reconstructions, camera images, "
                    "calibration) with exact ground truth.");
  auto& cli = app.cli();
  std::string preset = "tiny", scene_path, out;
  int seed = -1, vertices = 0;
  double noise_mm = -1;
  bool no_images = false;
  cli.add_option("--preset", preset, "Built-in scene: tiny, demo or full (ignored with --scene)")
      ->check(CLI::IsMember({"tiny", "demo", "full"}));
  cli.add_option("--scene", scene_path, "Scene file (surfcap.synth_scene/1 JSON, e.g. configs/synth/demo.json)")
      ->check(CLI::ExistingFile);
  cli.add_option("--out", out, "Capture folder to write")->required();
  cli.add_option("--seed", seed, "Random seed (-1: the scene's); the output is byte-identical for a seed");
  cli.add_option("--vertices", vertices, "Override the actor's vertex count (0: the scene's)")
      ->check(CLI::Range(0, 200000));
  cli.add_option("--noise-mm", noise_mm, "Override the reconstruction noise, mm (-1: the scene's)");
  cli.add_flag("--no-images", no_images, "Write no camera images");
  return app.run(argc, argv, [&] {
    synth::Scene scene = scene_path.empty() ? synth::preset_scene(preset) : synth::read_scene(scene_path);
    if (seed >= 0) scene.seed = seed;
    if (vertices > 0) scene.body.target_vertices = vertices;
    if (noise_mm >= 0) scene.reconstruction.noise_sigma = noise_mm / 1000;
    if (no_images) scene.images = false;
    scene.validate();
    spdlog::info("scene '{}': {} sequences, {} frames, {} cameras, seed {}", scene.name, scene.sequences.size(),
                 scene.total_frames(), scene.studio.cameras, scene.seed);
    core::StageReport report("synth");
    report.figures()["options"] = app.options_json();
    core::ProgressReporter progress("synth", static_cast<std::size_t>(scene.total_frames()));
    synth::generate_capture(scene, out, app.common().threads, report, progress.callback());
    progress.finish();
    report.write(std::filesystem::path(out) / "ground_truth" / "report.json");
    spdlog::info("wrote {} in {:.1f} s", out, report.to_json()["total_s"].get<double>());
  });
}
