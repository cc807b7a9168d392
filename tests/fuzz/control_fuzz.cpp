// libFuzzer target: control scripts (runtime::read_control_script) for the fixture character.
#include "fuzz_documents.hpp"
#include "surfcap/core/input_policy.hpp"
#include "surfcap/runtime/control_script.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace surfcap;
  const auto path = fuzz::document_file(fuzz::scratch_folder() / "control", "control.json", data, size);
  fuzz::run_reader([&] {
    const runtime::ControlScript script = runtime::read_control_script(path, fuzz::fixture_character());
    if (!(script.duration_s >= 0 && script.duration_s <= core::kMaxDurationS)) __builtin_trap();
    if (script.fps && !(*script.fps > 0 && *script.fps <= core::kMaxFps)) __builtin_trap();
  });
  return 0;
}
