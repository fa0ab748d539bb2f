#pragma once
// Human-readable summaries printed by aar-make-flightpaths (and quoted in
// flightpaths/README.md): per region / range bin sample counts, samples whose
// receiver box is not fully inside both images, the ranges where that
// happens, and the holds.

#include <string>
#include <vector>

#include "aar/flight_path.h"
#include "aar/rig.h"
#include "receiver_box.h"

namespace aar::flightpaths {

std::string DescribeConops(const StereoRig& rig, const std::vector<FlightSample>& samples, const ReceiverBox& box = {});
std::string DescribeCharacterization(const StereoRig& rig, const std::vector<FlightSample>& samples,
                                     const ReceiverBox& box = {});

}  // namespace aar::flightpaths
