// libFuzzer target for the mesh readers (see read_mesh_fuzz.h).
#include "io/fuzz/read_mesh_fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (!gp::fuzz::read_mesh_once(data, size)) __builtin_trap();
  return 0;
}
