#include "surfcap/blend/parameter_map.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>

#include "surfcap/core/error.hpp"

namespace surfcap::blend {
namespace {

double monomial(const std::vector<int>& exponents, const std::vector<double>& p) {
  double value = 1;
  for (std::size_t j = 0; j < exponents.size(); ++j) value *= std::pow(p[j], exponents[j]);
  return value;
}

void add_terms(int variables, int remaining, std::vector<int>& current, std::size_t axis,
               std::vector<std::vector<int>>& terms) {
  if (axis + 1 == current.size()) {
    current[axis] = remaining;
    terms.push_back(current);
    return;
  }
  for (int e = remaining; e >= 0; --e) {
    current[axis] = e;
    add_terms(variables, remaining - e, current, axis + 1, terms);
  }
}

}  // namespace

std::vector<std::vector<int>> polynomial_terms(int variables, int degree) {
  std::vector<std::vector<int>> terms;
  for (int total = 0; total <= degree; ++total) {
    std::vector<int> current(static_cast<std::size_t>(variables), 0);
    add_terms(variables, total, current, 0, terms);
  }
  return terms;
}

std::vector<std::vector<double>> weight_samples(int dimensions, double step) {
  const int per_axis = static_cast<int>(std::lround(1.0 / step)) + 1;
  long total = 1;
  for (int a = 0; a < dimensions; ++a) total *= per_axis;
  std::vector<std::vector<double>> samples;
  for (long index = 0; index < total; ++index) {
    std::vector<double> u(static_cast<std::size_t>(dimensions));
    long rest = index;
    for (int a = 0; a < dimensions; ++a, rest /= per_axis)
      u[a] = static_cast<double>(rest % per_axis) / (per_axis - 1);
    samples.push_back(u);
  }
  return samples;
}

ParameterMap fit_parameter_map(const Eigen::MatrixXd& u, const Eigen::MatrixXd& p, int degree,
                               std::vector<std::string> names) {
  if (u.rows() != p.rows() || u.cols() != p.cols())
    throw core::bad_arguments("a parameter map needs as many parameters as weight-space axes");
  ParameterMap map;
  map.degree = degree;
  map.parameters = std::move(names);
  map.monomials = polynomial_terms(static_cast<int>(p.cols()), degree);
  map.parameter_range.resize(p.cols(), 2);
  for (long j = 0; j < p.cols(); ++j) map.parameter_range.row(j) << p.col(j).minCoeff(), p.col(j).maxCoeff();
  Eigen::MatrixXd design(p.rows(), static_cast<long>(map.monomials.size()));
  for (long s = 0; s < p.rows(); ++s) {
    std::vector<double> values(static_cast<std::size_t>(p.cols()));
    for (long j = 0; j < p.cols(); ++j) values[j] = p(s, j);
    for (std::size_t k = 0; k < map.monomials.size(); ++k) design(s, static_cast<long>(k)) = monomial(map.monomials[k], values);
  }
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> solver(design);
  map.coefficients = solver.solve(u).transpose();
  const Eigen::MatrixXd residual = design * map.coefficients.transpose() - u;
  map.residual_rms = std::sqrt(residual.squaredNorm() / static_cast<double>(std::max<long>(1, residual.size())));
  map.residual_max = residual.size() ? residual.cwiseAbs().maxCoeff() : 0.0;
  return map;
}

std::vector<double> ParameterMap::weights_for(const std::vector<double>& p) const {
  std::vector<double> u(static_cast<std::size_t>(coefficients.rows()), 0.0);
  for (long a = 0; a < coefficients.rows(); ++a) {
    for (std::size_t k = 0; k < monomials.size(); ++k) u[a] += coefficients(a, static_cast<long>(k)) * monomial(monomials[k], p);
    u[a] = std::clamp(u[a], 0.0, 1.0);
  }
  return u;
}

core::Json ParameterMap::to_json() const {
  core::Json json;
  json["degree"] = degree;
  json["parameters"] = parameters;
  json["monomials"] = monomials;
  core::Json rows = core::Json::array();
  for (long a = 0; a < coefficients.rows(); ++a) {
    std::vector<double> row(coefficients.cols());
    for (long k = 0; k < coefficients.cols(); ++k) row[k] = coefficients(a, k);
    rows.push_back(row);
  }
  json["coefficients"] = rows;
  core::Json ranges = core::Json::array();
  for (long j = 0; j < parameter_range.rows(); ++j) ranges.push_back({parameter_range(j, 0), parameter_range(j, 1)});
  json["parameter_range"] = ranges;
  json["residual_rms"] = residual_rms;
  json["residual_max"] = residual_max;
  return json;
}

}  // namespace surfcap::blend
