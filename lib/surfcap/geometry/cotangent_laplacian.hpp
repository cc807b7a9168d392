#pragma once
// The cotangent Laplacian L = Gᵀ A G of a triangle mesh (tejera2013 §III, eqs. 1–3), assembled
// directly from the cotangent formula.
#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace surfcap::geometry {

/// L (n×n, symmetric positive semi-definite, L·1 = 0) with the positive sign convention:
/// L_ij = −½(cot α_ij + cot β_ij) for an edge ij, L_ii = −Σ_j L_ij, so xᵀLx = Σ_edges
/// ½(cot α + cot β)(x_i − x_j)². V n×3 (metres), F m×3. Degenerate triangles (area below
/// 1e-20 m²) contribute nothing. Differential coordinates of a mesh are δ = L·V (n×3).
Eigen::SparseMatrix<double> cotangent_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace surfcap::geometry
