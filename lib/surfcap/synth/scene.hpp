#pragma once
// A synthetic capture session: the actor, the studio, the reconstruction model and the
// sequences to perform. Stored as configs/synth/<name>.json ("surfcap.synth_scene/1",
// docs/synth.md); the presets (tiny, demo, full, studio, studio_tiny, long) are also built in.

#include <filesystem>
#include <string>
#include <vector>

#include "surfcap/core/json_document.hpp"
#include "surfcap/synth/body.hpp"
#include "surfcap/synth/garment.hpp"
#include "surfcap/synth/motion.hpp"
#include "surfcap/synth/reconstruction.hpp"

namespace surfcap::synth {

struct StudioOptions {
  int cameras = 8;
  int width = 640;
  int height = 480;
  double radius = 5.0;                              ///< metres from the vertical axis
  double elevation = 1.8;                           ///< camera height, metres
  double fov = 34.0;                                ///< vertical field of view, degrees
  Eigen::Vector3d target = Eigen::Vector3d(0, 0.9, 0);  ///< every camera looks here
};

struct Scene {
  std::string name = "custom";
  double fps = 25.0;
  int seed = 1;
  BodyOptions body;
  StudioOptions studio;
  ReconstructionOptions reconstruction;
  GarmentOptions garment;
  bool images = true;
  int contact_sheet_frames = 4;
  std::vector<MotionSpec> sequences;
  /// A cut: > 0 writes only the first N frames of each sequence (fewer if it has fewer). The
  /// motions keep their full length, so the frames written are those of the whole capture, byte
  /// for byte. 0: every frame.
  int frames_per_sequence = 0;

  /// bad_arguments naming the problem (sizes, counts, duplicate sequence names...).
  void validate() const;
  /// Frames written of a sequence: its length, or the cut.
  int written_frames(const MotionSpec& motion) const;
  long total_frames() const;  ///< frames written, over every sequence
};

/// "keep", "remove" or "rough"; bad_arguments for another name.
UnseenMode unseen_mode(const std::string& name);

/// Built-in presets: "tiny", "demo", "full", "studio", "studio_tiny", "long"; bad_arguments for another name.
Scene preset_scene(const std::string& name);
std::vector<std::string> preset_names();

core::Json scene_to_json(const Scene& scene);
/// Missing fields keep their defaults; `source` names the file in errors.
Scene scene_from_json(const core::Json& document, const std::string& source);
Scene read_scene(const std::filesystem::path& path);

}  // namespace surfcap::synth
