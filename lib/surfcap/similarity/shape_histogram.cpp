#include "surfcap/similarity/shape_histogram.hpp"

#include <cmath>
#include <complex>
#include <unsupported/Eigen/FFT>
#include <vector>

#include "surfcap/core/error.hpp"
#include "surfcap/core/surface_topology.hpp"
#include "surfcap/similarity/volume_sampling.hpp"

namespace surfcap::similarity {
namespace {

/// Angles at which the correlation is sampled before refinement: a power of two ≥ 4(M+1).
int correlation_samples(int order) {
  int samples = 8;
  while (samples < 4 * (order + 1)) samples *= 2;
  return samples;
}

/// corr(α) = P0 + Σ_m Re(P_m e^{imα}) and its first two derivatives.
struct Correlation {
  const std::vector<std::complex<double>>& power;
  double value(double angle) const {
    double sum = power[0].real();
    for (std::size_t m = 1; m < power.size(); ++m) sum += (power[m] * std::polar(1.0, static_cast<double>(m) * angle)).real();
    return sum;
  }
  std::pair<double, double> derivatives(double angle) const {
    double first = 0, second = 0;
    for (std::size_t m = 1; m < power.size(); ++m) {
      const double order = static_cast<double>(m);
      const std::complex<double> term = power[m] * std::polar(1.0, order * angle);
      first -= order * term.imag();
      second -= order * order * term.real();
    }
    return {first, second};
  }
};

}  // namespace

void ShapeHistogramOptions::validate() const {
  if (!(voxel_size > 0)) throw core::bad_arguments("histogram voxel size must be positive");
  if (!(max_radius > voxel_size)) throw core::bad_arguments("histogram max radius must exceed the voxel size");
  if (shells < 1 || elevation_bins < 1 || azimuth_order < 0 || azimuth_order > 64)
    throw core::bad_arguments("histogram bins: shells ≥ 1, elevation bins ≥ 1, 0 ≤ azimuth order ≤ 64");
}

core::Json ShapeHistogramOptions::to_json() const {
  return {{"voxel_size", voxel_size}, {"max_radius", max_radius}, {"shells", shells},
          {"elevation_bins", elevation_bins}, {"azimuth_order", azimuth_order}};
}

ShapeHistogramOptions ShapeHistogramOptions::from_json(const core::Json& json) {
  ShapeHistogramOptions options;
  options.voxel_size = json.value("voxel_size", options.voxel_size);
  options.max_radius = json.value("max_radius", options.max_radius);
  options.shells = json.value("shells", options.shells);
  options.elevation_bins = json.value("elevation_bins", options.elevation_bins);
  options.azimuth_order = json.value("azimuth_order", options.azimuth_order);
  return options;
}

Eigen::VectorXd shape_histogram(const core::Mesh& mesh, const ShapeHistogramOptions& options) {
  const VolumeSampler sampler(core::close_holes(mesh), options.voxel_size);
  // First pass: volume and centroid.
  double total = 0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  sampler.visit([&](double x, double y, double z, double fraction) {
    total += fraction;
    moment += fraction * Eigen::Vector3d(x, y, z);
  });
  if (total <= 0)
    throw core::Error(core::ExitCode::bad_input, "the surface encloses no volume at voxel size " +
                                                     std::to_string(options.voxel_size) + " m");
  const Eigen::RowVector3d centroid = (moment / total).transpose();
  const int order = options.azimuth_order;
  const int stride = 2 * order + 1;
  Eigen::VectorXd histogram = Eigen::VectorXd::Zero(options.size());
  std::vector<std::complex<double>> harmonics(static_cast<std::size_t>(order + 1));
  // Linear (tent) weights between neighbouring shells and elevation sectors, so that a sample
  // moving across a bin border changes the histogram continuously.
  auto split = [](double position, int bins, int& low, double& low_weight) {
    const double centre = std::clamp(position - 0.5, 0.0, static_cast<double>(bins - 1));
    low = std::min(bins - 1, static_cast<int>(centre));
    low_weight = 1.0 - (centre - low);
  };
  // Second pass: binning.
  sampler.visit([&](double x, double y, double z, double fraction) {
    const Eigen::RowVector3d p = Eigen::RowVector3d(x, y, z) - centroid;
    const double weight = fraction / total;
    const double radius = p.norm();
    const double polar = radius > 0 ? std::acos(std::clamp(p(1) / radius, -1.0, 1.0)) : 0.0;
    int shell, elevation;
    double shell_weight, elevation_weight;
    split(radius / options.max_radius * options.shells, options.shells, shell, shell_weight);
    split(polar / M_PI * options.elevation_bins, options.elevation_bins, elevation, elevation_weight);
    // e^{-imφ} with φ = atan2(z, x), by repeated multiplication.
    const double planar = std::hypot(p(0), p(2));
    const std::complex<double> step = planar > 0 ? std::complex<double>(p(0) / planar, -p(2) / planar) : 0.0;
    std::complex<double> power = 1.0;
    // Near the vertical axis a lattice-sized move turns φ a lot: harmonic m is faded out where the
    // lattice cannot resolve it (ρ ≲ m·h). The taper depends on ρ only, so rotations still
    // multiply coefficient m by e^{-imα} exactly.
    const double resolution = options.voxel_size * options.voxel_size;
    for (int m = 0; m <= order; ++m, power *= step)
      harmonics[static_cast<std::size_t>(m)] = power * (planar * planar / (planar * planar + m * m * resolution));
    for (int ds = 0; ds < 2; ++ds) {
      const double ws = ds == 0 ? shell_weight : 1.0 - shell_weight;
      if (ws <= 0 || shell + ds >= options.shells) continue;
      for (int de = 0; de < 2; ++de) {
        const double we = de == 0 ? elevation_weight : 1.0 - elevation_weight;
        if (we <= 0 || elevation + de >= options.elevation_bins) continue;
        const double w = weight * ws * we;
        double* cell =
            histogram.data() + (static_cast<long>(shell + ds) * options.elevation_bins + elevation + de) * stride;
        cell[0] += w;
        if (planar <= 0) continue;
        for (int m = 1; m <= order; ++m) {
          cell[2 * m - 1] += M_SQRT2 * w * harmonics[static_cast<std::size_t>(m)].real();
          cell[2 * m] += M_SQRT2 * w * harmonics[static_cast<std::size_t>(m)].imag();
        }
      }
    }
  });
  return histogram;
}

HistogramMatch match_histograms(const float* a, const float* b, const ShapeHistogramOptions& layout,
                                RotationSearch search) {
  const int order = layout.azimuth_order;
  const int stride = 2 * order + 1;
  const long cells = static_cast<long>(layout.shells) * layout.elevation_bins;
  // Cross power spectrum P_m = Σ_cells a_m conj(b_m) (the √2 scaling carries Parseval's factor 2).
  std::vector<std::complex<double>> power(static_cast<std::size_t>(order + 1));
  double norm_a = 0, norm_b = 0;
  for (long c = 0; c < cells; ++c) {
    const float* x = a + c * stride;
    const float* y = b + c * stride;
    power[0] += static_cast<double>(x[0]) * y[0];
    norm_a += static_cast<double>(x[0]) * x[0];
    norm_b += static_cast<double>(y[0]) * y[0];
    for (int m = 1; m <= order; ++m) {
      const double ar = x[2 * m - 1], ai = x[2 * m], br = y[2 * m - 1], bi = y[2 * m];
      power[static_cast<std::size_t>(m)] += std::complex<double>(ar * br + ai * bi, ai * br - ar * bi);
      norm_a += ar * ar + ai * ai;
      norm_b += br * br + bi * bi;
    }
  }
  const Correlation correlation{power};
  const int samples = correlation_samples(order);
  std::vector<double> values(static_cast<std::size_t>(samples));
  if (search == RotationSearch::fft && order > 0) {
    thread_local Eigen::FFT<double> fft;
    std::vector<std::complex<double>> spectrum(static_cast<std::size_t>(samples)), signal;
    for (int m = 0; m <= order; ++m) spectrum[static_cast<std::size_t>(m)] = power[static_cast<std::size_t>(m)];
    fft.inv(signal, spectrum);  // signal_k = (1/K) Σ_m P_m e^{2πimk/K}
    for (int k = 0; k < samples; ++k) values[static_cast<std::size_t>(k)] = signal[static_cast<std::size_t>(k)].real() * samples;
  } else {
    for (int k = 0; k < samples; ++k) values[static_cast<std::size_t>(k)] = correlation.value(2 * M_PI * k / samples);
  }
  const int best = static_cast<int>(std::max_element(values.begin(), values.end()) - values.begin());
  double angle = 2 * M_PI * best / samples, best_value = values[static_cast<std::size_t>(best)];
  // Newton refinement of the maximum, staying within the sampled peak.
  const double limit = 2 * M_PI / samples;
  double refined = angle;
  for (int iteration = 0; iteration < 4; ++iteration) {
    const auto [first, second] = correlation.derivatives(refined);
    if (!(second < 0)) break;
    refined = std::clamp(refined - first / second, angle - limit, angle + limit);
  }
  if (const double value = correlation.value(refined); value > best_value) {
    best_value = value;
    angle = refined;
  }
  return {std::sqrt(std::max(0.0, norm_a + norm_b - 2 * best_value)), std::remainder(angle, 2 * M_PI)};
}

HistogramMatch match_histograms(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                                const ShapeHistogramOptions& layout, RotationSearch search) {
  const Eigen::VectorXf fa = a.cast<float>(), fb = b.cast<float>();
  return match_histograms(fa.data(), fb.data(), layout, search);
}

}  // namespace surfcap::similarity
