// libFuzzer target: capture.json (core::read_capture) in a folder holding a valid cameras.json, so
// that mutations reach the cameras, sequences, patterns and the path policy.
#include "fuzz_documents.hpp"
#include "surfcap/core/capture.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace surfcap;
  static const std::filesystem::path folder = [] {
    const auto dir = fuzz::scratch_folder() / "capture";
    core::CaptureCamera camera;
    camera.name = "cam0";
    camera.width = 64;
    camera.height = 48;
    camera.K << 50, 0, 32, 0, 50, 24, 0, 0, 1;
    camera.t << 0, -1, 3;
    std::filesystem::create_directories(dir);
    core::write_cameras(dir / "cameras.json", {camera});
    return dir;
  }();
  const auto path = fuzz::document_file(folder, "capture.json", data, size);
  fuzz::run_reader([&] {
    const core::Capture capture = core::read_capture(path);
    // What is accepted has frame numbers that cannot overflow and paths inside the folder.
    for (const auto& sequence : capture.sequences)
      if (sequence.count < 1 || sequence.first < 0 || sequence.first > 2'000'000'000 - sequence.count) __builtin_trap();
  });
  return 0;
}
