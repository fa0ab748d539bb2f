// libFuzzer harness: calibration YAML (common/calibration_yaml.h, stereo_calibration.h).
#include "aar/calibration_yaml.h"
#include "aar/error.h"
#include "aar/stereo_calibration.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    aar::ReadCalibration(aar::fuzz::WriteInput(data, size, "calibration.yaml"));
  } catch (const aar::Error&) {
  }
  return 0;
}
