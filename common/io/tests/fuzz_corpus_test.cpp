// Replays the fuzzing corpus kept in testdata/fuzz/read_mesh (seeds and every
// crash input found and fixed) through the readers.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "io/fuzz/read_mesh_fuzz.h"
#include "testing/command.h"

TEST_CASE("the mesh-reader fuzz corpus reads or fails cleanly", "[io][fuzz]") {
  const auto dir = gp::testing::source_dir() / "testdata" / "fuzz" / "read_mesh";
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    INFO(entry.path().filename().string());
    CHECK(gp::fuzz::read_mesh_once(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()));
    ++files;
  }
  CHECK(files >= 4);
}
