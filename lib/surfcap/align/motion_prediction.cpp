#include "surfcap/align/motion_prediction.hpp"

#include <cstdlib>

#include "surfcap/align/pairwise_alignment.hpp"

namespace surfcap::align {

MotionPredictor::MotionPredictor(const std::vector<NodeFrame>& nodes, const Eigen::MatrixXd* costs,
                                 const MotionPredictionOptions& options)
    : nodes_(nodes), costs_(costs), options_(options) {
  for (std::size_t node = 0; node < nodes.size(); ++node)
    node_of_[{nodes[node].sequence, nodes[node].frame}] = static_cast<long>(node);
}

bool MotionPredictor::is_twin(long child, long from, const NodeFrame& a, const NodeFrame& b) const {
  const auto next = node_of_.find({b.sequence, 2 * b.frame - a.frame});
  return options_.twin_prediction && costs_ != nullptr && next != node_of_.end() &&
         (*costs_)(child, next->second) <= *options_.twin_prediction * (*costs_)(child, from);
}

Eigen::MatrixXd MotionPredictor::predict(long child, long from, long grand, const Eigen::MatrixXd& from_positions,
                                         const Eigen::MatrixXd& grand_positions, const AlignmentTemplate& model,
                                         const geometry::SurfaceQuery& child_query,
                                         const PairwiseOptions& pairwise) const {
  if (!options_.motion_prediction || grand < 0) return {};
  const NodeFrame a = nodes_[static_cast<std::size_t>(grand)], b = nodes_[static_cast<std::size_t>(from)];
  const NodeFrame c = nodes_[static_cast<std::size_t>(child)];
  if (a.sequence != b.sequence || std::abs(b.frame - a.frame) != 1) return {};
  const bool next_frame = c.sequence == b.sequence && c.frame - b.frame == b.frame - a.frame;
  if (!next_frame && !is_twin(child, from, a, b)) return {};
  const long n = model.deformer().surface_vertex_count();
  Eigen::MatrixXd predicted =
      from_positions.topRows(n) + *options_.motion_prediction * (from_positions.topRows(n) - grand_positions.topRows(n));
  if (!next_frame) {
    const RigidFit fit = rigid_initialisation(predicted, core::vertex_normals(predicted, model.mesh().F), child_query,
                                              model, pairwise);
    predicted = transformed(predicted, fit);
  }
  return predicted;
}

}  // namespace surfcap::align
