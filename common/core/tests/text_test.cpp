#include <catch2/catch.hpp>

#include "core/base64.h"
#include "core/error.h"

namespace {
std::vector<std::uint8_t> bytes(const std::string& s) { return {s.begin(), s.end()}; }
}  // namespace

TEST_CASE("base64 matches the RFC 4648 test vectors both ways", "[core]") {
  const std::pair<const char*, const char*> vectors[] = {{"", ""},         {"f", "Zg=="},         {"fo", "Zm8="},
                                                         {"foo", "Zm9v"}, {"foob", "Zm9vYg=="}, {"fooba", "Zm9vYmE="},
                                                         {"foobar", "Zm9vYmFy"}};
  for (const auto& [plain, coded] : vectors) {
    CHECK(gp::base64_encode(bytes(plain)) == coded);
    CHECK(gp::base64_decode(coded) == bytes(plain));
  }
}

TEST_CASE("base64 round-trips every byte value", "[core]") {
  std::vector<std::uint8_t> all(256);
  for (int i = 0; i < 256; ++i) all[static_cast<size_t>(i)] = static_cast<std::uint8_t>(i);
  CHECK(gp::base64_decode(gp::base64_encode(all)) == all);
}

TEST_CASE("base64 decoding rejects bad text", "[core]") {
  CHECK_THROWS_AS(gp::base64_decode("Zm9"), gp::InputError);    // length
  CHECK_THROWS_AS(gp::base64_decode("Zm9*"), gp::InputError);   // alphabet
  CHECK_THROWS_AS(gp::base64_decode("Z=9v"), gp::InputError);   // padding in the middle
}

#include "core/text_format.h"

TEST_CASE("fixed decimals never print a negative zero; XML text is escaped", "[core]") {
  CHECK(gp::format_fixed(1.23456, 2) == "1.23");
  CHECK(gp::format_fixed(-0.0001, 3) == "0.000");
  CHECK(gp::format_fixed(-0.5, 1) == "-0.5");
  CHECK(gp::escape_xml("a<b & \"c\">") == "a&lt;b &amp; &quot;c&quot;&gt;");
}
