#pragma once
// One fuzz input for the JSON spec readers: the bytes are parsed as a JSON
// file and read strictly as a pose-set manifest and through the generic
// SpecObject accessors. Each must pass or throw a gp::Error; anything else is
// a bug. Shared by the libFuzzer target and the unit test that replays
// testdata/fuzz/read_spec.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "core/error.h"
#include "pose/pose_set.h"
#include "spec/json_file.h"
#include "spec/spec_object.h"

namespace gp::fuzz {

inline void read_spec_once(const uint8_t* data, size_t size) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                     ("gp_fuzz_spec_" + std::to_string(::getpid()) + ".json");
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    read_pose_set_manifest(path);
  } catch (const Error&) {
  }
  try {
    const Json j = read_json_file(path);
    SpecObject root(j, "fuzz.json");
    root.number("a", 0, Range::positive());
    root.integer("b", 0);
    root.string("c", "");
    if (auto o = root.optional_object("d")) o->finish();
    if (auto a = root.optional_array("e"))
      for (size_t i = 0; i < a->size(); ++i) a->object(i).finish();
    root.finish();
  } catch (const Error&) {
  }
  std::error_code ignored;
  std::filesystem::remove(path, ignored);
}

}  // namespace gp::fuzz
