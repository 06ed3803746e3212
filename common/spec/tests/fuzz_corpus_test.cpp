// Replays the fuzzing corpus kept in testdata/fuzz/read_spec through the
// strict JSON readers: each input reads or throws a gp::Error.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "spec/fuzz/read_spec_fuzz.h"
#include "testing/command.h"

TEST_CASE("the spec-reader fuzz corpus reads or fails cleanly", "[spec][fuzz]") {
  const auto dir = gp::testing::source_dir() / "testdata" / "fuzz" / "read_spec";
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    INFO(entry.path().filename().string());
    CHECK_NOTHROW(gp::fuzz::read_spec_once(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()));
    ++files;
  }
  CHECK(files >= 2);
}
