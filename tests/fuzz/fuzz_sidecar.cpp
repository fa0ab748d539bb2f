// libFuzzer harness: frame and calibration sidecars (common/dataset.h).
#include "aar/dataset.h"
#include "aar/error.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::filesystem::path path = aar::fuzz::WriteInput(data, size, "000000.json");
  try {
    aar::ReadSidecar(path);
  } catch (const aar::Error&) {
  }
  aar::SidecarVerified(aar::fuzz::ScratchDir(), path, "");  // never throws
  return 0;
}
