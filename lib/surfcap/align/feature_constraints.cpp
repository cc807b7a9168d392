#include "surfcap/align/feature_constraints.hpp"

#include "surfcap/geometry/surface_query.hpp"

namespace surfcap::align {

FeatureMatching feature_constraints(const Eigen::MatrixXd& parent_surface, const Eigen::MatrixXi& F,
                                    const FrameFeatures& parent, const FrameFeatures& child,
                                    const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation,
                                    double max_distance, double height, const FeatureOptions& options) {
  FeatureMatching result;
  if (parent.size() == 0 || child.size() == 0) return result;
  const geometry::SurfaceQuery aligned(parent_surface, F);
  // Parent features that the aligned template covers, as template points.
  FrameFeatures covered;
  std::vector<geometry::SurfacePoint> anchors;
  std::vector<long> kept;
  for (long i = 0; i < parent.size(); ++i) {
    const geometry::SurfacePoint closest = aligned.closest_point(parent.points.row(i).transpose());
    if (closest.distance > max_distance) continue;
    if (aligned.face_normal(closest.face).dot(parent.normals.row(i).transpose()) < 0.5) continue;
    anchors.push_back(closest);
    kept.push_back(i);
  }
  const long k = static_cast<long>(kept.size());
  result.candidates = k;
  covered.points.resize(k, 3);
  covered.normals.resize(k, 3);
  covered.descriptors.resize(k, parent.descriptors.cols());
  Eigen::MatrixXd predicted(k, 3);
  for (long j = 0; j < k; ++j) {
    const long i = kept[static_cast<std::size_t>(j)];
    covered.points.row(j) = anchors[static_cast<std::size_t>(j)].position.transpose();
    covered.normals.row(j) = parent.normals.row(i);
    covered.descriptors.row(j) = parent.descriptors.row(i);
    predicted.row(j) = (rotation * anchors[static_cast<std::size_t>(j)].position + translation).transpose();
  }
  for (const FeatureMatch& match : match_features(covered, child, predicted, height, options)) {
    const auto& anchor = anchors[static_cast<std::size_t>(match.parent)];
    result.constraints.push_back({anchor.face, anchor.barycentric, child.points.row(match.child).transpose()});
  }
  return result;
}

void add_feature_targets(const Eigen::MatrixXd& surface, const Eigen::MatrixXi& F,
                         const std::vector<FeatureConstraint>& constraints, double weight, Eigen::MatrixXd& targets,
                         Eigen::VectorXd& weights) {
  if (constraints.empty()) return;
  Eigen::MatrixXd offset_sum = Eigen::MatrixXd::Zero(surface.rows(), 3);
  Eigen::VectorXd weight_sum = Eigen::VectorXd::Zero(surface.rows());
  for (const auto& constraint : constraints) {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    for (int c = 0; c < 3; ++c) point += constraint.barycentric(c) * surface.row(F(constraint.face, c)).transpose();
    const Eigen::Vector3d offset = constraint.target - point;
    for (int c = 0; c < 3; ++c) {
      const double w = weight * constraint.barycentric(c);
      offset_sum.row(F(constraint.face, c)) += w * offset.transpose();
      weight_sum(F(constraint.face, c)) += w;
    }
  }
  for (long v = 0; v < surface.rows(); ++v) {
    if (weight_sum(v) <= 0) continue;
    const Eigen::RowVector3d feature_target = surface.row(v) + offset_sum.row(v) / weight_sum(v);
    targets.row(v) = (weights(v) * targets.row(v) + weight_sum(v) * feature_target) / (weights(v) + weight_sum(v));
    weights(v) += weight_sum(v);
  }
}

}  // namespace surfcap::align
