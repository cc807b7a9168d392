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

/// glTF vertex colours are linear (glTF 2.0 §3.7.2.1); captured colours are sRGB-encoded.
double srgb_to_linear(double c);
double linear_to_srgb(double c);

/// Unit area-weighted vertex normals of row-major float positions (+y where a vertex has no
/// incident area: glTF normals must be unit length).
std::vector<float> unit_normals(const std::vector<float>& positions, const Eigen::MatrixXi& faces);

/// Adds the template as mesh 0 (POSITION, NORMAL, indices, COLOR_0 (linear) / TEXCOORD_0, one
/// material with the PNG texture when given) on node 0 of scene 0. Returns the mesh index.
/// `exact_colors` (when given) receives the sRGB colours as float32 when COLOR_0 cannot restore
/// them exactly (colours that are not all k/255). A `position_scale` S ≠ 1 (a power of two,
/// morph_position_scale) stores POSITION / S and sets node 0's scale to S: exact, and the
/// quantised morph targets reach S m.
int add_template_mesh(GlbBuilder& builder, const core::Mesh& mesh, const std::vector<std::uint8_t>& texture_png,
                      const std::string& name, std::vector<float>* exact_colors = nullptr, double position_scale = 1);

/// Components (flat index over frames × vertices × 3) where template + target ≠ frame in
/// float32 arithmetic, with their exact values: what a reader needs to restore frames bit for bit.
struct TargetCorrections {
  std::vector<std::uint32_t> indices;
  std::vector<float> values;
};

/// The largest |component| of a morph-target delta stored as normalized SHORT (KHR_mesh_quantization)
/// in the compressed form, in units of S/32767 m (S the node scale); larger deltas stay float.
inline constexpr int max_quantised_delta = 32000;
/// The largest node scale the compressed form uses (deltas beyond 2^8 m stay float).
inline constexpr int max_position_scale_exponent = 8;

/// The node scale of the compressed form: the smallest power of two S ≥ 1 with every
/// |frame − template| component ≤ S·max_quantised_delta/32767 (capped at 2^8); 1 uncompressed.
double morph_position_scale(const GlbBuilder& builder, const core::Mesh& template_mesh,
                            const std::vector<const Eigen::MatrixXd*>& frames);

/// Appends one morph target per frame to mesh `mesh` — POSITION = frame − template (float32, or
/// in the compressed form normalized SHORT rounded to S/32767 m, S the `position_scale` given to
/// add_template_mesh) and NORMAL = normals of the
/// frame as stored − template normals — its name "<prefix><frame>" to `names`; returns the index
/// of the first. Fills `corrections` when given (uncompressed form only: the compressed form is
/// not exact).
int add_morph_targets(GlbBuilder& builder, int mesh, const core::Mesh& template_mesh,
                      const std::vector<Eigen::MatrixXd>& frames, const std::string& prefix,
                      std::vector<std::string>& names, TargetCorrections* corrections, double position_scale = 1);

/// Sets mesh.weights and extras.targetNames once every target is added.
void finish_morph_targets(GlbBuilder& builder, int mesh, const std::vector<std::string>& target_names);

/// An animation of node 0 showing targets first .. first+frames−1 in turn at `fps` (LINEAR:
/// consecutive frames blend in between), with translation/rotation channels from `root` when
/// given (world = R_y(heading)·centred + (x, y, z)). Returns the animation index (-1 if no frames).
int add_morph_animation(GlbBuilder& builder, int first_target, int frames, int total_targets, double fps,
                        const std::vector<core::RootMotion>* root, const std::string& name);

}  // namespace surfcap::asset::detail
