// libFuzzer target: parts documents. First byte even: a learnt model's parts.json
// (learn::read_learnt_model) beside the fixture character's part files (learn::write_learnt_model);
// odd: a part config (configs/parts/*.json, learn::evaluate_part_config) on its template.
#include "fuzz_documents.hpp"
#include "surfcap/learn/part_model.hpp"
#include "surfcap/learn/part_set.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace surfcap;
  if (size < 1) return 0;
  static const std::filesystem::path folder = [] {
    const auto dir = fuzz::scratch_folder() / "model";
    learn::write_learnt_model(dir, *fuzz::fixture_character().parts);
    return dir;
  }();
  if (data[0] % 2 == 0) {
    const auto path = fuzz::document_file(folder, "parts.json", data + 1, size - 1);
    fuzz::run_reader([&] {
      const learn::LearntModel model = learn::read_learnt_model(path);
      const long v = model.template_mesh.vertex_count();
      for (const auto& part : model.parts)
        for (int index : part.part.vertices)
          if (index < 0 || index >= v) __builtin_trap();
    });
  } else {
    const auto path = fuzz::document_file(folder, "part_config.json", data + 1, size - 1);
    fuzz::run_reader([&] {
      const core::Json config = core::read_json_document(path, "part_config", 1);
      core::read_document_fields(path, [&] {
        return learn::evaluate_part_config(config, fuzz::fixture_character().template_mesh, path);
      });
    });
  }
  return 0;
}
