#include "surfcap/blend/warp_plot.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"

namespace surfcap::blend {

void write_warp_plot(const std::filesystem::path& path, const std::vector<std::vector<double>>& warps,
                     const std::vector<int>& frame_counts, const std::vector<std::string>& names) {
  constexpr int width = 640, height = 480, margin = 50;
  cv::Mat image(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Point origin(margin, height - margin);
  const int plot_w = width - 2 * margin, plot_h = height - 2 * margin;
  cv::rectangle(image, cv::Point(margin, margin), cv::Point(width - margin, height - margin), cv::Scalar(0, 0, 0), 1);
  for (int tick = 1; tick < 4; ++tick) {
    const int x = margin + plot_w * tick / 4, y = height - margin - plot_h * tick / 4;
    cv::line(image, cv::Point(x, margin), cv::Point(x, height - margin), cv::Scalar(220, 220, 220), 1);
    cv::line(image, cv::Point(margin, y), cv::Point(width - margin, y), cv::Scalar(220, 220, 220), 1);
  }
  cv::putText(image, "normalised time t", cv::Point(width / 2 - 70, height - 15), cv::FONT_HERSHEY_SIMPLEX, 0.5,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(image, "source frame / length", cv::Point(5, margin - 15), cv::FONT_HERSHEY_SIMPLEX, 0.5,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  const cv::Scalar palette[] = {{200, 80, 30}, {30, 30, 220}, {40, 160, 40}, {160, 40, 160},
                                {0, 140, 220}, {120, 120, 0}, {90, 90, 90}, {200, 0, 120}};
  for (std::size_t i = 0; i < warps.size(); ++i) {
    const cv::Scalar colour = palette[i % 8];
    const auto& warp = warps[i];
    std::vector<cv::Point> points;
    const double last = std::max(1, frame_counts[i] - 1);
    for (std::size_t k = 0; k < warp.size(); ++k) {
      const double t = warp.size() > 1 ? static_cast<double>(k) / (warp.size() - 1) : 0.0;
      points.emplace_back(origin.x + static_cast<int>(std::lround(t * plot_w)),
                          origin.y - static_cast<int>(std::lround(warp[k] / last * plot_h)));
    }
    cv::polylines(image, points, false, colour, 2, cv::LINE_AA);
    cv::putText(image, i < names.size() ? names[i] : std::to_string(i),
                cv::Point(margin + 10, margin + 20 + 18 * static_cast<int>(i)), cv::FONT_HERSHEY_SIMPLEX, 0.5, colour,
                1, cv::LINE_AA);
  }
  std::vector<uchar> buffer;
  if (!cv::imencode(".png", image, buffer)) throw core::io_error(path, "PNG encoding failed");
  core::write_file_atomically(path, std::span<const std::byte>(reinterpret_cast<const std::byte*>(buffer.data()),
                                                               buffer.size()));
}

}  // namespace surfcap::blend
