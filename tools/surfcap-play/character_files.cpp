#include "character_files.hpp"

#include "surfcap/asset/glb_character.hpp"
#include "surfcap/core/error.hpp"

namespace surfcap::tools {

void add_character_options(CLI::App& app, CharacterSource& source) {
  app.add_option("--character", source.character, "Packaged character (character.glb of surfcap-export)");
  app.add_option("--database", source.database, "Instead of --character: aligned database (database.json) ...");
  app.add_option("--graph", source.graph, "... and graph.json of surfcap-precompute (transitions/ beside it)");
  app.add_option("--parts", source.parts, "... and optionally parts.json of surfcap-learn");
}

asset::Character load_character(const CharacterSource& source) {
  if (!source.character.empty() && (!source.database.empty() || !source.graph.empty()))
    throw core::bad_arguments("give --character or --database/--graph, not both");
  if (source.character.empty()) {
    if (source.database.empty() || source.graph.empty())
      throw core::bad_arguments("--character (or --database and --graph) is required");
    return asset::assemble_character({source.database, source.graph, source.parts, "character"});
  }
  return asset::read_character_glb(source.character);
}

void write_animation(const std::filesystem::path& path, const core::Mesh& template_mesh,
                     const std::vector<Eigen::MatrixXd>& centred_frames, const std::vector<core::RootMotion>& root_motion,
                     double fps, const std::string& name, bool compress) {
  asset::GlbWriteOptions options;
  options.compress = compress;
  asset::write_animation_glb(path, template_mesh, centred_frames, root_motion, fps, name, options);
}

}  // namespace surfcap::tools
