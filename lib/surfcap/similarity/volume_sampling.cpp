#include "surfcap/similarity/volume_sampling.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"

namespace surfcap::similarity {
namespace {

struct Crossing {
  double y;
  int direction;  // +1 entering (face normal points down), -1 leaving
  bool operator<(const Crossing& other) const { return y != other.y ? y < other.y : direction < other.direction; }
};

}  // namespace

VolumeSampler::VolumeSampler(const core::Mesh& mesh, double spacing) : spacing_(spacing) {
  const auto& V = mesh.V;
  const auto& F = mesh.F;
  const Eigen::RowVector3d low = V.colwise().minCoeff(), high = V.colwise().maxCoeff();
  // The column grid is held whole: a mesh far larger than the spacing (corrupt coordinates) is
  // bad input, refused before the grid is allocated or walked.
  const double column_count = (std::floor((high(0) - low(0)) / spacing) + 2) * (std::floor((high(2) - low(2)) / spacing) + 2);
  if (!(column_count <= static_cast<double>(core::memory_budget()) / (4 * sizeof(std::vector<Crossing>))))
    throw core::Error(core::ExitCode::bad_input,
                      "the mesh spans " + std::to_string(high(0) - low(0)) + " × " + std::to_string(high(2) - low(2)) +
                          " m: too many sampling columns of " + std::to_string(spacing) + " m for the memory budget (--max-memory)");
  // Lattice indices of the first and last column/layer centre inside the bounding box.
  auto first_index = [&](double value) { return static_cast<long>(std::ceil(value / spacing - 0.5)); };
  auto last_index = [&](double value) { return static_cast<long>(std::floor(value / spacing - 0.5)); };
  const long x0 = first_index(low(0)), x1 = last_index(high(0));
  const long z0 = first_index(low(2)), z1 = last_index(high(2));
  if (x1 < x0 || z1 < z0) return;
  const long nx = x1 - x0 + 1, nz = z1 - z0 + 1;
  std::vector<std::vector<Crossing>> columns(static_cast<std::size_t>(nx * nz));
  // Column centres are nudged by an irrational fraction of a cell so that rays never pass
  // exactly through shared edges or vertices (which would double-count or miss a crossing).
  const double nudge_x = spacing * 1.234567e-4, nudge_z = spacing * 2.718281e-4;
  auto centre = [&](long index, double nudge) { return (static_cast<double>(index) + 0.5) * spacing + nudge; };

  for (long f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    // Signed doubled area of the xz projection, with the orientation of the normal's y.
    const double area = (b(2) - a(2)) * (c(0) - a(0)) - (b(0) - a(0)) * (c(2) - a(2));
    if (area == 0.0) continue;  // vertical triangle: no vertical ray crosses it
    const long i_begin = std::max(x0, first_index(std::min({a(0), b(0), c(0)}) - nudge_x));
    const long i_end = std::min(x1, last_index(std::max({a(0), b(0), c(0)}) - nudge_x));
    const long k_begin = std::max(z0, first_index(std::min({a(2), b(2), c(2)}) - nudge_z));
    const long k_end = std::min(z1, last_index(std::max({a(2), b(2), c(2)}) - nudge_z));
    for (long i = i_begin; i <= i_end; ++i) {
      const double x = centre(i, nudge_x);
      for (long k = k_begin; k <= k_end; ++k) {
        const double z = centre(k, nudge_z);
        // Barycentric coordinates in the xz plane.
        const double wa = ((b(2) - z) * (c(0) - x) - (b(0) - x) * (c(2) - z)) / area;
        const double wb = ((c(2) - z) * (a(0) - x) - (c(0) - x) * (a(2) - z)) / area;
        const double wc = 1.0 - wa - wb;
        if (wa < 0 || wb < 0 || wc < 0) continue;
        const double y = wa * a(1) + wb * b(1) + wc * c(1);
        // area is the y component of the face normal: pointing down means the upward ray enters.
        columns[static_cast<std::size_t>((i - x0) * nz + (k - z0))].push_back({y, area < 0 ? 1 : -1});
      }
    }
  }

  for (long i = 0; i < nx; ++i) {
    for (long k = 0; k < nz; ++k) {
      auto& crossings = columns[static_cast<std::size_t>(i * nz + k)];
      if (crossings.size() < 2) continue;
      std::sort(crossings.begin(), crossings.end());
      int winding = 0;
      const double x = (static_cast<double>(i + x0) + 0.5) * spacing, z = (static_cast<double>(k + z0) + 0.5) * spacing;
      for (std::size_t c = 0; c + 1 < crossings.size(); ++c) {
        winding += crossings[c].direction;
        if (winding > 0 && crossings[c + 1].y > crossings[c].y)
          intervals_.push_back({x, z, crossings[c].y, crossings[c + 1].y});
      }
    }
  }
}

Eigen::MatrixXd interior_samples(const core::Mesh& mesh, double spacing) {
  const VolumeSampler sampler(mesh, spacing);
  std::vector<double> samples;
  sampler.visit([&](double x, double y, double z, double fraction) { samples.insert(samples.end(), {x, y, z, fraction}); });
  return Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>>(
      samples.data(), static_cast<long>(samples.size() / 4), 4);
}

}  // namespace surfcap::similarity
