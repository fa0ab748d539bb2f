// libFuzzer harness: rig JSON (common/rig.h), and the ideal calibration it implies.
#include "aar/error.h"
#include "aar/rig.h"
#include "aar/stereo_calibration.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const aar::StereoRig rig = aar::LoadRig(aar::fuzz::WriteInput(data, size, "rig.json"));
    aar::IdealCalibration(rig);
  } catch (const aar::Error&) {
  }
  return 0;
}
