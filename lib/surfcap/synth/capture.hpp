#pragma once
// surfcap-synth's work: perform a scene and write a capture folder (DESIGN §3.1) with
// reconstructions, calibrated camera images and ground truth (docs/synth.md).

#include <filesystem>

#include "surfcap/core/progress.hpp"
#include "surfcap/core/report.hpp"
#include "surfcap/render/camera.hpp"
#include "surfcap/render/rasterizer.hpp"
#include "surfcap/synth/scene.hpp"
#include "surfcap/synth/texture.hpp"

namespace surfcap::synth {

/// The actor performing one frame: the true surface (template topology), joints and skirt.
struct PerformedFrame {
  Eigen::MatrixXd V;                  ///< world positions of the template vertices
  Pose pose;
  GarmentState garment;
  std::vector<Eigen::Vector3d> joints;  ///< world joint positions
};

/// The actor of a scene (body, texture, rest normals): everything a frame needs.
struct Actor {
  Body body;
  BodyTexture texture;
  Eigen::MatrixXd rest_normals;
  explicit Actor(const Scene& scene);
  PerformedFrame perform(const Scene& scene, const MotionSpec& motion, int frame) const;
  /// Render options showing this actor's texture on a mesh of the template topology.
  render::RenderOptions render_options() const;
};

/// Writes the capture into `directory` (created; existing files of the same names are replaced).
/// Frames are processed on `threads` threads; the output does not depend on the thread count.
/// Timings and quality figures go into `report`.
void generate_capture(const Scene& scene, const std::filesystem::path& directory, int threads,
                      core::StageReport& report, const core::ProgressCallback& progress = {});

/// Seed of frame `frame` of sequence `sequence` (reconstruction connectivity and noise).
std::uint64_t frame_seed(int scene_seed, int sequence, int frame);

}  // namespace surfcap::synth
