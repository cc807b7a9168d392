#pragma once
// A parametric motion space (casas2011 §4, casas2013 §3.1): the sequences of one space time
// warped to normalised time, the hybrid blend refined to tolerance ε, the parameter map
// w = h⁻¹(p), and the files of DESIGN §3.4 (docs/blend.md).
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "surfcap/blend/hybrid_blend.hpp"
#include "surfcap/blend/parameter_map.hpp"
#include "surfcap/blend/space_config.hpp"
#include "surfcap/core/database.hpp"
#include "surfcap/core/json_document.hpp"
#include "surfcap/core/progress.hpp"

namespace surfcap::blend {

struct MotionSpaceOptions {
  int threads = 0;                 ///< 0: all hardware threads; outputs do not depend on it
  double sample_step = 0.05;       ///< parameter-map sampling step per weight-space axis
  int checks_per_interval = 3;     ///< see HybridOptions
  int max_depth = 6;               ///< see HybridOptions
  double sparsity_fraction = 0.1;  ///< see HybridOptions
  int validation_samples = 10;     ///< random weights (fixed seed) where the hybrid error is measured
  std::vector<double> sweep_tolerances_mm{2, 5, 10, 20};  ///< memory/error vs ε report; empty: skip
  void validate() const;
};

struct MotionSpace {
  SpaceConfig config;
  std::vector<std::vector<double>> warps;           ///< [N][T] fractional source frames
  std::vector<int> source_frame_counts;             ///< frames in each source's range
  std::vector<std::vector<core::RootMotion>> roots;  ///< [N][T] warped root motion
  std::vector<double> durations_s;                   ///< per source, (frames − 1)/fps
  std::unique_ptr<SourceSet> sources;
  std::optional<HybridBlend> hybrid;
  std::optional<ParameterMap> parameter_map;
  core::Json figures = core::Json::object();  ///< errors, memory, timings for the report
};

/// Builds one space from the database. `blender` is the template's prefactored blender and must
/// outlive the result.
MotionSpace build_motion_space(const core::AlignedDatabase& database, const NonlinearBlender& blender,
                               const SpaceConfig& config, const MotionSpaceOptions& options,
                               const core::ProgressCallback& progress = {});

/// The high-level parameters of the blend at u (one per config parameter).
std::vector<double> measure_parameters(const MotionSpace& space, const std::vector<double>& u);

/// Writes <output>/spaces/<name>/{space.json, references.npy, root.npy, warp.npy, warp.png,
/// displacements.*.npy} atomically, space.json last.
void write_motion_space(const std::filesystem::path& output, const MotionSpace& space);

}  // namespace surfcap::blend
