// A libFuzzer target for one file reader: COLOSIM_FUZZ_READER names the function of
// readers.h it feeds (set per target in tests/CMakeLists.txt). Run by scripts/fuzz.
#include <cstddef>
#include <cstdint>
#include <string>

#include "readers.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  colosim::fuzz::COLOSIM_FUZZ_READER(std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}
