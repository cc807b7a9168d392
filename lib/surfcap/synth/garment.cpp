#include "surfcap/synth/garment.hpp"

#include <algorithm>
#include <cmath>

namespace surfcap::synth {

GarmentState garment_at(const Skeleton& sk, const MotionSpec& motion, double fps, double time,
                        const GarmentOptions& o) {
  constexpr double step = 0.01;  // seconds between samples of the past motion
  const int samples = static_cast<int>(o.history / step);
  const double omega = 2 * M_PI * o.natural_frequency;
  const double omega_d = omega * std::sqrt(1 - o.damping * o.damping);
  const RootState now = root_at(sk, motion, fps, time);
  const Eigen::Matrix3d to_local = rotation_y(now.heading).transpose();

  // Pelvis position and heading at the sample times, in the current heading frame.
  auto local_position = [&](double t) {
    const RootState r = root_at(sk, motion, fps, t);
    return Eigen::Vector3d(to_local * r.position);
  };
  // Yaw of the pelvis: the heading plus the pelvis' own twist in the gait.
  auto heading = [&](double t) {
    const Pose pose = pose_at(sk, motion, fps, t);
    const Eigen::Matrix3d R = rotation_y(pose.heading) * pose.local[pelvis];
    return std::atan2(R(0, 2), R(2, 2));
  };
  std::vector<Eigen::Vector3d> p(static_cast<std::size_t>(samples + 2));
  std::vector<double> h(p.size());
  for (std::size_t k = 0; k < p.size(); ++k) {
    p[k] = local_position(time - static_cast<double>(k) * step);
    h[k] = heading(time - static_cast<double>(k) * step);
  }
  // Damped pendulum driven by the pivot's acceleration (impulse response convolution),
  // drag from the exponentially lagged velocity.
  Eigen::Vector3d inertial = Eigen::Vector3d::Zero(), lagged_velocity = Eigen::Vector3d::Zero();
  double twist = 0, weight_sum = 0;
  for (int k = 0; k < samples; ++k) {
    const double tau = k * step;
    const Eigen::Vector3d velocity = (p[k] - p[k + 1]) / step;
    const Eigen::Vector3d acceleration = (p[k] - 2 * p[k + 1] + p[k + 2]) / (step * step);
    const double angular_acceleration = (h[k] - 2 * h[k + 1] + h[k + 2]) / (step * step);
    const double response = std::exp(-o.damping * omega * tau) * std::sin(omega_d * tau) / omega_d * step;
    inertial += response * acceleration / o.length;
    twist -= response * angular_acceleration;
    const double w = std::exp(-tau / o.drag_lag);
    lagged_velocity += w * velocity;
    weight_sum += w;
  }
  lagged_velocity /= weight_sum;
  GarmentState state;
  state.swing_back = std::clamp(o.drag * lagged_velocity.z() + inertial.z(), -0.8, 0.8);
  state.swing_side = std::clamp(-(o.drag * lagged_velocity.x() + inertial.x()), -0.8, 0.8);
  state.flare = std::clamp(-inertial.y(), -0.2, 0.45);
  state.twist = std::clamp(twist, -0.5, 0.5);
  return state;
}

}  // namespace surfcap::synth
