#pragma once
// The template's deformation model (casas2011 §3.2 eq. 2, DESIGN §4): a tetrahedral Laplacian
// L = GᵀDG over the TetGen volume mesh of the template, soft positional constraints on surface
// vertices and iterative rotation updates of the differential coordinates (one rotation per tet,
// as-rigid-as-possible): each iteration solves
//   (L + W) x = Gᵀ D [R_e ∇x₀]_e + W c
// with R_e the rotation closest to element e's current deformation gradient (elements: the tets
// plus the surface triangles as thin shells, so no surface vertex is ever left unattached). This is eq. 2 in its
// gradient-domain (Poisson) form — δ(R) = GᵀD R∇x₀ are the rotated differential coordinates —
// which keeps the system as sparse as L itself. The matrix depends only on the constraint
// weights, so one factorisation serves every rotation iteration of a level.
//
// The volume under surface no camera saw is the reconstruction's guess, not the body's: a visual
// hull fills what no camera looks into (under a skirt, between the legs) with phantom volume, a
// multi-view stereo closes it with a flat patch. Its tets, whose surface vertices are all unseen,
// carry kUnseenRigidity of their weight, so the guessed shape does not hold the surface that
// follows it (a hem flaring out of a cone the hull made of it); the surface triangles keep their
// full weight, so the unseen surface still moves as a membrane.
//
// Parts of the template that touch at rest — a hand on the hip, thighs pressed together, an arm a
// visual hull fused to the torso — are close in space but far apart along the surface; the tets
// between them would glue them together in every frame. Those tets are cut (weight 0): each
// part keeps its own volume and its surface triangles, and they move apart when the data does.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <string>
#include <vector>

#include "surfcap/core/mesh.hpp"
#include "surfcap/core/option_table.hpp"
#include "surfcap/geometry/sparse_cholesky.hpp"
#include "surfcap/geometry/tetrahedral_laplacian.hpp"

namespace surfcap::align {

struct DeformerOptions {
  geometry::TetrahedraliseOptions tetrahedra;
  /// true, or TetGen failing on the template: a surface model (triangle gradients, areas).
  bool surface_model = false;

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    t.field("surface_model", self.surface_model, "Deform with a surface Laplacian instead of the tet volume");
    t.field("interior_spacing_edges", self.tetrahedra.interior_spacing_edges,
            "Interior points of the tet mesh: grid spacing in template mean edges (0: none)", core::Range::at_least(0));
  }
};

class VolumeDeformer {
 public:
  /// Tetrahedralises the template (closed surface) and builds G, D and L. If TetGen fails (open or
  /// self-intersecting surface) it falls back to the surface model and says so in model().
  /// `unseen` (empty, or one flag per template vertex): surface vertices no camera saw; the tets
  /// whose surface vertices are all unseen keep kUnseenRigidity of their weight. Tets joining
  /// parts far apart along the surface are cut (cut_elements()).
  VolumeDeformer(const core::Mesh& template_mesh, const DeformerOptions& options = {},
                 const std::vector<char>& unseen = {});

  /// The weight factor of a tet under unseen surface: its rigidity is a guess's, yet a positive
  /// one keeps its interior vertices attached. The constraint weights stay relative to the
  /// template's full rigidity (L's normalisation is taken before softening).
  static constexpr double kUnseenRigidity = 0.01;

  /// "tetrahedral" or "surface (…reason…)".
  const std::string& model() const { return model_; }
  long vertex_count() const { return rest_.rows(); }           ///< surface + interior
  long surface_vertex_count() const { return surface_vertices_; }
  long element_count() const { return element_weights_.size(); }
  long softened_elements() const { return softened_elements_; }  ///< tets under unseen surface
  long cut_elements() const { return cut_elements_; }  ///< tets joining parts far apart along the surface
  /// The surface vertices, sorted, where the cut tets joined parts far apart along the surface.
  const std::vector<long>& cut_vertices() const { return cut_vertices_; }
  const Eigen::MatrixXd& rest() const { return rest_; }        ///< all vertices at rest (n×3)
  const Eigen::MatrixXi& tetrahedra() const { return tetrahedra_; }

  /// A factorisation of L + diag(weights) (weights per surface vertex, ≥ 0, dimensionless:
  /// relative to the mean diagonal of L on the surface; at least one must be positive).
  geometry::SparseCholesky factor(const Eigen::VectorXd& weights) const;
  /// The same into `solver`, reusing the symbolic analysis of its previous factorisation (every
  /// weight vector gives the pattern of L): the same factor, bit for bit, at less cost.
  void factor(const Eigen::VectorXd& weights, geometry::SparseCholesky& solver) const;

  /// Iterates rotation fits and solves from `initial` (n×3 all vertices) towards `targets`
  /// (surface×3) with `weights` (the ones `solver` was factored with). Returns all vertices.
  Eigen::MatrixXd deform(const geometry::SparseCholesky& solver, const Eigen::MatrixXd& initial,
                         const Eigen::MatrixXd& targets, const Eigen::VectorXd& weights, int iterations) const;

  /// The deformation energy Σ_e D_e ‖∇x − R_e∇x₀‖² of `positions` with best-fit rotations (normalised
  /// like L); zero for rigid motions.
  double rigidity_energy(const Eigen::MatrixXd& positions) const;

 private:
  Eigen::MatrixXd rotated_gradients(const Eigen::MatrixXd& positions) const;
  /// L + diag(weights) + a tiny regulariser (the matrix factor() factors).
  Eigen::SparseMatrix<double> system(const Eigen::VectorXd& weights) const;

  std::string model_;
  Eigen::MatrixXd rest_;
  Eigen::MatrixXi tetrahedra_;
  long surface_vertices_ = 0;
  Eigen::SparseMatrix<double> G_;            ///< 3E×n
  Eigen::SparseMatrix<double> GtD_;          ///< Gᵀ D / scale
  Eigen::SparseMatrix<double> L_;            ///< GᵀDG / scale
  Eigen::VectorXd element_weights_;          ///< D per element
  Eigen::MatrixXd rest_gradients_;           ///< 3E×3: ∇x₀ per element
  double scale_ = 1;
  long softened_elements_ = 0;
  long cut_elements_ = 0;
  std::vector<long> cut_vertices_;
};

}  // namespace surfcap::align
