#include "surfcap/align/crease_targets.hpp"

#include <numbers>

#include "surfcap/align/alignment_template.hpp"
#include "surfcap/align/creases.hpp"
#include "surfcap/align/observed_surface.hpp"
#include "surfcap/align/pairwise_alignment.hpp"

namespace surfcap::align {

CreaseTargets::CreaseTargets(const AlignmentTemplate& model, const geometry::SurfaceQuery& target,
                             const ObservedSurface& observed, const CreaseOptions& options, double normal_compatibility)
    : model_(model), target_(target), observed_(observed), options_(options), normal_compatibility_(normal_compatibility) {
  if (options.weight && !model.crease_vertices().empty())
    lines_ = std::make_unique<CreaseLines>(target.vertices(), target.faces(), options.angle_deg * std::numbers::pi / 180,
                                           options.distance_edges * model.mean_edge());
}

CreaseTargets::~CreaseTargets() = default;

void CreaseTargets::add(const Eigen::MatrixXd& surface, TargetSet& targets, PairwiseResult& result) const {
  if (!lines_) return;
  const Eigen::MatrixXd normals = core::vertex_normals(surface, model_.mesh().F);
  const double gate = options_.distance_edges * model_.mean_edge();
  result.crease_constraints = 0;
  for (const int v : model_.crease_vertices()) {
    Eigen::Vector3d point;
    if (!lines_->closest(surface.row(v).transpose(), normals.row(v).transpose(), gate, normal_compatibility_, point))
      continue;
    if (observed_.partial() && !observed_.observed(target_.closest_point(point))) continue;
    targets.positions.row(v) = point.transpose();
    targets.weights(v) = *options_.weight;
    ++result.crease_constraints;
  }
}

}  // namespace surfcap::align
