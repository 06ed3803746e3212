// Every stage in the build follows the shared command-line conventions:
// --help lists the common options, an unknown flag is a usage error (exit 2)
// reported in the one-line format.
#include <catch2/catch.hpp>

#include <filesystem>

#include "testing/command.h"

namespace fs = std::filesystem;

TEST_CASE("every stage prints --help and rejects unknown flags with exit 2", "[cli]") {
  const fs::path bin = GP_TOOLS_DIR;
  std::vector<std::string> tools;
  for (const auto& entry : fs::directory_iterator(bin))
    if (entry.is_regular_file() && (fs::status(entry).permissions() & fs::perms::owner_exec) != fs::perms::none)
      tools.push_back(entry.path().filename().string());
  std::sort(tools.begin(), tools.end());
  REQUIRE(std::find(tools.begin(), tools.end(), "register-check") != tools.end());
  for (const std::string& tool : tools) {
    INFO(tool);
    gp::testing::CommandResult help = gp::testing::run_command(gp::testing::tool_path(tool) + " --help");
    CHECK(help.exit_code == 0);
    for (const char* option : {"--out", "--force", "--threads", "--quiet", "--verbose"})
      CHECK_THAT(help.out, Catch::Contains(option));
    gp::testing::CommandResult bad =
        gp::testing::run_command(gp::testing::tool_path(tool) + " --no-such-flag");
    CHECK(bad.exit_code == 2);
    CHECK_THAT(bad.err, Catch::StartsWith(tool + ": error[usage]: "));
  }
}
