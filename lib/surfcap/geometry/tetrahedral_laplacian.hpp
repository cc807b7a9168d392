#pragma once
// Volumetric meshes for deformation (casas2011 §3.2, DESIGN §4): the template's interior
// tetrahedralised with TetGen, the per-tet gradient operator G and the tetrahedral Laplacian
// L = GᵀDG (D = tet volumes), whose deformations preserve volume better than a surface Laplacian.

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace surfcap::geometry {

/// A tetrahedral mesh whose first `surface_vertices` vertices are the input surface's, in order.
struct TetMesh {
  Eigen::MatrixXd V;  ///< n×3 (surface vertices first, then interior points), metres
  Eigen::MatrixXi T;  ///< t×4 vertex indices, positively oriented
  long surface_vertices = 0;
};

struct TetrahedraliseOptions {
  /// Spacing of the interior grid points, in mean surface edge lengths (≤ 0: no interior points).
  double interior_spacing_edges = 2.5;
};

/// Tetrahedralises the volume bounded by a closed triangle surface (V n×3, F m×3): the Delaunay
/// tetrahedralisation (TetGen) of the surface vertices plus interior grid points, keeping the tets
/// whose centroid lies inside the surface. Unlike a constrained ("-p") tetrahedralisation this
/// copes with the small self-intersections and gaps of real reconstructions (arms touching the
/// torso); tets bridging a gap outside the surface are dropped. Surface vertices come first, in
/// order; some may belong to no tet (the deformer keeps them attached through surface elements).
/// Throws core::internal_error if TetGen fails.
TetMesh tetrahedralise(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const TetrahedraliseOptions& options = {});

/// Per-tet volumes (t), positive for positively oriented tets.
Eigen::VectorXd tet_volumes(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T);

/// G (3t×n): rows 3k..3k+2 are the gradient (x, y, z), constant over tet k, of the piecewise-linear
/// function with vertex values x (n). G·1 = 0, and G·V = I stacked (the gradient of the coordinates).
/// Degenerate tets (|volume| below 1e-18 m³) get zero rows.
Eigen::SparseMatrix<double> tetrahedral_gradient_operator(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T);

/// L = Gᵀ D G (n×n, symmetric positive semi-definite, L·1 = 0), D = diag(volume) repeated per axis.
Eigen::SparseMatrix<double> tetrahedral_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T);

}  // namespace surfcap::geometry
