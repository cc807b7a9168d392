#include "surfcap/blend/parameter_map_json.hpp"

#include <numeric>
#include <string>
#include <vector>

#include "surfcap/core/error.hpp"
#include "surfcap/core/json_integer.hpp"

namespace surfcap::blend {

ParameterMap read_parameter_map(const core::Json& json, const std::filesystem::path& file, ParameterMapKeys keys,
                                int dimensions) {
  const bool gltf = keys == ParameterMapKeys::gltf;
  const auto fail = [&](const std::string& what) { return core::bad_input(file, "parameter map: " + what); };
  ParameterMap map;
  map.degree = static_cast<int>(core::integer_field(json, "degree", file, 0, 16));
  map.parameters = core::get_field<std::vector<std::string>>(json, "parameters", file);
  if (dimensions < 0) dimensions = static_cast<int>(map.parameters.size());
  if (static_cast<int>(map.parameters.size()) != dimensions) throw fail("one parameter name per weight-space axis expected");
  for (const core::Json& term : core::get_field<core::Json>(json, "monomials", file)) {
    if (!term.is_array() || static_cast<int>(term.size()) != dimensions)
      throw fail("monomial " + std::to_string(map.monomials.size()) + " needs " + std::to_string(dimensions) + " exponents");
    std::vector<int> exponents;
    for (const core::Json& exponent : term)
      exponents.push_back(static_cast<int>(core::checked_integer(exponent, "parameter map: an exponent", file, 0, map.degree)));
    if (std::accumulate(exponents.begin(), exponents.end(), 0) > map.degree)
      throw fail("monomial " + std::to_string(map.monomials.size()) + " exceeds degree " + std::to_string(map.degree));
    map.monomials.push_back(std::move(exponents));
  }
  using Rows = std::vector<std::vector<double>>;
  const auto coefficients = core::get_field<Rows>(json, "coefficients", file);
  const auto ranges = core::get_field<Rows>(json, gltf ? "parameterRange" : "parameter_range", file);
  if (static_cast<int>(coefficients.size()) != dimensions || static_cast<int>(ranges.size()) != dimensions)
    throw fail("coefficients and ranges need one row per weight-space axis");
  const auto terms = static_cast<long>(map.monomials.size());
  map.coefficients.resize(dimensions, terms);
  map.parameter_range.resize(dimensions, 2);
  for (int a = 0; a < dimensions; ++a) {
    if (static_cast<long>(coefficients[a].size()) != terms || ranges[a].size() != 2)
      throw fail("row " + std::to_string(a) + " of the coefficients or ranges has the wrong length");
    for (long k = 0; k < terms; ++k) map.coefficients(a, k) = coefficients[a][k];
    map.parameter_range.row(a) << ranges[a][0], ranges[a][1];
  }
  const char* rms = gltf ? "residualRms" : "residual_rms";
  const char* max = gltf ? "residualMax" : "residual_max";
  map.residual_rms = gltf ? core::get_field<double>(json, rms, file) : json.value(rms, 0.0);
  map.residual_max = gltf ? core::get_field<double>(json, max, file) : json.value(max, 0.0);
  return map;
}

}  // namespace surfcap::blend
