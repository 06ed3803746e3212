// libFuzzer target for the JSON spec readers (see read_spec_fuzz.h).
#include "spec/fuzz/read_spec_fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  gp::fuzz::read_spec_once(data, size);
  return 0;
}
