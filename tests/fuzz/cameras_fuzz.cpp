// libFuzzer target: cameras.json (core::read_cameras). What it accepts is a usable pinhole camera.
#include "fuzz_documents.hpp"
#include "surfcap/core/capture.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace surfcap;
  const auto path = fuzz::document_file(fuzz::scratch_folder() / "cameras", "cameras.json", data, size);
  fuzz::run_reader([&] {
    for (const auto& camera : core::read_cameras(path))
      if (!(camera.K(0, 0) > 0 && camera.K(1, 1) > 0 && camera.K(2, 2) == 1 && camera.width > 0 && camera.height > 0 &&
            camera.t.allFinite()))
        __builtin_trap();
  });
  return 0;
}
