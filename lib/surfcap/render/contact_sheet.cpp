#include "surfcap/render/contact_sheet.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

#include "surfcap/core/error.hpp"

namespace surfcap::render {
namespace {

Image resized(const Image& image, double scale) {
  if (scale == 1.0) return image;
  const cv::Mat source(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.pixels.data()));
  cv::Mat target;
  cv::resize(source, target, cv::Size(), scale, scale, scale < 1 ? cv::INTER_AREA : cv::INTER_LINEAR);
  Image result;
  result.width = target.cols;
  result.height = target.rows;
  result.pixels.assign(target.data, target.data + target.total() * 3);
  return result;
}

void draw_label(Image& sheet, const std::string& text, int x, int y) {
  cv::Mat canvas(sheet.height, sheet.width, CV_8UC3, sheet.pixels.data());
  const cv::Point origin(x + 4, y + 14);
  cv::putText(canvas, text, origin, cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
  cv::putText(canvas, text, origin, cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
}

}  // namespace

Image contact_sheet(const std::vector<Image>& images, const ContactSheetOptions& options) {
  if (images.empty()) throw core::internal_error("contact_sheet: no images");
  if (options.columns < 1 || options.padding < 0 || !(options.scale > 0))
    throw core::internal_error("contact_sheet: bad options");
  std::vector<Image> cells;
  int cell_width = 0, cell_height = 0;
  for (const auto& image : images) {
    cells.push_back(resized(image, options.scale));
    cell_width = std::max(cell_width, cells.back().width);
    cell_height = std::max(cell_height, cells.back().height);
  }
  const int count = static_cast<int>(cells.size());
  const int columns = std::min(options.columns, count);
  const int rows = (count + columns - 1) / columns;
  Image sheet(columns * cell_width + (columns + 1) * options.padding,
              rows * cell_height + (rows + 1) * options.padding, options.background);
  for (int i = 0; i < count; ++i) {
    const int x = options.padding + (i % columns) * (cell_width + options.padding);
    const int y = options.padding + (i / columns) * (cell_height + options.padding);
    sheet.paste(cells[static_cast<std::size_t>(i)], x, y);
    if (static_cast<std::size_t>(i) < options.labels.size() && !options.labels[static_cast<std::size_t>(i)].empty())
      draw_label(sheet, options.labels[static_cast<std::size_t>(i)], x, y);
  }
  return sheet;
}

}  // namespace surfcap::render
