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
  bool images = false, no_images = false, visual_hull = false, remesh = false, floor_cut = false, no_floor_cut = false,
       textures = false, no_textures = false;
  std::string unseen;
  int reconstruction_vertices = -1, frames_per_sequence = -1;
  double voxel_mm = -1, outliers = -1, blobs = -1;
  cli.add_option("--preset", preset, "Built-in scene: tiny, demo, full, studio, studio_tiny or long (ignored with --scene)")
      ->check(CLI::IsMember(synth::preset_names()));
  cli.add_option("--scene", scene_path, "Scene file (surfcap.synth_scene/1 JSON, e.g. configs/synth/demo.json)")
      ->check(CLI::ExistingFile);
  cli.add_option("--out", out, "Capture folder to write")->required();
  cli.add_option("--seed", seed, "Random seed (-1: the scene's); the output is byte-identical for a seed");
  cli.add_option("--vertices", vertices, "Override the actor's vertex count (0: the scene's)")
      ->check(CLI::Range(0, 200000));
  cli.add_option("--noise-mm", noise_mm, "Override the reconstruction noise, mm (-1: the scene's)");
  cli.add_flag("--images", images, "Write the camera images even if the scene has none (preset long)");
  cli.add_flag("--no-images", no_images, "Write no camera images")->excludes("--images");
  cli.add_option("--frames-per-sequence", frames_per_sequence,
                 "A cut: only the first N frames of each sequence, the same as the whole capture's (0: all)")
      ->check(CLI::NonNegativeNumber);
  // Studio models (docs/synth.md); each overrides the scene's.
  cli.add_flag("--visual-hull", visual_hull, "Reconstruct by shape from silhouette");
  cli.add_flag("--remesh", remesh, "Reconstruct by remeshing the true surface (no visual hull)")->excludes("--visual-hull");
  cli.add_option("--voxel-mm", voxel_mm, "Visual-hull carving grid spacing, mm")->check(CLI::Range(2.0, 100.0));
  cli.add_option("--reconstruction-vertices", reconstruction_vertices,
                 "Target vertices per reconstruction with the studio models (0: the template's edge length)")
      ->check(CLI::Range(0, 500000));
  cli.add_flag("--floor-cut", floor_cut, "Remove the surface below the floor height (open soles)");
  cli.add_flag("--no-floor-cut", no_floor_cut, "Keep the surface below the floor")->excludes("--floor-cut");
  cli.add_option("--unseen", unseen, "Faces seen by fewer than two cameras: keep, remove or rough")
      ->check(CLI::IsMember({"keep", "remove", "rough"}));
  cli.add_option("--outliers", outliers, "Share of vertices pushed off the surface")->check(CLI::Range(0.0, 0.2));
  cli.add_option("--blobs", blobs, "Mean spurious blobs per frame")->check(CLI::Range(0.0, 20.0));
  cli.add_flag("--textures", textures, "Also write each frame as OBJ + MTL + PNG atlas");
  cli.add_flag("--no-textures", no_textures, "Write no textured OBJ")->excludes("--textures");
  return app.run(argc, argv, [&] {
    synth::Scene scene = scene_path.empty() ? synth::preset_scene(preset) : synth::read_scene(scene_path);
    if (seed >= 0) scene.seed = seed;
    if (vertices > 0) scene.body.target_vertices = vertices;
    if (noise_mm >= 0) scene.reconstruction.noise_sigma = noise_mm / 1000;
    if (images) scene.images = true;
    if (no_images) scene.images = false;
    if (frames_per_sequence >= 0) scene.frames_per_sequence = frames_per_sequence;
    auto& r = scene.reconstruction;
    if (visual_hull) r.visual_hull = true;
    if (remesh) r.visual_hull = false;
    if (voxel_mm > 0) r.voxel = voxel_mm / 1000;
    if (reconstruction_vertices >= 0) r.vertices = reconstruction_vertices;
    if (floor_cut) r.floor_cut = true;
    if (no_floor_cut) r.floor_cut = false;
    if (!unseen.empty()) r.unseen = synth::unseen_mode(unseen);
    if (outliers >= 0) r.outlier_fraction = outliers;
    if (blobs >= 0) r.blobs = blobs;
    if (textures) r.textures = true;
    if (no_textures) r.textures = false;
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
