#pragma once
// Where surfcap-play gets its character and puts its animation: character.glb through the asset
// module, or (for development and tests) the build outputs assembled in memory.
#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "surfcap/asset/character.hpp"
#include "surfcap/core/database.hpp"

namespace surfcap::tools {

struct CharacterSource {
  std::string character;  ///< character.glb
  std::string database;   ///< or: database.json + graph.json (+ parts.json)
  std::string graph;
  std::string parts;
};

void add_character_options(CLI::App& app, CharacterSource& source);
asset::Character load_character(const CharacterSource& source);

/// DIR/animation.glb: the template mesh with one morph-target animation of the centred frames and
/// the root motion on its node.
void write_animation(const std::filesystem::path& path, const core::Mesh& template_mesh,
                     const std::vector<Eigen::MatrixXd>& centred_frames, const std::vector<core::RootMotion>& root_motion,
                     double fps, const std::string& name, bool compress);

}  // namespace surfcap::tools
