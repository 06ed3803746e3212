#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/sha256.h"

namespace fs = std::filesystem;

TEST_CASE("sha256 matches the FIPS 180-4 example vectors", "[core]") {
  CHECK(gp::sha256_hex("") ==
        "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  CHECK(gp::sha256_hex("abc") ==
        "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  // Two-block message: the padding spills into a second block.
  CHECK(gp::sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq") ==
        "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST_CASE("errors carry their category and location", "[core]") {
  gp::SpecError e("must be positive", "spec.json:/measurements/waist");
  CHECK(e.code() == gp::ExitCode::spec);
  CHECK(static_cast<int>(e.code()) == 4);
  CHECK(std::string(gp::category_name(e.code())) == "spec");
  CHECK(e.message() == "must be positive (spec.json:/measurements/waist)");
}

TEST_CASE("atomic writes leave either the old or the new file", "[core]") {
  const fs::path dir = fs::temp_directory_path() / "gp_core_test_atomic";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path file = dir / "a.txt";
  gp::write_file_atomic(file, [](std::ostream& out) { out << "first"; });
  REQUIRE_THROWS_AS(gp::write_file_atomic(file,
                                          [](std::ostream& out) {
                                            out << "partial";
                                            throw gp::NumericalError("boom");
                                          }),
                    gp::NumericalError);
  std::ifstream in(file);
  std::string content;
  in >> content;
  CHECK(content == "first");
  // No temporary file is left behind.
  int entries = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    (void)e;
    ++entries;
  }
  CHECK(entries == 1);
  fs::remove_all(dir);
}

TEST_CASE("a staged output folder appears only on commit", "[core]") {
  const fs::path root = fs::temp_directory_path() / "gp_core_test_staged";
  fs::remove_all(root);
  const fs::path out = root / "out";
  {
    gp::StagedOutputDir staged(out, false);
    gp::write_file_atomic(staged.file("report.json"), [](std::ostream& o) { o << "{}"; });
    CHECK_FALSE(fs::exists(out));
  }
  CHECK_FALSE(fs::exists(out));  // destroyed without commit: nothing visible
  {
    gp::StagedOutputDir staged(out, false);
    gp::write_file_atomic(staged.file("report.json"), [](std::ostream& o) { o << "{}"; });
    staged.commit();
  }
  CHECK(fs::exists(out / "report.json"));
  CHECK_THROWS_AS(gp::StagedOutputDir(out, false), gp::UsageError);
  {
    gp::StagedOutputDir staged(out, true);
    gp::write_file_atomic(staged.file("new.json"), [](std::ostream& o) { o << "{}"; });
    staged.commit();
  }
  CHECK(fs::exists(out / "new.json"));
  CHECK_FALSE(fs::exists(out / "report.json"));
  fs::remove_all(root);
}
