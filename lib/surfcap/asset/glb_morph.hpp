#pragma once
// Internal to asset/glb_*.cpp: the standard glTF content shared by character.glb and
// animation.glb — the template mesh, one POSITION morph target per frame and animations that
// step through them (glTF 2.0 §3.7.2.2 morph targets, §3.11 animations).
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "surfcap/asset/glb_model.hpp"
#include "surfcap/core/database.hpp"
#include "surfcap/core/mesh.hpp"

namespace surfcap::asset::detail {

/// Row-major float32 copy of a matrix (n×k → n·k values).
std::vector<float> row_major_floats(const Eigen::MatrixXd& matrix);

/// Adds the template as mesh 0 (POSITION, indices, COLOR_0 / TEXCOORD_0, one material with the
/// PNG texture when given) on node 0 of scene 0. Returns the mesh index.
int add_template_mesh(GlbBuilder& builder, const core::Mesh& mesh, const std::vector<std::uint8_t>& texture_png,
                      const std::string& name);

/// Components (flat index over frames × vertices × 3) where template + target ≠ frame in
/// float32 arithmetic, with their exact values: what a reader needs to restore frames bit for bit.
struct TargetCorrections {
  std::vector<std::uint32_t> indices;
  std::vector<float> values;
};

/// Appends one POSITION morph target per frame (frame − base, float32; base = the template's
/// row-major positions) to mesh `mesh`, its name "<prefix><frame>" to `names`; returns the index
/// of the first. Fills `corrections` when given.
int add_morph_targets(GlbBuilder& builder, int mesh, const std::vector<float>& base,
                      const std::vector<Eigen::MatrixXd>& frames, const std::string& prefix,
                      std::vector<std::string>& names, TargetCorrections* corrections);

/// Sets mesh.weights and extras.targetNames once every target is added.
void finish_morph_targets(GlbBuilder& builder, int mesh, const std::vector<std::string>& target_names);

/// An animation of node 0 showing targets first .. first+frames−1 in turn at `fps` (LINEAR:
/// consecutive frames blend in between), with translation/rotation channels from `root` when
/// given (world = R_y(heading)·centred + (x, y, z)). Returns the animation index (-1 if no frames).
int add_morph_animation(GlbBuilder& builder, int first_target, int frames, int total_targets, double fps,
                        const std::vector<core::RootMotion>* root, const std::string& name);

}  // namespace surfcap::asset::detail
