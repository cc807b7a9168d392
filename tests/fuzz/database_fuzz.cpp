// libFuzzer target: database.json (core::read_database) beside the template and sequence files of
// the fixture character (written by core::write_database), so mutations reach every field.
#include "fuzz_documents.hpp"
#include "surfcap/core/database.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace surfcap;
  static const std::filesystem::path folder = [] {
    const auto dir = fuzz::scratch_folder() / "database";
    core::AlignedDatabase database;
    database.template_mesh = fuzz::fixture_character().template_mesh;
    database.sequences = fuzz::fixture_character().sequences;
    core::write_database(dir, database);
    return dir;
  }();
  const auto path = fuzz::document_file(folder, "database.json", data, size);
  fuzz::run_reader([&] {
    const core::AlignedDatabase database = core::read_database(path);
    const long v = database.template_mesh.vertex_count();
    for (const auto& sequence : database.sequences) {
      if (sequence.root_motion.size() != sequence.frames.size()) __builtin_trap();
      for (const auto& frame : sequence.frames)
        if (frame.rows() != v || !frame.allFinite()) __builtin_trap();
    }
    if (!database.root_sequence.empty()) {
      const int root = database.sequence_index(database.root_sequence);
      if (root < 0 || database.root_frame < 0 || database.root_frame >= database.sequences[root].frame_count()) __builtin_trap();
    }
    if (!(database.fps > 0)) __builtin_trap();
  });
  return 0;
}
