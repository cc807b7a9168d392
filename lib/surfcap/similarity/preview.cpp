#include "surfcap/similarity/preview.hpp"

#include <algorithm>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"

namespace surfcap::similarity {

namespace {

constexpr long kMaxPreviewSide = 2048;  ///< larger matrices are shown as block means

/// The matrix as shown: itself up to kMaxPreviewSide frames, else the means of factor×factor
/// blocks (memory of the preview bounded whatever N).
FloatRows displayed_matrix(const FloatRows& matrix, long factor) {
  const long n = matrix.rows(), m = (n + factor - 1) / factor;
  Eigen::MatrixXd sums = Eigen::MatrixXd::Zero(m, m);
  for (long i = 0; i < n; ++i)
    for (long j = 0; j < n; ++j) sums(i / factor, j / factor) += matrix(i, j);
  FloatRows shown(m, m);
  for (long p = 0; p < m; ++p)
    for (long q = 0; q < m; ++q) {
      const double rows = static_cast<double>(std::min(n, (p + 1) * factor) - p * factor);
      const double cols = static_cast<double>(std::min(n, (q + 1) * factor) - q * factor);
      shown(p, q) = static_cast<float>(sums(p, q) / (rows * cols));
    }
  return shown;
}

}  // namespace

void write_similarity_png(const std::filesystem::path& path, const FloatRows& full, const FrameIndex& index,
                          const SimilarityTree* tree) {
  const long factor = (full.rows() + kMaxPreviewSide - 1) / kMaxPreviewSide;
  const FloatRows reduced = factor > 1 ? displayed_matrix(full, factor) : FloatRows();
  const FloatRows& matrix = factor > 1 ? reduced : full;
  auto pixel = [&](long frame) { return static_cast<int>(frame / std::max(1L, factor)); };
  const int n = static_cast<int>(matrix.rows());
  const int cell = std::max(1, (512 + n - 1) / n);
  std::vector<float> values(matrix.data(), matrix.data() + matrix.size());
  const auto percentile = values.begin() + static_cast<long>(0.99 * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), percentile, values.end());
  const float scale = std::max(1e-12f, *percentile);
  cv::Mat gray(n, n, CV_8UC1);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      gray.at<unsigned char>(i, j) = static_cast<unsigned char>(std::clamp(matrix(i, j) / scale, 0.0f, 1.0f) * 255.0f);
  cv::Mat colour;
  cv::applyColorMap(gray, colour, cv::COLORMAP_JET);
  cv::Mat image;
  cv::resize(colour, image, cv::Size(n * cell, n * cell), 0, 0, cv::INTER_NEAREST);
  for (int s = 1; s < index.sequences(); ++s) {
    const int border = pixel(index.start(s)) * cell;
    cv::line(image, {border, 0}, {border, n * cell - 1}, cv::Scalar(255, 255, 255), 1);
    cv::line(image, {0, border}, {n * cell - 1, border}, cv::Scalar(255, 255, 255), 1);
  }
  if (tree) {
    const int radius = std::max(1, cell / 2);
    const int root = pixel(tree->root) * cell + cell / 2;
    cv::line(image, {root, 0}, {root, n * cell - 1}, cv::Scalar(255, 255, 255), 1, cv::LINE_4);
    cv::line(image, {0, root}, {n * cell - 1, root}, cv::Scalar(255, 255, 255), 1, cv::LINE_4);
    for (const auto& edge : tree->edges) {
      const cv::Point a(pixel(edge.child) * cell + cell / 2, pixel(edge.parent) * cell + cell / 2);
      const cv::Point b(pixel(edge.parent) * cell + cell / 2, pixel(edge.child) * cell + cell / 2);
      cv::circle(image, a, radius, cv::Scalar(0, 0, 0), cv::FILLED);
      cv::circle(image, b, radius, cv::Scalar(0, 0, 0), cv::FILLED);
    }
  }
  std::vector<unsigned char> png;
  if (!cv::imencode(".png", image, png)) throw core::internal_error("PNG encoding failed for " + path.string());
  core::write_file_atomically(path, std::span(reinterpret_cast<const std::byte*>(png.data()), png.size()));
}

}  // namespace surfcap::similarity
