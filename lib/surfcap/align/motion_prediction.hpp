#pragma once
// Motion prediction along the similarity tree: when a child's parent and grandparent are its next
// two frames of one sequence (frames f+1, f+2 → f, or f−1, f−2 → f), the child is predicted at
// constant velocity, and the coarsest patch levels also try that start (PredictionOptions). A limb
// that moves farther in a frame than the patch gate (a running stride) is matched where it went.
// A cyclic motion (run, walk) makes frames a cycle apart near copies of each other and the tree
// links such twins: an edge into the twin of the frame that follows parent and grandparent is
// one step of their motion a cycle later, and is predicted too.

#include <Eigen/Core>

#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "surfcap/core/option_table.hpp"
#include "surfcap/geometry/surface_query.hpp"

namespace surfcap::align {

class AlignmentTemplate;
struct PairwiseOptions;

/// The child is predicted at parent + `motion_prediction` × (parent − grandparent) per vertex; with
/// `twin_prediction`, also when its similarity cost to the frame after parent and grandparent is
/// at most this fraction of its cost to the parent (off: next frames only).
struct MotionPredictionOptions {
  std::optional<double> motion_prediction = 1.0;
  std::optional<double> twin_prediction = 0.25;

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    t.field("motion_prediction", self.motion_prediction,
            "Predict a child from its next two aligned frames: parent + this x (parent - grandparent)",
            core::Range::above_to(0, 2));
    t.field("twin_prediction", self.twin_prediction,
            "Also predict a child whose similarity cost to its parent's next frame is at most this fraction of its "
            "cost to the parent (a cycle's twin)",
            core::Range::above_to(0, 1));
  }
};

/// A node of the tree as a captured frame.
struct NodeFrame {
  int sequence = 0;  ///< capture sequence index
  int frame = 0;     ///< frame number
};

class MotionPredictor {
 public:
  /// `costs`: N×N similarity costs (null: no twins).
  MotionPredictor(const std::vector<NodeFrame>& nodes, const Eigen::MatrixXd* costs,
                  const MotionPredictionOptions& options);

  /// The surface of node `child` predicted from node `from` (all deformer vertices `from_positions`)
  /// and its own parent `grand` (`grand_positions`; grand < 0: none); empty when no prediction
  /// applies. A twin's prediction, a cycle's travel away, is moved onto the child's reconstruction
  /// `child_query` by the whole-body rigid initialisation.
  Eigen::MatrixXd predict(long child, long from, long grand, const Eigen::MatrixXd& from_positions,
                          const Eigen::MatrixXd& grand_positions, const AlignmentTemplate& model,
                          const geometry::SurfaceQuery& child_query, const PairwiseOptions& pairwise) const;

 private:
  /// Is `child` (not the frame after `a`, `b`) the twin of that frame?
  bool is_twin(long child, long from, const NodeFrame& a, const NodeFrame& b) const;

  const std::vector<NodeFrame>& nodes_;
  const Eigen::MatrixXd* costs_;
  const MotionPredictionOptions& options_;
  std::map<std::pair<int, int>, long> node_of_;  ///< (capture sequence, frame) → node
};

}  // namespace surfcap::align
