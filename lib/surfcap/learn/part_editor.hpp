#pragma once
// The learnt part-based Laplacian editor (tejera2013 §IV-B): each part deforms within its learnt
// space (eq. 7); edits propagate parent → children through the frontier vertices, which anchor
// the child and are blended between child and parent. Also plain Laplacian editing and, given a
// one-part model, the global learnt basis, for comparison. Everything that does not change
// between edits is factored once; edits are const calls (the runtime reuses the editor).
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "surfcap/learn/learnt_laplacian_space.hpp"
#include "surfcap/learn/part_model.hpp"

namespace surfcap::learn {

enum class EditMethod {
  learnt,     ///< the model's parts (part-based; a one-part whole-mesh model gives the global basis)
  laplacian,  ///< plain Laplacian editing of the whole mesh with rotation updates (no learning)
};

struct EditorOptions {
  EditMethod method = EditMethod::learnt;
  int rotation_iterations = 3;   ///< rotation updates of δ after the joint solve
  double constraint_weight = 10;  ///< w of a constraint of weight 1 (energy w²‖x − c‖²)
  double frontier_weight = 10;    ///< w of the frontier anchors of child parts
  double regularisation = 0.01;   ///< μ: pull of r towards the reference pose's coefficients
  /// r is pulled to the reference pose's coefficients. true: its δ outside the learnt space is
  /// kept too, so constraints it meets reproduce it exactly (interactive editing). false: only
  /// the learnt space is used (reconstruction of other poses from sparse constraints).
  bool keep_detail = true;
  void validate() const;
};

/// A soft positional constraint on a template vertex.
struct Constraint {
  int vertex = 0;
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  double weight = 1;
};

/// Factorisations for one handle set (constrained vertices and weights); targets may change.
class PreparedHandles;

class PartEditor {
 public:
  /// `reference` n×3: the pose edits start from (defaults to the model's template).
  PartEditor(const LearntModel& model, const EditorOptions& options, const Eigen::MatrixXd& reference = {});
  ~PartEditor();
  PartEditor(PartEditor&&) noexcept;

  /// Factors everything that depends on which vertices are constrained (vertices unique).
  std::shared_ptr<const PreparedHandles> prepare(const std::vector<int>& vertices,
                                                 const std::vector<double>& weights) const;
  /// The edited mesh (n×3) for targets (k×3 in the order of the prepared vertices).
  Eigen::MatrixXd solve(const PreparedHandles& handles, const Eigen::MatrixXd& targets) const;
  /// prepare + solve (duplicate vertices: the last constraint wins).
  Eigen::MatrixXd edit(const std::vector<Constraint>& constraints) const;

  const Eigen::MatrixXd& reference() const { return reference_; }
  const std::vector<PartModel>& parts() const { return parts_; }

 private:
  struct PartSpace;
  EditorOptions options_;
  Eigen::MatrixXd reference_;
  std::vector<PartModel> parts_;
  std::vector<std::unique_ptr<PartSpace>> spaces_;
  std::unique_ptr<LearntLaplacianSpace> coupled_;  ///< every part at once: places an unconstrained root
};

}  // namespace surfcap::learn
