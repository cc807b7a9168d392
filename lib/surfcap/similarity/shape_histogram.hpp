#pragma once
// Volumetric shape histograms (Huang, Hilton & Starck 2010, as used by casas2011 §3.1): the
// interior volume binned into radial shells × elevation sectors × azimuth around the centroid.
//
// The azimuth of each (shell, elevation) cell is kept as its circular Fourier series up to
// order M instead of 2M+1 hard sectors. Rotating the shape about the vertical axis by α then
// multiplies coefficient m by e^{-imα} exactly, so the best alignment is found over continuous
// angles (the cross-correlation is evaluated with an FFT and refined by Newton steps) rather than
// over cyclic shifts of a few sectors, which keeps rotated frames within 1% of self-similarity.

#include <Eigen/Core>

#include "surfcap/core/json_document.hpp"
#include "surfcap/core/mesh.hpp"

namespace surfcap::similarity {

struct ShapeHistogramOptions {
  double voxel_size = 0.01;  ///< grid spacing of the volume sampling (metres)
  double max_radius = 1.2;   ///< outer radius of the last shell (metres); farther samples join it
  int shells = 8;            ///< radial shells, equal width
  int elevation_bins = 8;    ///< sectors of the polar angle from +y, equal angle
  int azimuth_order = 8;     ///< highest circular harmonic kept (≈ 2M+1 azimuth sectors)

  void validate() const;  ///< bad_arguments on nonsense values
  core::Json to_json() const;
  static ShapeHistogramOptions from_json(const core::Json& json);
  /// Length of a histogram vector: shells × elevation_bins × (2·azimuth_order + 1).
  long size() const { return static_cast<long>(shells) * elevation_bins * (2 * azimuth_order + 1); }
};

/// The histogram of a closed surface: per cell [c0, √2·Re c1, √2·Im c1, …, √2·Re cM, √2·Im cM]
/// with c_m = Σ_samples e^{-imφ} / total samples, so the vector's squared norm is the L2 norm
/// of the angular density (Parseval) and the c0 entries sum to 1. An open surface is sampled with
/// its holes closed (core::close_holes: a fan over each boundary loop, exact for planar cuts).
/// bad_input if the surface encloses no grid cell (tiny or flat mesh).
Eigen::VectorXd shape_histogram(const core::Mesh& mesh, const ShapeHistogramOptions& options);

/// Best rotation about +y between two histograms: the angle α that rotating `b`'s shape by
/// maximises its correlation with `a`, and the remaining L2 distance.
struct HistogramMatch {
  double distance = 0;
  double angle = 0;  ///< radians
};

enum class RotationSearch { fft, exhaustive };

HistogramMatch match_histograms(const float* a, const float* b, const ShapeHistogramOptions& layout,
                                RotationSearch search = RotationSearch::fft);
HistogramMatch match_histograms(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                                const ShapeHistogramOptions& layout, RotationSearch search = RotationSearch::fft);

}  // namespace surfcap::similarity
