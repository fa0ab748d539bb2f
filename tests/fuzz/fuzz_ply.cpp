// libFuzzer harness: PLY point clouds (analyzer/ply.h).
#include "aar/analyzer/ply.h"
#include "aar/error.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    aar::ReadPly(aar::fuzz::WriteInput(data, size, "cloud.ply"));
  } catch (const aar::Error&) {
  }
  return 0;
}
