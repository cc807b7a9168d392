#include "surfcap/align/coverage_targets.hpp"

#include <vector>

#include "surfcap/align/alignment_template.hpp"
#include "surfcap/align/feature_constraints.hpp"
#include "surfcap/align/observed_surface.hpp"
#include "surfcap/align/pairwise_alignment.hpp"
#include "surfcap/align/pairwise_checks.hpp"
#include "surfcap/align/silhouette_evidence.hpp"

namespace surfcap::align {

CoverageTargets::CoverageTargets(const AlignmentTemplate& model, const geometry::SurfaceQuery& target,
                                 const ObservedSurface& observed, const PairwiseOptions& options,
                                 const std::vector<render::Camera>* cameras)
    : model_(model),
      target_(target),
      observed_(observed),
      options_(options),
      cameras_(cameras),
      target_normals_(core::vertex_normals(target.vertices(), target.faces())) {}

void CoverageTargets::add(const Eigen::MatrixXd& surface, double reach, TargetSet& targets,
                          PairwiseResult& result) const {
  if (!options_.coverage.weight) return;
  const double gate = options_.checks.uncovered_distance_edges * model_.mean_edge();
  std::vector<FeatureConstraint> pulls;
  const std::vector<long> far = far_from_vertices(target_.vertices(), surface, gate);
  if (!far.empty()) {
    const geometry::SurfaceQuery aligned(surface, model_.mesh().F);
    std::optional<SilhouetteEvidence> evidence;
    for (const long i : far) {
      if (!observed_.observed_vertex(i)) continue;
      const Eigen::Vector3d x = target_.vertices().row(i).transpose();
      const auto closest = aligned.closest_point_within(x, reach);
      if (!closest || closest->face < 0 || closest->distance <= gate || closest->distance > reach ||
          !model_.observed_face(closest->face))
        continue;
      if (aligned.face_normal(closest->face).dot(target_normals_.row(i).transpose()) < options_.normal_compatibility)
        continue;
      if (cameras_ != nullptr && !cameras_->empty()) {
        if (!evidence) evidence.emplace(*cameras_, surface, model_.mesh().F, gate);
        if (!evidence->outside(x)) continue;
      }
      pulls.push_back({closest->face, closest->barycentric, x});
    }
  }
  result.coverage_constraints = static_cast<long>(pulls.size());
  add_feature_targets(surface, model_.mesh().F, pulls, *options_.coverage.weight, targets.positions, targets.weights);
}

}  // namespace surfcap::align
