#include "surfcap/render/png.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <span>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"

namespace surfcap::render {

std::vector<std::uint8_t> encode_png(const Image& image) {
  if (image.empty()) throw core::internal_error("encode_png: empty image");
  const cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.pixels.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  std::vector<std::uint8_t> bytes;
  if (!cv::imencode(".png", bgr, bytes, {cv::IMWRITE_PNG_COMPRESSION, 6}))
    throw core::internal_error("encode_png: OpenCV could not encode the image");
  return bytes;
}

void write_png(const std::filesystem::path& path, const Image& image) {
  const auto bytes = encode_png(image);
  core::write_file_atomically(path, std::as_bytes(std::span(bytes.data(), bytes.size())));
}

Image read_png(const std::filesystem::path& path) {
  const std::string bytes = core::read_file(path);
  const std::vector<std::uint8_t> buffer(bytes.begin(), bytes.end());
  const cv::Mat decoded = cv::imdecode(buffer, cv::IMREAD_COLOR);
  if (decoded.empty()) throw core::bad_input(path, "not a readable PNG image");
  cv::Mat rgb;
  cv::cvtColor(decoded, rgb, cv::COLOR_BGR2RGB);
  Image image;
  image.width = rgb.cols;
  image.height = rgb.rows;
  image.pixels.assign(rgb.data, rgb.data + rgb.total() * 3);
  return image;
}

}  // namespace surfcap::render
