#pragma once
// Parameter map w = h⁻¹(p) (casas2011 §4.2): the weight space is sampled (step 0.05 per axis),
// each sample's high-level parameters p are measured, and a polynomial of total degree ≤ degree
// in p is fitted by least squares to each weight-space coordinate u_a.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "surfcap/core/json_document.hpp"

namespace surfcap::blend {

struct ParameterMap {
  int degree = 2;
  std::vector<std::string> parameters;       ///< names, one per weight-space axis
  std::vector<std::vector<int>> monomials;   ///< exponents of p per term
  Eigen::MatrixXd coefficients;              ///< axes × terms: u_a = Σ_k c_ak Π_j p_j^e_kj
  Eigen::MatrixXd parameter_range;           ///< parameters × 2: measured min, max
  double residual_rms = 0;                   ///< of u over the samples
  double residual_max = 0;

  /// u = h⁻¹(p), clamped to [0,1]^d.
  std::vector<double> weights_for(const std::vector<double>& p) const;
  core::Json to_json() const;
};

/// Monomials of total degree ≤ degree in `variables` variables, in graded lexicographic order.
std::vector<std::vector<int>> polynomial_terms(int variables, int degree);

/// Least-squares fit of u (samples × d) as polynomials in p (samples × d).
ParameterMap fit_parameter_map(const Eigen::MatrixXd& u, const Eigen::MatrixXd& p, int degree,
                               std::vector<std::string> names);

/// The sample grid: every point of {0, step, 2·step, …, 1}^d (axis 0 fastest).
std::vector<std::vector<double>> weight_samples(int dimensions, double step = 0.05);

}  // namespace surfcap::blend
