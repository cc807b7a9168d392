#include "surfcap/synth/texture.hpp"

#include <Eigen/Geometry>
#include <array>
#include <cmath>

namespace surfcap::synth {
namespace {

std::uint64_t mix(std::uint64_t x) {  // splitmix64 finaliser
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// Deterministic uniform numbers in [0, 1) for a cell.
struct CellRandom {
  std::uint64_t state;
  double next() {
    state = mix(state);
    return static_cast<double>(state >> 11) * (1.0 / 9007199254740992.0);
  }
};

Eigen::Vector3d base_color(Region region) {
  switch (region) {
    case Region::skin: return {0.86, 0.66, 0.54};
    case Region::hair: return {0.28, 0.18, 0.11};
    case Region::shirt: return {0.22, 0.38, 0.72};
    case Region::skirt: return {0.74, 0.20, 0.24};
    case Region::trousers: return {0.30, 0.30, 0.36};
    case Region::shoes: return {0.16, 0.15, 0.14};
  }
  return {0.5, 0.5, 0.5};
}

const std::array<Eigen::Vector3d, 6> feature_palette = {
    Eigen::Vector3d(0.97, 0.92, 0.20), Eigen::Vector3d(0.98, 0.98, 0.96), Eigen::Vector3d(0.05, 0.05, 0.06),
    Eigen::Vector3d(0.15, 0.75, 0.30), Eigen::Vector3d(0.98, 0.55, 0.10), Eigen::Vector3d(0.20, 0.85, 0.90)};

}  // namespace

BodyTexture::BodyTexture(std::uint64_t seed, double feature_size) : seed_(seed), cell_(feature_size) {}

Eigen::Vector3d BodyTexture::color(const Eigen::Vector3d& p, Region region) const {
  const Eigen::Vector3d q = p / cell_;
  const Eigen::Vector3d cell = q.array().floor();
  std::uint64_t key = seed_;
  for (int k = 0; k < 3; ++k) key = mix(key ^ static_cast<std::uint64_t>(static_cast<std::int64_t>(cell[k]) + (1 << 20)));
  CellRandom random{key};
  const double kind = random.next();
  const Eigen::Vector3d centre = cell.array() + 0.5 + 0.2 * (Eigen::Array3d(random.next(), random.next(), random.next()) - 0.5);
  const Eigen::Vector3d local = q - centre;
  const Eigen::Vector3d& ink = feature_palette[static_cast<std::size_t>(random.next() * feature_palette.size()) % feature_palette.size()];
  // Low-frequency shading so large areas are not flat.
  const double shade = 0.9 + 0.1 * std::sin(3.1 * p.x() / cell_ * 0.37 + 1.7 * p.y() / cell_ * 0.41) *
                                 std::cos(2.3 * p.z() / cell_ * 0.33 - 0.9 * p.y() / cell_ * 0.29);
  Eigen::Vector3d color = base_color(region) * shade;
  if (kind < 0.42) {  // a disc: a ball cut by the surface
    const double radius = 0.22 + 0.16 * random.next();
    if (local.norm() < radius) color = ink;
  } else if (kind < 0.84) {  // a rotated cube: polygons with sharp corners
    const double half = 0.16 + 0.1 * random.next();
    const Eigen::Vector3d axis = Eigen::Vector3d(random.next() - 0.5, random.next() - 0.5, random.next() - 0.5);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(M_PI * random.next(), axis.normalized()).toRotationMatrix();
    if ((R * local).cwiseAbs().maxCoeff() < half) color = ink;
  }
  return color;
}

Eigen::Vector3d surface_albedo(const Body& body, const BodyTexture& texture, long face, const Eigen::Vector3d& b) {
  int corner;
  b.maxCoeff(&corner);
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) p += b[k] * body.rest.V.row(body.rest.F(face, k)).transpose();
  return texture.color(p, body.regions[static_cast<std::size_t>(body.rest.F(face, corner))]);
}

Eigen::MatrixXd vertex_albedo(const Body& body, const BodyTexture& texture) {
  Eigen::MatrixXd colors(body.rest.vertex_count(), 3);
  for (long v = 0; v < colors.rows(); ++v)
    colors.row(v) = texture.color(body.rest.V.row(v).transpose(), body.regions[static_cast<std::size_t>(v)]).transpose();
  return colors;
}

}  // namespace surfcap::synth
