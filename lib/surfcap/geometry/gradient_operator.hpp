#pragma once
// Per-triangle gradient operator G and the triangle-area matrix A, so that the cotangent
// Laplacian is L = Gᵀ A G (casas2011 §3, Botsch & Sorkine "On linear variational surface
// deformation methods"). Used by Poisson reconstruction of blended deformation gradients.
#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace surfcap::geometry {

/// G (3m×n): rows 3k..3k+2 hold the (x, y, z) gradient, constant over triangle k of (V, F), of
/// the piecewise-linear function whose vertex values are x (n). G·1 = 0. Degenerate triangles
/// (area below 1e-20 m²) get zero rows.
Eigen::SparseMatrix<double> gradient_operator(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

/// A (3m×3m) diagonal: the area of triangle k repeated on rows 3k..3k+2 (square metres).
Eigen::SparseMatrix<double> triangle_area_matrix(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

/// Gᵀ A G (n×n, positive semi-definite): the cotangent Laplacian with the positive sign
/// convention (Σ_edges ½(cot α + cot β)(x_i − x_j)² = xᵀ L x).
Eigen::SparseMatrix<double> gradient_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace surfcap::geometry
