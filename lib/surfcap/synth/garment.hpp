#pragma once
// Secondary motion of the skirt: it hangs from the waist like a damped pendulum driven by the
// pelvis' acceleration, trails behind with air drag and flares in free fall — so it lags behind
// the body and is not a blend of the skeleton's rigid motions.

#include "surfcap/synth/motion.hpp"

namespace surfcap::synth {

struct GarmentOptions {
  double natural_frequency = 1.3;  ///< Hz, of the skirt as a pendulum
  double damping = 0.18;           ///< ratio of critical damping
  double length = 0.32;            ///< pendulum length, metres
  double drag = 0.14;              ///< trailing angle per m/s of speed, radians
  double drag_lag = 0.15;          ///< time constant of the drag's response, seconds
  double history = 2.5;            ///< seconds of past motion that still matter
};

/// Angles (radians) in the heading-aligned frame of the pelvis.
struct GarmentState {
  double swing_back = 0;  ///< hem rotated backwards (about +x) — positive when moving forward
  double swing_side = 0;  ///< hem rotated towards +x (about +z)
  double flare = 0;       ///< hem rotated outwards, all around
  double twist = 0;       ///< hem rotated about +y
};

/// The skirt's state at `time`: a causal, linear response to the root's motion over the past
/// `history` seconds, so periodic motion gives an exactly periodic garment.
GarmentState garment_at(const Skeleton& skeleton, const MotionSpec& motion, double fps, double time,
                        const GarmentOptions& options = {});

}  // namespace surfcap::synth
