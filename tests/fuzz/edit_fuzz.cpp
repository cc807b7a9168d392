// libFuzzer target: edit files (learn::edit_constraints) against the fixture character's parts.
// What is accepted constrains existing vertices to finite, plausible targets.
#include "fuzz_documents.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/learn/edit_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace surfcap;
  static const learn::PartSet parts = fuzz::fixture_character().parts->part_set();
  const auto& V = fuzz::fixture_character().template_mesh.V;
  const auto path = fuzz::document_file(fuzz::scratch_folder() / "edit", "edit.json", data, size);
  fuzz::run_reader([&] {
    const core::Json edit = core::read_json_document(path, "edit", 1);
    for (const auto& constraint : learn::edit_constraints(edit, parts, V, path))
      if (constraint.vertex < 0 || constraint.vertex >= V.rows() || !constraint.target.allFinite() ||
          constraint.target.cwiseAbs().maxCoeff() > 2 * core::kMaxCoordinate || !(constraint.weight > 0))
        __builtin_trap();
  });
  return 0;
}
