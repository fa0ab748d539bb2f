#pragma once
// Held-out approaches: seeded variants of the CONOPS approach (conops.h), for
// measuring the analyzer on paths nobody tuned it on (docs/results.md,
// "Beyond the thesis: held-out scenarios"). The same legs and holds, with their ranges, speeds
// and durations, the approach's depression and lateral offset, the attitude's
// and the wander's sinusoids all drawn from a seed.

#include <cstdint>

#include "aar/rig.h"
#include "conops.h"

namespace aar::flightpaths {

/// The options of variant `seed` (splitmix64 stream of the seed, every draw
/// uniform): start 160-174.9 m at 2-3 m/s; legs ending near 120, 90 and 70 m
/// (region A), a hold of 20-50 s at 44-60 m (region B), region C entered at
/// 38 m at 0.3-0.5 m/s, a hold of 20-50 s at 33-37 m and 30-60 s at the
/// contact position; depression at the start 11-19 deg, lateral offset
/// -5..5 m; roll, pitch and yaw each a slow (30-90 s, 0.5-2 deg) and a fast
/// (8-25 s, 0.2-0.8 deg) sinusoid of random phase; the wander's amplitudes
/// 2-6 and 1-3 mm. A draw whose receiver box leaves either image at some
/// sample (ReceiverBox, ComputeBoxVisibility) is replaced by the stream's
/// next; throws aar::Error when 100 draws in a row do. `time_step_s` as
/// ConopsOptions'. A pure function of the rig, the seed and the step.
ConopsOptions ConopsVariantOptions(const StereoRig& rig, uint64_t seed, double time_step_s = 0.5);

}  // namespace aar::flightpaths
