#include "surfcap/align/image_features.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>

#include "surfcap/core/error.hpp"

namespace surfcap::align {

namespace {

/// A deterministic order of keypoints, strongest first (OpenCV's SIFT collects them from parallel
/// workers).
bool stronger(const cv::KeyPoint& a, const cv::KeyPoint& b) {
  if (a.response != b.response) return a.response > b.response;
  if (a.pt.y != b.pt.y) return a.pt.y < b.pt.y;
  if (a.pt.x != b.pt.x) return a.pt.x < b.pt.x;
  if (a.size != b.size) return a.size < b.size;
  return a.angle < b.angle;
}

/// SIFT's octave of a keypoint (−1: the doubled image).
int keypoint_octave(const cv::KeyPoint& keypoint) {
  return static_cast<int>(static_cast<signed char>(keypoint.octave & 255));
}

/// The `limit` strongest SIFT keypoints of `image` (strongest first) and their descriptors
/// (rows follow the keypoints). One Gaussian pyramid serves detection and description. The
/// descriptors are those SIFT computes for the kept keypoints on their own (detect, then compute):
/// that computation builds the same pyramid from the doubled image whenever a kept keypoint lies
/// on it, and is what runs when none does.
void detect_strongest(cv::SIFT& sift, const cv::Mat& image, int limit, std::vector<cv::KeyPoint>& keypoints,
                      cv::Mat& descriptors) {
  std::vector<cv::KeyPoint> all;
  cv::Mat all_descriptors;
  sift.detectAndCompute(image, cv::noArray(), all, all_descriptors);
  std::vector<int> order(all.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  // Equal in every field: the same keypoint found twice, either row will do.
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return stronger(all[static_cast<std::size_t>(a)], all[static_cast<std::size_t>(b)]);
  });
  if (static_cast<int>(order.size()) > limit) order.resize(static_cast<std::size_t>(std::max(0, limit)));
  keypoints.clear();
  bool doubled = false;
  for (const int i : order) {
    keypoints.push_back(all[static_cast<std::size_t>(i)]);
    doubled = doubled || keypoint_octave(keypoints.back()) < 0;
  }
  if (keypoints.empty()) return;
  if (!doubled || all_descriptors.rows != static_cast<int>(all.size())) {
    sift.compute(image, keypoints, descriptors);
    return;
  }
  descriptors.create(static_cast<int>(keypoints.size()), all_descriptors.cols, all_descriptors.type());
  for (std::size_t k = 0; k < order.size(); ++k)
    all_descriptors.row(order[k]).copyTo(descriptors.row(static_cast<int>(k)));
}

using Descriptors = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// The nearest and second-nearest rows of the other set, as (index, distance²) pairs, for every
/// row of either set. An exact search over every pair, each distance computed once for both
/// directions; distances are summed in FLANN's order (four components at a time) and ties kept as
/// FLANN's linear search keeps them (the earlier row first).
struct Neighbours {
  std::vector<std::array<int, 2>> index;
  std::vector<std::array<float, 2>> distance;

  explicit Neighbours(std::size_t count)
      : index(count, {-1, -1}), distance(count, {std::numeric_limits<float>::max(), std::numeric_limits<float>::max()}) {}

  void add(std::size_t row, float squared, int other) {
    auto& d = distance[row];
    auto& i = index[row];
    if (squared >= d[1]) return;
    if (i[0] < 0) {
      d[0] = squared, i[0] = other;
    } else if (d[0] > squared) {
      d[1] = d[0], i[1] = i[0];
      d[0] = squared, i[0] = other;
    } else {
      d[1] = squared, i[1] = other;
    }
  }
};

float squared_distance(const float* a, const float* b, long size) {
  float result = 0;
  long k = 0;
  for (; k + 3 < size; k += 4) {
    const float d0 = a[k] - b[k], d1 = a[k + 1] - b[k + 1], d2 = a[k + 2] - b[k + 2], d3 = a[k + 3] - b[k + 3];
    result += d0 * d0 + d1 * d1 + d2 * d2 + d3 * d3;
  }
  for (; k < size; ++k) {
    const float d0 = a[k] - b[k];
    result += d0 * d0;
  }
  return result;
}

/// forward: for every parent row its two nearest child rows; backward: the reverse.
void two_nearest_both_ways(const Descriptors& parent, const Descriptors& child, Neighbours& forward,
                           Neighbours& backward) {
  const long columns = parent.cols();
  for (long p = 0; p < parent.rows(); ++p)
    for (long c = 0; c < child.rows(); ++c) {
      const float squared = squared_distance(child.row(c).data(), parent.row(p).data(), columns);
      forward.add(static_cast<std::size_t>(p), squared, static_cast<int>(c));
      backward.add(static_cast<std::size_t>(c), squared, static_cast<int>(p));
    }
}

/// The part of `camera`'s image where the reconstruction (vertices V) can show, for SIFT: the box
/// of the vertices' projections grown by a margin for the filters and descriptor windows of the
/// keypoints on it (a quarter of the box's larger side, at least 48 pixels), its origin on a
/// multiple of 32 pixels so that the pyramid's octaves sample the crop on the whole image's grid.
/// The whole image where a vertex is behind the camera.
cv::Rect feature_box(const core::CaptureCamera& camera, const Eigen::MatrixXd& V, const cv::Mat& K,
                     const cv::Mat& distortion) {
  const cv::Rect whole(0, 0, camera.width, camera.height);
  if (V.rows() == 0) return whole;
  std::vector<cv::Point3d> points(static_cast<std::size_t>(V.rows()));
  for (long v = 0; v < V.rows(); ++v) {
    const Eigen::Vector3d c = camera.R * V.row(v).transpose() + camera.t;
    if (!(c.z() > 0)) return whole;
    points[static_cast<std::size_t>(v)] = {c.x(), c.y(), c.z()};
  }
  std::vector<cv::Point2d> pixels;
  cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, distortion, pixels);
  double x0 = camera.width, y0 = camera.height, x1 = 0, y1 = 0;
  for (const auto& p : pixels) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) return whole;
    x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
  }
  const double margin = std::max(48.0, 0.25 * std::max(x1 - x0, y1 - y0));
  constexpr int kGrid = 32;
  const int left = std::max(0, static_cast<int>(std::floor((x0 - margin) / kGrid)) * kGrid);
  const int top = std::max(0, static_cast<int>(std::floor((y0 - margin) / kGrid)) * kGrid);
  const int right = std::min(camera.width, static_cast<int>(std::ceil(x1 + margin)) + 1);
  const int bottom = std::min(camera.height, static_cast<int>(std::ceil(y1 + margin)) + 1);
  if (right <= left || bottom <= top) return {};
  return cv::Rect(left, top, right - left, bottom - top);
}

}  // namespace

void serial_image_processing() { cv::setNumThreads(1); }

FrameFeatures detect_frame_features(const core::Capture& capture, int sequence, int frame,
                                    const geometry::SurfaceQuery& reconstruction, const FeatureOptions& options) {
  FrameFeatures features;
  if (capture.sequences[static_cast<std::size_t>(sequence)].images.empty()) return features;
  const cv::Ptr<cv::SIFT> sift = cv::SIFT::create();
  std::vector<Eigen::Vector3d> points, normals;
  std::vector<cv::Mat> descriptor_rows;
  for (int c = 0; c < static_cast<int>(capture.cameras.size()); ++c) {
    const auto& camera = capture.cameras[static_cast<std::size_t>(c)];
    const auto path = capture.image_path(sequence, frame, c);
    const cv::Mat image = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
    if (image.empty()) throw core::bad_input(path, "unreadable camera image", frame);
    if (image.cols != camera.width || image.rows != camera.height)
      throw core::bad_input(path, "image size differs from camera " + camera.name + " in cameras.json", frame);
    cv::Mat K(3, 3, CV_64F), distortion(1, 5, CV_64F);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) K.at<double>(i, j) = camera.K(i, j);
    for (int i = 0; i < 5; ++i) distortion.at<double>(0, i) = camera.distortion(i);
    // Keypoints off the reconstruction are dropped below: detect only where it can show.
    const cv::Rect box = feature_box(camera, reconstruction.vertices(), K, distortion);
    if (box.empty()) continue;
    std::vector<cv::KeyPoint> keypoints;
    cv::Mat descriptors;
    detect_strongest(*sift, image(box), options.max_per_image, keypoints, descriptors);
    features.detected += static_cast<long>(keypoints.size());
    if (keypoints.empty()) continue;
    // Undistorted normalised coordinates of the keypoints → camera rays → first surface hit.
    std::vector<cv::Point2f> pixels;
    for (const auto& keypoint : keypoints)
      pixels.push_back(keypoint.pt + cv::Point2f(static_cast<float>(box.x), static_cast<float>(box.y)));
    std::vector<cv::Point2f> normalised;
    cv::undistortPoints(pixels, normalised, K, distortion);
    const Eigen::Vector3d centre = -camera.R.transpose() * camera.t;
    for (int k = 0; k < descriptors.rows && k < static_cast<int>(normalised.size()); ++k) {
      const Eigen::Vector3d direction =
          (camera.R.transpose() * Eigen::Vector3d(normalised[static_cast<std::size_t>(k)].x,
                                                  normalised[static_cast<std::size_t>(k)].y, 1.0))
              .normalized();
      const auto hit = reconstruction.first_hit(centre, direction);
      if (!hit) continue;
      const Eigen::Vector3d normal = reconstruction.face_normal(hit->face);
      if (-normal.dot(direction) < options.min_facing) continue;  // grazing: unreliable position
      points.push_back(hit->position);
      normals.push_back(normal);
      descriptor_rows.push_back(descriptors.row(k));
      features.cameras.push_back(c);
    }
  }
  const long k = static_cast<long>(points.size());
  features.points.resize(k, 3);
  features.normals.resize(k, 3);
  features.descriptors.resize(k, 128);
  for (long i = 0; i < k; ++i) {
    features.points.row(i) = points[static_cast<std::size_t>(i)].transpose();
    features.normals.row(i) = normals[static_cast<std::size_t>(i)].transpose();
    const cv::Mat& row = descriptor_rows[static_cast<std::size_t>(i)];
    for (int j = 0; j < 128; ++j) features.descriptors(i, j) = row.at<float>(0, j);
  }
  return features;
}

std::vector<FeatureMatch> match_features(const FrameFeatures& parent, const FrameFeatures& child,
                                         const Eigen::MatrixXd& predicted, double height,
                                         const FeatureOptions& options) {
  std::vector<FeatureMatch> candidates;
  if (parent.size() < 2 || child.size() < 2) return candidates;
  Neighbours forward(static_cast<std::size_t>(parent.size())), backward(static_cast<std::size_t>(child.size()));
  two_nearest_both_ways(parent.descriptors, child.descriptors, forward, backward);
  const float ratio2 = static_cast<float>(options.ratio * options.ratio);
  const double max_displacement = options.max_displacement_height * height;
  for (long p = 0; p < parent.size(); ++p) {
    const auto& [best, second] = forward.index[static_cast<std::size_t>(p)];
    if (best < 0) continue;
    const auto& distance = forward.distance[static_cast<std::size_t>(p)];
    if (distance[0] > ratio2 * distance[1]) continue;                          // ratio test
    if (backward.index[static_cast<std::size_t>(best)][0] != p) continue;     // mutual
    const auto& back = backward.distance[static_cast<std::size_t>(best)];
    if (back[0] > ratio2 * back[1]) continue;
    if ((child.points.row(best) - predicted.row(p)).norm() > max_displacement) continue;
    candidates.push_back({p, best});
  }
  // Neighbour consistency: the displacement (child − predicted parent) of a match must agree with
  // the median displacement of its nearest matches (by parent position).
  const long m = static_cast<long>(candidates.size());
  const int k = std::min<int>(options.neighbours, static_cast<int>(m) - 1);
  if (k < 3) return {};
  Eigen::MatrixXd displacement(m, 3), origin(m, 3);
  for (long i = 0; i < m; ++i) {
    origin.row(i) = predicted.row(candidates[static_cast<std::size_t>(i)].parent);
    displacement.row(i) = child.points.row(candidates[static_cast<std::size_t>(i)].child) - origin.row(i);
  }
  const double tolerance = options.neighbour_tolerance_height * height;
  std::vector<FeatureMatch> accepted;
  std::vector<std::pair<double, long>> order(static_cast<std::size_t>(m));
  for (long i = 0; i < m; ++i) {
    for (long j = 0; j < m; ++j) order[static_cast<std::size_t>(j)] = {(origin.row(j) - origin.row(i)).squaredNorm(), j};
    std::partial_sort(order.begin(), order.begin() + k + 1, order.end());
    Eigen::Vector3d median;
    std::vector<double> values(static_cast<std::size_t>(k));
    for (int axis = 0; axis < 3; ++axis) {
      for (int n = 0; n < k; ++n) values[static_cast<std::size_t>(n)] = displacement(order[static_cast<std::size_t>(n + 1)].second, axis);
      std::nth_element(values.begin(), values.begin() + k / 2, values.end());
      median(axis) = values[static_cast<std::size_t>(k / 2)];
    }
    if ((displacement.row(i).transpose() - median).norm() <= tolerance) accepted.push_back(candidates[static_cast<std::size_t>(i)]);
  }
  return accepted;
}

}  // namespace surfcap::align
