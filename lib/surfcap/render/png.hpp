#pragma once
// PNG files of images (through OpenCV's codec, kept inside png.cpp).

#include <cstdint>
#include <filesystem>
#include <vector>

#include "surfcap/render/image.hpp"

namespace surfcap::render {

/// PNG bytes of `image` (deterministic: fixed compression level).
std::vector<std::uint8_t> encode_png(const Image& image);
/// Writes atomically (temporary name, then rename); io_error (exit 4) on failure.
void write_png(const std::filesystem::path& path, const Image& image);
/// Reads an 8-bit PNG (grey or colour) as RGB; io_error if unreadable, bad_input if not an image.
Image read_png(const std::filesystem::path& path);

}  // namespace surfcap::render
