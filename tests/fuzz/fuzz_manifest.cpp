// libFuzzer harness: manifest.json, opened as a dataset (common/opened_dataset.h).
#include "aar/dataset.h"
#include "aar/error.h"
#include "aar/opened_dataset.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  aar::fuzz::WriteInput(data, size, aar::kManifestName);
  try {
    aar::OpenedDataset::Open(aar::fuzz::ScratchDir());
  } catch (const aar::Error&) {
  }
  return 0;
}
