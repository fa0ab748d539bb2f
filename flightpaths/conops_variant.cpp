#include "conops_variant.h"

#include <numbers>
#include <string>

#include "aar/error.h"
#include "aar/random_stream.h"
#include "receiver_box.h"

namespace aar::flightpaths {
namespace {

std::vector<Sinusoid> Sinusoids(RandomStream& s, double slow_lo, double slow_hi, double slow_period_lo,
                                double slow_period_hi, double fast_lo, double fast_hi, double fast_period_lo,
                                double fast_period_hi) {
  std::vector<Sinusoid> terms(2);
  terms[0] = {s.Uniform(slow_lo, slow_hi), s.Uniform(slow_period_lo, slow_period_hi),
              s.Uniform(0.0, 2.0 * std::numbers::pi)};
  terms[1] = {s.Uniform(fast_lo, fast_hi), s.Uniform(fast_period_lo, fast_period_hi),
              s.Uniform(0.0, 2.0 * std::numbers::pi)};
  return terms;
}

ConopsOptions Draw(RandomStream& s, double time_step_s) {
  ConopsOptions o;
  o.time_step_s = time_step_s;
  o.start_range_m = s.Uniform(160.0, 174.9);
  o.start_speed_mps = s.Uniform(2.0, 3.0);
  o.far_depression_deg = s.Uniform(11.0, 19.0);
  o.far_lateral_offset_m = s.Uniform(-5.0, 5.0);
  o.lateral_zero_range_m = s.Uniform(40.0, 50.0);
  o.legs = {
      {s.Uniform(112.0, 128.0), s.Uniform(1.6, 2.4)},  // region A
      {s.Uniform(85.0, 95.0), s.Uniform(1.1, 1.6)},
      {s.Uniform(66.0, 74.0), s.Uniform(0.8, 1.2)},
      {s.Uniform(44.0, 60.0), 0.0, s.Uniform(0.15, 0.3), s.Uniform(20.0, 50.0)},  // hold in region B
      {s.Uniform(40.0, 43.0), s.Uniform(0.4, 0.6)},
      {38.0, s.Uniform(0.3, 0.5)},                                                // into region C
      {s.Uniform(33.0, 37.0), 0.0, s.Uniform(0.15, 0.3), s.Uniform(20.0, 50.0)},  // hold in region C
      {0.0, 0.0, s.Uniform(0.15, 0.3), s.Uniform(30.0, 60.0)},                    // contact position
  };
  o.roll = Sinusoids(s, 0.5, 2.0, 30.0, 90.0, 0.2, 0.8, 8.0, 25.0);
  o.pitch = Sinusoids(s, 0.5, 2.0, 30.0, 90.0, 0.2, 0.8, 8.0, 25.0);
  o.yaw = Sinusoids(s, 0.5, 2.0, 30.0, 90.0, 0.2, 0.8, 8.0, 25.0);
  o.wander_x = Sinusoids(s, 0.002, 0.006, 5.0, 10.0, 0.001, 0.003, 2.0, 4.0);
  o.wander_y = Sinusoids(s, 0.002, 0.006, 5.0, 10.0, 0.001, 0.003, 2.0, 4.0);
  o.wander_z = Sinusoids(s, 0.002, 0.006, 5.0, 10.0, 0.001, 0.003, 2.0, 4.0);
  return o;
}

}  // namespace

ConopsOptions ConopsVariantOptions(const StereoRig& rig, uint64_t seed, double time_step_s) {
  RandomStream stream(seed);
  const ReceiverBox box;
  constexpr int kDraws = 100;
  for (int draw = 0; draw < kDraws; ++draw) {
    const ConopsOptions options = Draw(stream, time_step_s);
    bool in_view = true;
    for (const FlightSample& sample : GenerateConops(rig, options)) {
      if (!ComputeBoxVisibility(rig, box, sample.tanker_from_receiver).FullyInBoth()) {
        in_view = false;
        break;
      }
    }
    if (in_view) return options;
  }
  throw Error("conops variant " + std::to_string(seed) + ": the receiver leaves the images in " +
              std::to_string(kDraws) + " draws in a row (a rig whose cameras see too little of the approach?)");
}

}  // namespace aar::flightpaths
