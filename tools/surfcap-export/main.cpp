// surfcap-export: build outputs (aligned database, motion graph, part models) → character.glb
// (DESIGN §3.5, docs/formats.md "Character asset"). Glue only: lib/surfcap/asset does the work.
#include <spdlog/spdlog.h>

#include <filesystem>

#include "surfcap/asset/character.hpp"
#include "surfcap/asset/character_preview.hpp"
#include "surfcap/asset/glb_character.hpp"
#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/cli.hpp"
#include "surfcap/core/error.hpp"
#include "surfcap/core/report.hpp"
#include "surfcap/core/version.hpp"
#include "surfcap/render/png.hpp"

namespace fs = std::filesystem;
using namespace surfcap;

namespace {

core::Json content_figures(const asset::Character& character, const asset::GlbSummary& summary) {
  core::Json figures = {{"file_bytes", summary.file_bytes}, {"json_bytes", summary.json_bytes},
                        {"buffer_bytes", summary.buffer_bytes}, {"accessors", summary.accessors},
                        {"morph_targets", summary.morph_targets}, {"animations", summary.animations},
                        {"vertices", character.vertex_count()}, {"faces", character.template_mesh.face_count()},
                        {"texture", !character.texture_png.empty()}, {"compressed", summary.compressed}, {"parts", character.parts ? character.parts->parts.size() : 0}};
  for (const auto& s : character.sequences) figures["sequences"].push_back({{"name", s.name}, {"frames", s.frame_count()}});
  for (const auto& s : character.spaces)
    figures["spaces"].push_back({{"name", s.name}, {"frames", s.frames}, {"nodes", s.node_count()},
                                 {"stored_vertices", s.displacement_vertices.size()}});
  for (const auto& t : character.transitions)
    figures["transitions"].push_back({{"from", t.from}, {"to", t.to}, {"rows", t.rows}, {"cols", t.cols}});
  return figures;
}

}  // namespace

int main(int argc, char** argv) {
  core::ToolApp app("surfcap-export", "Package the build outputs into one glTF 2.0 character (character.glb)");
  CLI::App& cli = app.cli();
  asset::CharacterInputs inputs;
  std::string output, report_path, preview_path;
  asset::GlbWriteOptions write_options;
  bool uncompressed = false;
  cli.add_option("--database", inputs.database, "aligned database (database.json)")->required();
  cli.add_option("--graph", inputs.graph, "graph.json of surfcap-precompute (transitions/ beside it)")->required();
  cli.add_option("--parts", inputs.parts, "parts.json of surfcap-learn (optional)");
  cli.add_option("--output", output, "the character file (.glb)")->required();
  cli.add_option("--name", inputs.name, "character name")->capture_default_str();
  cli.add_option("--report", report_path, "report JSON (default: <output dir>/report/export.json)");
  cli.add_option("--preview", preview_path, "preview PNG (default: <output without .glb>.png)");
  cli.add_flag("--uncompressed", uncompressed,
               "float32 accessors only, frames exact (no KHR_mesh_quantization / EXT_meshopt_compression)");
  return app.run(argc, argv, [&] {
    const fs::path glb = output;
    if (glb.extension() != ".glb") throw core::bad_arguments("--output must name a .glb file: " + output);
    core::StageReport report("export");
    asset::Character character;
    {
      auto timer = report.time("assemble");
      character = asset::assemble_character(inputs);
    }
    character.provenance = {{"tool", "surfcap-export"}, {"version", std::string(core::version())},
                            {"options", app.provenance_json()}, {"character", character.provenance}};
    asset::GlbSummary summary;
    {
      auto timer = report.time("write");
      write_options.compress = !uncompressed;
      summary = asset::write_character_glb(glb, character, write_options);
    }
    {
      // The file must read back to the same bytes: reader and writer agree (docs/formats.md).
      auto timer = report.time("verify");
      report.figures()["round_trip_identical"] =
          asset::character_glb_bytes(asset::read_character_glb(glb), write_options) == core::read_file(glb);
    }
    const fs::path preview = preview_path.empty() ? fs::path(glb).replace_extension(".png") : fs::path(preview_path);
    {
      auto timer = report.time("preview");
      render::write_png(preview, asset::character_preview(character));
    }
    report.figures()["content"] = content_figures(character, summary);
    report.figures()["output"] = glb.string();
    report.figures()["preview"] = preview.string();
    report.write(report_path.empty() ? glb.parent_path() / "report" / "export.json" : fs::path(report_path));
    spdlog::info("wrote {} ({:.2f} MB, {} morph targets, {} spaces, {} transitions)", glb.string(),
                 summary.file_bytes / 1e6, summary.morph_targets, character.spaces.size(), character.transitions.size());
  });
}
