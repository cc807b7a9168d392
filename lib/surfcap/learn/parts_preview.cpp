#include "surfcap/learn/parts_preview.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"

namespace surfcap::learn {

void write_parts_preview(const std::filesystem::path& png, const core::Mesh& mesh, const PartSet& parts, int height) {
  static const double palette[][3] = {{0.85, 0.85, 0.85}, {0.90, 0.30, 0.25}, {0.25, 0.55, 0.90}, {0.30, 0.80, 0.35},
                                      {0.95, 0.75, 0.20}, {0.70, 0.35, 0.85}, {0.20, 0.80, 0.80}, {0.95, 0.50, 0.70}};
  const long n = mesh.vertex_count();
  Eigen::MatrixXd colour = Eigen::MatrixXd::Zero(n, 3);
  Eigen::VectorXd count = Eigen::VectorXd::Zero(n);
  for (std::size_t j = 0; j < parts.parts.size(); ++j)
    for (int v : parts.parts[j].vertices) {
      for (int c = 0; c < 3; ++c) colour(v, c) += palette[j % 8][c];
      count[v] += 1;
    }
  for (long v = 0; v < n; ++v)
    if (count[v] > 0) colour.row(v) /= count[v];
  const Eigen::RowVector3d lo = mesh.V.colwise().minCoeff(), hi = mesh.V.colwise().maxCoeff();
  const double scale = 0.9 * height / std::max(1e-9, (hi - lo).maxCoeff());
  const int view_width = static_cast<int>(scale * std::max(hi[0] - lo[0], hi[2] - lo[2]) / 0.9) + 1;
  cv::Mat image(height, 2 * view_width, CV_8UC3, cv::Scalar(40, 40, 40));
  cv::Mat depth(height, 2 * view_width, CV_64F, cv::Scalar(-1e30));
  const Eigen::MatrixXd normals = core::vertex_normals(mesh.V, mesh.F);
  for (int view = 0; view < 2; ++view) {  // front (looking along −z), side (looking along −x)
    const int horizontal = view == 0 ? 0 : 2, toward = view == 0 ? 2 : 0;
    const double sign = view == 0 ? 1.0 : -1.0;
    auto project = [&](long v, double& u, double& w) {
      u = view * view_width + 0.5 * view_width + scale * sign * (mesh.V(v, horizontal) - 0.5 * (lo[horizontal] + hi[horizontal]));
      w = height - (0.05 * height + scale * (mesh.V(v, 1) - lo[1]));
    };
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
      double u[3], w[3], z[3];
      for (int k = 0; k < 3; ++k) {
        project(mesh.F(f, k), u[k], w[k]);
        z[k] = mesh.V(mesh.F(f, k), toward);  // the viewer sits on the + side
      }
      const double area = (u[1] - u[0]) * (w[2] - w[0]) - (u[2] - u[0]) * (w[1] - w[0]);
      if (std::abs(area) < 1e-12) continue;
      const int x0 = std::max(0, static_cast<int>(std::floor(std::min({u[0], u[1], u[2]})))),
                x1 = std::min(image.cols - 1, static_cast<int>(std::ceil(std::max({u[0], u[1], u[2]})))),
                y0 = std::max(0, static_cast<int>(std::floor(std::min({w[0], w[1], w[2]})))),
                y1 = std::min(image.rows - 1, static_cast<int>(std::ceil(std::max({w[0], w[1], w[2]}))));
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const double px = x + 0.5, py = y + 0.5;
          const double b0 = ((u[1] - px) * (w[2] - py) - (u[2] - px) * (w[1] - py)) / area;
          const double b1 = ((u[2] - px) * (w[0] - py) - (u[0] - px) * (w[2] - py)) / area;
          const double b2 = 1 - b0 - b1;
          if (b0 < 0 || b1 < 0 || b2 < 0) continue;
          const double zz = b0 * z[0] + b1 * z[1] + b2 * z[2];
          if (zz <= depth.at<double>(y, x)) continue;
          depth.at<double>(y, x) = zz;
          Eigen::RowVector3d c = Eigen::RowVector3d::Zero();
          double shade = 0;
          const double bary[3] = {b0, b1, b2};
          for (int k = 0; k < 3; ++k) {
            c += bary[k] * colour.row(mesh.F(f, k));
            shade += bary[k] * std::abs(normals(mesh.F(f, k), toward));
          }
          c *= 0.35 + 0.65 * shade;
          image.at<cv::Vec3b>(y, x) = cv::Vec3b(cv::saturate_cast<uchar>(255 * c[2]), cv::saturate_cast<uchar>(255 * c[1]),
                                                cv::saturate_cast<uchar>(255 * c[0]));
        }
    }
  }
  for (std::size_t j = 0; j < parts.parts.size(); ++j) {
    const double* p = palette[j % 8];
    const cv::Point corner(8, 20 + 18 * static_cast<int>(j));
    cv::rectangle(image, corner + cv::Point(0, -10), corner + cv::Point(12, 2),
                  cv::Scalar(255 * p[2], 255 * p[1], 255 * p[0]), cv::FILLED);
    cv::putText(image, parts.parts[j].name, corner + cv::Point(18, 0), cv::FONT_HERSHEY_SIMPLEX, 0.45,
                cv::Scalar(230, 230, 230), 1, cv::LINE_AA);
  }
  std::vector<uchar> buffer;
  if (!cv::imencode(".png", image, buffer)) throw core::io_error(png, "PNG encoding failed");
  core::write_file_atomically(png, std::span<const std::byte>(reinterpret_cast<const std::byte*>(buffer.data()), buffer.size()));
}

}  // namespace surfcap::learn
