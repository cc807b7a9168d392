#include "surfcap/align/appearance_flow.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/video/tracking.hpp>

#include "surfcap/core/error.hpp"
#include "surfcap/render/rasterizer.hpp"

namespace surfcap::align {

namespace {

/// World direction of the ray through pixel (x, y) (no distortion).
Eigen::Vector3d pixel_ray(const render::Camera& camera, double x, double y) {
  const Eigen::Vector3d p((x - camera.K(0, 2)) / camera.K(0, 0), (y - camera.K(1, 2)) / camera.K(1, 1), 1.0);
  return (camera.R.transpose() * p).normalized();
}

Eigen::MatrixXd face_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::MatrixXd N(F.rows(), 3);
  for (long f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double length = n.norm();
    N.row(f) = length > 0 ? Eigen::RowVector3d((n / length).transpose()) : Eigen::RowVector3d::Zero();
  }
  return N;
}

/// The pixels of `image` in `box` as 8-bit grey.
cv::Mat to_mat(const GreyImage& image, const cv::Rect& box) {
  cv::Mat mat(box.height, box.width, CV_8U);
  for (int y = 0; y < box.height; ++y)
    for (int x = 0; x < box.width; ++x)
      mat.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(
          std::clamp(std::lround(255.0 * image.at(box.x + x, box.y + y)), 0L, 255L));
  return mat;
}

/// Component-wise weighted median of 3-vectors.
Eigen::Vector3d component_median(const std::vector<std::pair<Eigen::Vector3d, double>>& values,
                                std::vector<std::pair<double, double>>& scratch) {
  Eigen::Vector3d median;
  for (int axis = 0; axis < 3; ++axis) {
    scratch.clear();
    for (const auto& value : values) scratch.emplace_back(value.first(axis), value.second);
    median(axis) = weighted_median(scratch);
  }
  return median;
}

}  // namespace

double weighted_median(std::vector<std::pair<double, double>>& values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  double total = 0;
  for (const auto& value : values) total += value.second;
  double below = 0;  // weight of the values left of [first, last)
  auto first = values.begin(), last = values.end();
  while (last - first > 1) {
    const auto middle = first + (last - first) / 2;
    std::nth_element(first, middle, last, [](const auto& a, const auto& b) { return a.first < b.first; });
    double left = below;
    for (auto it = first; it != middle; ++it) left += it->second;
    // Values equal to the pivot may lie on either side of it: a reached half inside them is the pivot.
    if (left >= 0.5 * total) {
      last = middle;
    } else if (left + middle->second >= 0.5 * total) {
      return middle->first;
    } else {
      below = left + middle->second;
      first = middle + 1;
    }
  }
  if (first != last) return first->first;
  return std::max_element(values.begin(), values.end(), [](const auto& a, const auto& b) { return a.first < b.first; })
      ->first;
}

std::optional<double> GreyImage::sample(double x, double y) const {
  if (!(x >= 0 && y >= 0 && x <= width - 1 && y <= height - 1)) return std::nullopt;
  const int x0 = std::min(static_cast<int>(x), width - 2 < 0 ? 0 : width - 2);
  const int y0 = std::min(static_cast<int>(y), height - 2 < 0 ? 0 : height - 2);
  const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
  const double fx = x - x0, fy = y - y0;
  return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x1, y0)) + fy * ((1 - fx) * at(x0, y1) + fx * at(x1, y1));
}

std::vector<GreyImage> read_grey_images(const core::Capture& capture, int sequence, int frame) {
  std::vector<GreyImage> images;
  if (capture.sequences[static_cast<std::size_t>(sequence)].images.empty()) return images;
  for (int c = 0; c < static_cast<int>(capture.cameras.size()); ++c) {
    const auto path = capture.image_path(sequence, frame, c);
    const cv::Mat image = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
    if (image.empty()) throw core::bad_input(path, "unreadable camera image", frame);
    const auto& camera = capture.cameras[static_cast<std::size_t>(c)];
    if (image.cols != camera.width || image.rows != camera.height)
      throw core::bad_input(path, "image size differs from camera " + camera.name + " in cameras.json", frame);
    GreyImage grey;
    grey.width = image.cols;
    grey.height = image.rows;
    grey.pixels.resize(static_cast<std::size_t>(image.cols) * static_cast<std::size_t>(image.rows));
    for (int y = 0; y < image.rows; ++y)
      for (int x = 0; x < image.cols; ++x)
        grey.pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(image.cols) + static_cast<std::size_t>(x)] =
            static_cast<float>(image.at<std::uint8_t>(y, x)) / 255.0f;
    images.push_back(std::move(grey));
  }
  return images;
}

std::vector<render::Camera> capture_cameras(const core::Capture& capture) {
  std::vector<render::Camera> cameras;
  for (const auto& camera : capture.cameras) cameras.push_back(render::from_capture_camera(camera));
  return cameras;
}

bool has_distortion(const core::Capture& capture) {
  for (const auto& camera : capture.cameras)
    if (camera.distortion.cwiseAbs().maxCoeff() > 0) return true;
  return false;
}

TemplateAppearance::TemplateAppearance(const core::Mesh& root_surface, std::vector<render::Camera> cameras,
                                       std::vector<GreyImage> root_images, double mean_edge,
                                       const FlowOptions& options)
    : V_(root_surface.V),
      F_(root_surface.F),
      face_normals_(face_normals(root_surface.V, root_surface.F)),
      cameras_(std::move(cameras)),
      images_(std::move(root_images)),
      tolerance_(options.visibility_edges * mean_edge),
      min_facing_(options.min_facing) {
  if (images_.size() != cameras_.size()) throw core::internal_error("TemplateAppearance: one image per camera");
  for (const auto& camera : cameras_) depth_.push_back(render::render_visibility(V_, F_, camera).depth);
  long seen = 0;
  for (long f = 0; f < F_.rows(); ++f)
    if (value(f, Eigen::Vector3d::Constant(1.0 / 3.0))) ++seen;
  coverage_ = F_.rows() > 0 ? static_cast<double>(seen) / static_cast<double>(F_.rows()) : 0.0;
}

std::optional<double> TemplateAppearance::value(long face, const Eigen::Vector3d& b, int camera) const {
  if (camera >= 0)
    if (const auto own = sample(face, b, camera)) return own;
  return sample(face, b, -1);
}

std::optional<double> TemplateAppearance::sample(long face, const Eigen::Vector3d& b, int only) const {
  const Eigen::Vector3d x = b[0] * V_.row(F_(face, 0)).transpose() + b[1] * V_.row(F_(face, 1)).transpose() +
                            b[2] * V_.row(F_(face, 2)).transpose();
  const Eigen::Vector3d n = face_normals_.row(face).transpose();
  double sum = 0, weights = 0;
  for (std::size_t c = 0; c < cameras_.size(); ++c) {
    if (only >= 0 && static_cast<int>(c) != only) continue;
    const render::Camera& camera = cameras_[c];
    const Eigen::Vector3d towards = camera.centre() - x;
    const double facing = n.dot(towards) / towards.norm();
    if (facing < min_facing_) continue;
    const double z = camera.to_camera(x).z();
    if (z <= 0) continue;
    const Eigen::Vector2d u = camera.project(x);
    const long px = std::lround(u.x()), py = std::lround(u.y());
    if (px < 0 || py < 0 || px >= camera.width || py >= camera.height) continue;
    const float visible = depth_[c][static_cast<std::size_t>(py) * static_cast<std::size_t>(camera.width) + static_cast<std::size_t>(px)];
    if (!(z <= visible + tolerance_)) continue;  // occluded (or no surface: +inf never occludes)
    const auto grey = images_[c].sample(u.x(), u.y());
    if (!grey) continue;
    const double w = facing * facing;
    sum += w * *grey;
    weights += w;
  }
  if (weights <= 0) return std::nullopt;
  return sum / weights;
}

namespace {

/// The template's bounding box in the rendering plus `margin` pixels, within the image: flow only
/// there (the actor covers a small part of a studio image). Empty when no pixel shows the template.
cv::Rect flow_box(const render::Visibility& seen, int w, int h, int margin) {
  int x0 = w, y0 = h, x1 = -1, y1 = -1;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (seen.face[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)] >= 0) {
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
      }
  if (x1 < 0) return {};
  x0 = std::max(0, x0 - margin), y0 = std::max(0, y0 - margin);
  x1 = std::min(w - 1, x1 + margin), y1 = std::min(h - 1, y1 + margin);
  return cv::Rect(x0, y0, x1 - x0 + 1, y1 - y0 + 1);
}

/// What the template at `surface` looks like in `camera` (index `c`, the child's `actual` image
/// for the background) within `box` (flow_box): per pixel of the box (row-major) the root
/// appearance of its template point, the point itself (barycentric in the face `seen` shows) and
/// whether it is usable (1), shown but too grazing (2) or not the template's (0). Empty when no
/// pixel shows an appearance.
struct CameraPrediction {
  cv::Rect box;
  GreyImage image;
  std::vector<Eigen::Vector3d> barycentric;
  std::vector<char> valid;
  /// The index in the box's buffers of image pixel (x, y), which is in the box.
  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y - box.y) * static_cast<std::size_t>(box.width) + static_cast<std::size_t>(x - box.x);
  }
};

std::optional<CameraPrediction> predict_camera(const TemplateAppearance& appearance, const Eigen::MatrixXd& surface,
                                               const Eigen::MatrixXi& F, const Eigen::MatrixXd& normals,
                                               const render::Visibility& seen, const render::Camera& camera,
                                               std::size_t c, const GreyImage& actual, const cv::Rect& box,
                                               const FlowOptions& options) {
  if (box.empty()) return std::nullopt;
  const int w = camera.width, h = camera.height;
  // Elsewhere the child's background (median of its border pixels); template points no root
  // camera saw get the mean appearance.
  std::vector<float> border;
  for (int x = 0; x < w; ++x) border.insert(border.end(), {actual.at(x, 0), actual.at(x, h - 1)});
  for (int y = 0; y < h; ++y) border.insert(border.end(), {actual.at(0, y), actual.at(w - 1, y)});
  std::nth_element(border.begin(), border.begin() + static_cast<long>(border.size() / 2), border.end());
  const float background = border[border.size() / 2];
  const std::size_t pixels = static_cast<std::size_t>(box.width) * static_cast<std::size_t>(box.height);
  CameraPrediction prediction{box, GreyImage{box.width, box.height, std::vector<float>(pixels, background)}, {}, {}};
  GreyImage& predicted = prediction.image;
  prediction.barycentric.assign(pixels, Eigen::Vector3d::Constant(-1));
  prediction.valid.assign(pixels, 0);
  double valid_sum = 0;
  long valid_count = 0;
  const Eigen::Vector3d centre = camera.centre();
  for (int y = box.y; y < box.y + box.height; ++y)
    for (int x = box.x; x < box.x + box.width; ++x) {
      const int f = seen.face[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)];
      if (f < 0) continue;
      const std::size_t i = prediction.index(x, y);
      const Eigen::Vector3d a = surface.row(F(f, 0)), b = surface.row(F(f, 1)), d = surface.row(F(f, 2));
      const Eigen::Vector3d normal = normals.row(f).transpose();
      const Eigen::Vector3d ray = pixel_ray(camera, x, y);
      const double along = normal.dot(ray);
      if (std::abs(along) < 1e-9) continue;
      const Eigen::Vector3d hit = centre + ray * (normal.dot(a - centre) / along);
      prediction.barycentric[i] = geometry::barycentric_coordinates(hit, a, b, d);
      const auto value = appearance.value(f, prediction.barycentric[i], static_cast<int>(c));
      if (!value) continue;
      predicted.pixels[i] = static_cast<float>(*value);
      prediction.valid[i] = static_cast<char>(-along >= options.min_facing ? 1 : 2);
      valid_sum += *value;
      ++valid_count;
    }
  if (valid_count == 0) return std::nullopt;
  const float fill = static_cast<float>(valid_sum / static_cast<double>(valid_count));
  for (int y = box.y; y < box.y + box.height; ++y)
    for (int x = box.x; x < box.x + box.width; ++x) {
      const std::size_t i = prediction.index(x, y);
      if (seen.face[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)] >= 0 &&
          prediction.valid[i] == 0)
        predicted.pixels[i] = fill;
    }
  return prediction;
}

/// The first hit of the ray centre + s·ray (s > 0, `ray` unit), cast through the point (qx, qy)
/// of the image in which `child_faces` shows the child's reconstruction: the nearest hit among the
/// faces seen at the four pixel centres around the point, or the tree's ray cast where the ray
/// passes through none of them (a silhouette, faces smaller than a pixel).
std::optional<geometry::SurfacePoint> first_hit_near(const std::vector<int>& child_faces, int w, int h,
                                                     const geometry::SurfaceQuery& child,
                                                     const Eigen::Vector3d& centre, const Eigen::Vector3d& ray,
                                                     double qx, double qy) {
  const int x0 = static_cast<int>(std::floor(qx)), y0 = static_cast<int>(std::floor(qy));
  std::array<int, 4> faces{-1, -1, -1, -1};
  int count = 0;
  for (int dy = 0; dy <= 1; ++dy)
    for (int dx = 0; dx <= 1; ++dx) {
      const int x = x0 + dx, y = y0 + dy;
      if (x < 0 || y < 0 || x >= w || y >= h) continue;
      const int f = child_faces[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)];
      if (f >= 0 && std::find(faces.begin(), faces.begin() + count, f) == faces.begin() + count) faces[count++] = f;
    }
  std::optional<geometry::SurfacePoint> best;
  const Eigen::MatrixXd& V = child.vertices();
  const Eigen::MatrixXi& F = child.faces();
  for (int k = 0; k < count; ++k) {
    // Möller–Trumbore.
    const int f = faces[static_cast<std::size_t>(k)];
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Eigen::Vector3d e1 = b - a, e2 = c - a, p = ray.cross(e2);
    const double determinant = e1.dot(p);
    if (std::abs(determinant) < 1e-300) continue;
    const Eigen::Vector3d from_a = centre - a;
    const double u = from_a.dot(p) / determinant;
    if (u < 0 || u > 1) continue;
    const Eigen::Vector3d q = from_a.cross(e1);
    const double v = ray.dot(q) / determinant;
    if (v < 0 || u + v > 1) continue;
    const double s = e2.dot(q) / determinant;
    if (!(s > 0) || (best && s >= best->distance)) continue;
    best = geometry::SurfacePoint{f, centre + s * ray, Eigen::Vector3d(1 - u - v, u, v), s};
  }
  if (best) return best;
  return child.first_hit(centre, ray);
}

/// Per template vertex, the offsets (and barycentric weights) of the forward-backward consistent
/// flow pixels of one camera: the moved pixel's ray hits the child's reconstruction there.
void collect_offsets(const CameraPrediction& prediction, const render::Visibility& seen,
                     const std::vector<int>& child_faces, const render::Camera& camera, const cv::Mat& forward, const cv::Mat& backward,
                     const Eigen::MatrixXd& surface, const Eigen::MatrixXi& F, const Eigen::MatrixXd& normals,
                     const geometry::SurfaceQuery& child, double max_offset, const FlowOptions& options,
                     std::vector<std::vector<std::pair<Eigen::Vector3d, double>>>& offsets, long& pixels) {
  const int w = camera.width;
  const cv::Rect& box = prediction.box;
  const int x0 = box.x, y0 = box.y, x1 = box.x + box.width - 1, y1 = box.y + box.height - 1;
  const Eigen::Vector3d centre = camera.centre();
  const double tolerance2 = options.consistency_px * options.consistency_px;
  for (int y = y0; y <= y1; y += options.stride)
    for (int x = x0; x <= x1; x += options.stride) {
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
      const std::size_t j = prediction.index(x, y);
      if (prediction.valid[j] != 1) continue;
      const cv::Point2f flow = forward.at<cv::Point2f>(y - y0, x - x0);
      const double qx = x + flow.x, qy = y + flow.y;
      if (!(qx >= x0 && qy >= y0 && qx <= x1 && qy <= y1)) continue;
      // Forward-backward check at the nearest pixel of the moved point.
      const cv::Point2f back = backward.at<cv::Point2f>(static_cast<int>(std::lround(qy)) - y0,
                                                        static_cast<int>(std::lround(qx)) - x0);
      const double ex = flow.x + back.x, ey = flow.y + back.y;
      if (ex * ex + ey * ey > tolerance2) continue;
      const Eigen::Vector3d ray = pixel_ray(camera, qx, qy);
      const auto target = first_hit_near(child_faces, w, camera.height, child, centre, ray, qx, qy);
      if (!target) continue;
      const Eigen::Vector3d target_normal = child.face_normal(target->face);
      if (-target_normal.dot(ray) < options.min_facing) continue;
      const int f = seen.face[i];
      if (target_normal.dot(normals.row(f).transpose()) < options.normal_compatibility) continue;
      const Eigen::Vector3d& b = prediction.barycentric[j];
      const Eigen::Vector3d point = b[0] * surface.row(F(f, 0)).transpose() + b[1] * surface.row(F(f, 1)).transpose() +
                                    b[2] * surface.row(F(f, 2)).transpose();
      const Eigen::Vector3d offset = target->position - point;
      if (offset.norm() > max_offset) continue;
      for (int k = 0; k < 3; ++k)
        if (b[k] > 1e-3) offsets[static_cast<std::size_t>(F(f, k))].push_back({offset, b[k]});
      ++pixels;
    }
}

}  // namespace

FlowTargets flow_targets(const TemplateAppearance& appearance, const Eigen::MatrixXd& surface,
                         const Eigen::MatrixXi& F, const ChildViews& child, double mean_edge,
                         const FlowOptions& options) {
  const long n = surface.rows();
  FlowTargets result;
  result.targets = surface;
  result.support = Eigen::VectorXd::Zero(n);
  const auto& cameras = appearance.cameras();
  if (child.images().size() != cameras.size()) return result;
  const Eigen::MatrixXd normals = face_normals(surface, F);
  std::vector<std::vector<std::pair<Eigen::Vector3d, double>>> offsets(static_cast<std::size_t>(n));
  // DIS's medium preset down to full resolution: the texture that tells a slide along the surface
  // is a few pixels across (a print's dots, a seam) and would be blurred away at half resolution.
  const cv::Ptr<cv::DISOpticalFlow> dis = cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_MEDIUM);
  dis->setFinestScale(0);
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    const render::Camera& camera = cameras[c];
    const GreyImage& actual = child.images()[c];
    const render::Visibility seen = render::render_visibility(surface, F, camera);
    const cv::Rect box = flow_box(seen, camera.width, camera.height, options.margin_px);
    const auto prediction = predict_camera(appearance, surface, F, normals, seen, camera, c, actual, box, options);
    if (!prediction) continue;
    const cv::Mat from = to_mat(prediction->image, cv::Rect(0, 0, box.width, box.height)), to = to_mat(actual, box);
    cv::Mat forward, backward;
    dis->calc(from, to, forward);
    dis->calc(to, from, backward);
    collect_offsets(*prediction, seen, child.faces(c, camera), camera, forward, backward, surface, F, normals,
                    child.reconstruction(), options.max_offset_edges * mean_edge, options, offsets, result.pixels);
  }
  std::vector<std::pair<double, double>> scratch;
  for (long v = 0; v < n; ++v) {
    const auto& values = offsets[static_cast<std::size_t>(v)];
    if (values.empty()) continue;
    double support = 0;
    for (const auto& value : values) support += value.second;
    result.support(v) = support;
    result.targets.row(v) = surface.row(v) + component_median(values, scratch).transpose();
  }
  return result;
}

ChildViews::ChildViews(const geometry::SurfaceQuery& reconstruction, std::vector<GreyImage> images)
    : reconstruction_(&reconstruction), images_(std::move(images)), faces_(images_.size()) {}

const std::vector<int>& ChildViews::faces(std::size_t c, const render::Camera& camera) const {
  if (c >= faces_.size()) throw core::internal_error("ChildViews: no image of camera " + std::to_string(c));
  if (faces_[c].empty())
    faces_[c] = render::render_visibility(reconstruction_->vertices(), reconstruction_->faces(), camera).face;
  return faces_[c];
}

long set_flow_targets(const FlowTargets& flow, double weight, Eigen::MatrixXd& targets, Eigen::VectorXd& weights) {
  long vertices = 0;
  for (long v = 0; v < targets.rows(); ++v) {
    if (flow.support(v) <= 0) continue;
    targets.row(v) = flow.targets.row(v);
    weights(v) = weight * std::min(1.0, flow.support(v));
    ++vertices;
  }
  return vertices;
}

}  // namespace surfcap::align
