#include "surfcap/asset/glb_trajectory.hpp"

#include <algorithm>
#include <bitset>
#include <cmath>

#include "surfcap/core/error.hpp"
#include "surfcap/core/npy.hpp"

namespace surfcap::asset::detail {
namespace {

constexpr std::int64_t fixed_point_limit = std::int64_t{1} << 24;  // |q| below: q · 2^exponent is a float32

std::uint32_t zigzag(std::int64_t d) {
  const auto v = static_cast<std::int32_t>(d);
  return (static_cast<std::uint32_t>(v) << 1) ^ static_cast<std::uint32_t>(v >> 31);
}
std::int64_t unzigzag(std::uint32_t u) { return static_cast<std::int64_t>(u >> 1) ^ -static_cast<std::int64_t>(u & 1); }

/// round(value / 2^exponent) in `q`; false beyond 24 bits (or NaN).
bool fixed_point(double value, int exponent, std::int64_t& q) {
  const double mantissa = std::nearbyint(std::ldexp(value, -exponent));
  if (!(std::abs(mantissa) < static_cast<double>(fixed_point_limit))) return false;
  q = static_cast<std::int64_t>(mantissa);
  return true;
}

float from_fixed_point(std::int64_t q, int exponent) { return static_cast<float>(std::ldexp(static_cast<double>(q), exponent)); }

/// The fixed point of a float16 displacement value such that float_to_half(q · 2^exponent)
/// restores the value the reader gets (values whose float16 step is coarser than 2^exponent keep
/// their bits; finer ones are rounded to the step).
bool half_fixed_point(std::uint16_t half, int exponent, std::int64_t& q) {
  std::int64_t rounded = 0;
  if (!fixed_point(core::half_to_float(half), exponent, rounded)) return false;
  return fixed_point(core::half_to_float(core::float_to_half(from_fixed_point(rounded, exponent))), exponent, q);
}

/// Accumulates one code into q; bad_input beyond 24 bits.
void accumulate(std::int64_t& q, std::uint32_t code, const std::filesystem::path& source, const std::string& what) {
  q += unzigzag(code);
  if (q <= -fixed_point_limit || q >= fixed_point_limit)
    throw core::bad_input(source, what + ": a trajectory leaves the 24-bit fixed-point range");
}

/// The largest power of two ≤ step_mm, within [2^-24, 2^-8] m.
int step_exponent(double step_mm) {
  if (!(step_mm > 0)) return -24;
  return std::clamp(static_cast<int>(std::floor(std::log2(step_mm / 1000))), -24, -8);
}

}  // namespace

int reference_step_exponent(double tolerance_mm) { return step_exponent(tolerance_mm / 256); }
int displacement_step_exponent(double tolerance_mm) { return step_exponent(tolerance_mm / 32); }

bool encode_references(const std::vector<float>& references, long sources, long frames, long vertices, int exponent,
                       std::vector<std::uint32_t>& codes) {
  std::vector<std::uint32_t> out(references.size());
  std::vector<std::int64_t> previous(static_cast<std::size_t>(vertices * 3));
  for (long n = 0; n < sources; ++n) {
    std::fill(previous.begin(), previous.end(), 0);
    for (long t = 0; t < frames; ++t)
      for (long i = 0; i < vertices * 3; ++i) {
        const std::size_t at = static_cast<std::size_t>((n * frames + t) * vertices * 3 + i);
        std::int64_t q = 0;
        if (!fixed_point(references[at], exponent, q)) return false;
        out[at] = zigzag(q - previous[i]);
        previous[i] = q;
      }
  }
  codes.swap(out);
  return true;
}

std::vector<float> decode_references(const std::vector<std::uint32_t>& codes, long sources, long frames,
                                     long vertices, int exponent, const std::filesystem::path& source,
                                     const std::string& what) {
  if (codes.size() != static_cast<std::size_t>(sources * frames * vertices * 3))
    throw core::bad_input(source, what + ": wrong number of reference codes");
  std::vector<float> references(codes.size());
  std::vector<std::int64_t> q(static_cast<std::size_t>(vertices * 3));
  for (long n = 0; n < sources; ++n) {
    std::fill(q.begin(), q.end(), 0);
    for (long t = 0; t < frames; ++t)
      for (long i = 0; i < vertices * 3; ++i) {
        const std::size_t at = static_cast<std::size_t>((n * frames + t) * vertices * 3 + i);
        accumulate(q[i], codes[at], source, what);
        references[at] = from_fixed_point(q[i], exponent);
      }
  }
  return references;
}

bool encode_displacements(const CharacterSpace& space, long vertices, int exponent, DisplacementCodes& codes) {
  const long nodes = space.node_count(), frames = space.frames, words = (frames + 31) / 32;
  const auto& offsets = space.displacement_offsets;
  DisplacementCodes out;
  out.masks.assign(static_cast<std::size_t>(nodes * vertices * words), 0);
  out.values.reserve(space.displacement_values.size());
  std::vector<long> entry(static_cast<std::size_t>(vertices));        // stored entry of v in the row, or -1
  std::vector<std::int64_t> previous(static_cast<std::size_t>(vertices * 3));  // q at v's previous stored frame
  for (long r = 0; r < nodes; ++r) {
    std::fill(previous.begin(), previous.end(), 0);
    for (long t = 0; t < frames; ++t) {
      std::fill(entry.begin(), entry.end(), -1);
      for (auto k = offsets[r * frames + t]; k < offsets[r * frames + t + 1]; ++k) {
        const long v = space.displacement_vertices[k];
        if (v < 0 || v >= vertices || entry[v] >= 0) return false;  // out of range or stored twice
        entry[v] = static_cast<long>(k);
      }
      for (long v = 0; v < vertices; ++v) {
        if (entry[v] < 0) continue;
        out.masks[(r * vertices + v) * words + t / 32] |= std::uint32_t{1} << (t % 32);
        for (int c = 0; c < 3; ++c) {
          std::int64_t q = 0;
          if (!half_fixed_point(space.displacement_values[entry[v] * 3 + c], exponent, q)) return false;
          out.values.push_back(zigzag(q - previous[v * 3 + c]));
          previous[v * 3 + c] = q;
        }
      }
    }
  }
  codes = std::move(out);
  return true;
}

void decode_displacements(const DisplacementCodes& codes, long vertices, int exponent, CharacterSpace& space,
                          const std::filesystem::path& source, const std::string& what) {
  const long nodes = space.node_count(), frames = space.frames, words = (frames + 31) / 32;
  if (codes.masks.size() != static_cast<std::size_t>(nodes * vertices * words) || codes.values.size() % 3 != 0)
    throw core::bad_input(source, what + ": frame masks or values of the wrong size");
  const std::uint32_t last_word = frames % 32 == 0 ? ~std::uint32_t{0} : (std::uint32_t{1} << (frames % 32)) - 1;
  std::size_t stored = 0;
  for (std::size_t i = 0; i < codes.masks.size(); ++i) {
    if (i % words == static_cast<std::size_t>(words - 1) && (codes.masks[i] & ~last_word) != 0)
      throw core::bad_input(source, what + ": a frame mask sets a frame beyond T");
    stored += std::bitset<32>(codes.masks[i]).count();
  }
  if (stored * 3 != codes.values.size())
    throw core::bad_input(source, what + ": " + std::to_string(codes.values.size() / 3) + " values for " +
                                      std::to_string(stored) + " stored entries");
  space.displacement_offsets.assign(1, 0);
  space.displacement_vertices.clear();
  space.displacement_values.clear();
  space.displacement_vertices.reserve(stored);
  space.displacement_values.reserve(3 * stored);
  std::vector<std::int64_t> q(static_cast<std::size_t>(vertices * 3));
  std::size_t at = 0;
  for (long r = 0; r < nodes; ++r) {
    std::fill(q.begin(), q.end(), 0);
    for (long t = 0; t < frames; ++t) {
      for (long v = 0; v < vertices; ++v) {
        if (!((codes.masks[(r * vertices + v) * words + t / 32] >> (t % 32)) & 1)) continue;
        space.displacement_vertices.push_back(static_cast<std::int32_t>(v));
        for (int c = 0; c < 3; ++c) {
          accumulate(q[v * 3 + c], codes.values[at++], source, what);
          space.displacement_values.push_back(core::float_to_half(from_fixed_point(q[v * 3 + c], exponent)));
        }
      }
      space.displacement_offsets.push_back(static_cast<std::int64_t>(space.displacement_vertices.size()));
    }
  }
}

QuantisedBasis quantise_basis(const Eigen::MatrixXd& basis) {
  const long n = basis.rows() / 3, k = basis.cols();
  QuantisedBasis quantised;
  quantised.codes.assign(static_cast<std::size_t>(k * n * 4), 0);
  for (long c = 0; c < k; ++c) {
    float largest = 0;
    for (long r = 0; r < 3 * n; ++r) largest = std::max(largest, std::abs(static_cast<float>(basis(r, c))));
    int exponent = 0;
    if (largest > 0) {
      std::frexp(largest, &exponent);
      exponent -= 15;  // largest / 2^exponent in [2^14, 2^15)
      if (std::lround(std::ldexp(largest, -exponent)) > 32767) ++exponent;
    }
    quantised.exponents.push_back(exponent);
    for (long v = 0; v < n; ++v)
      for (int x = 0; x < 3; ++x)
        quantised.codes[static_cast<std::size_t>((c * n + v) * 4 + x)] =
            static_cast<std::int16_t>(std::lround(std::ldexp(static_cast<float>(basis(3 * v + x, c)), -exponent)));
  }
  return quantised;
}

Eigen::MatrixXd dequantise_basis(const std::vector<std::int16_t>& codes, const std::vector<int>& exponents, long rows,
                                 const std::filesystem::path& source, const std::string& what) {
  const long k = static_cast<long>(exponents.size()), n = rows / 3;
  if (rows % 3 != 0 || static_cast<long>(codes.size()) != k * n * 4)
    throw core::bad_input(source, what + ": the basis codes do not hold " + std::to_string(k) + " columns of " +
                                      std::to_string(n) + " vertices");
  Eigen::MatrixXd basis(rows, k);
  for (long c = 0; c < k; ++c) {
    if (exponents[c] < -64 || exponents[c] > 8) throw core::bad_input(source, what + ": a basis exponent is out of range");
    for (long v = 0; v < n; ++v)
      for (int x = 0; x < 3; ++x)
        basis(3 * v + x, c) = static_cast<float>(std::ldexp(codes[static_cast<std::size_t>((c * n + v) * 4 + x)], exponents[c]));
  }
  return basis;
}

}  // namespace surfcap::asset::detail
