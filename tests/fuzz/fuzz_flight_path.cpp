// libFuzzer harness: flight-path CSV (common/flight_path.h).
#include "aar/error.h"
#include "aar/flight_path.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    aar::ReadFlightPath(aar::fuzz::WriteInput(data, size, "path.csv"));
  } catch (const aar::Error&) {
  }
  return 0;
}
