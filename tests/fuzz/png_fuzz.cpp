// libFuzzer target: camera images. core::png_size (the header check of every camera image) and
// render::read_png (a full decode through OpenCV) on arbitrary bytes.
#include "fuzz_documents.hpp"
#include "surfcap/core/capture.hpp"
#include "surfcap/render/png.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace surfcap;
  const auto path = fuzz::document_file(fuzz::scratch_folder() / "png", "image.png", data, size);
  fuzz::run_reader([&] {
    const auto [width, height] = core::png_size(path, 0);
    if (width < 0 || height < 0) __builtin_trap();
    // Decode only what a camera could hold (cameras.json bounds the size).
    if (static_cast<double>(width) * height > 1 << 22) return;
    const render::Image image = render::read_png(path);
    if (image.pixels.size() != static_cast<std::size_t>(image.width) * image.height * 3) __builtin_trap();
  });
  return 0;
}
