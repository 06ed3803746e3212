#pragma once
// Running the stages as a user would, for command-line tests, and locating the
// test environment (tools, sources, the optional shared avatars).
#include <filesystem>
#include <string>

namespace gp::testing {

struct CommandResult {
  int exit_code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

// Runs `command_line` through /bin/sh with stdout and stderr captured.
CommandResult run_command(const std::string& command_line);

// "<build>/bin/<tool>", quoted for the shell.
std::string tool_path(const std::string& tool);

// A fresh, empty folder under the system's temporary folder. It is removed
// with everything in it when the test process exits, unless the environment
// sets GP_KEEP_TEST_DIRS (to look at a failing test's files).
std::filesystem::path fresh_temp_dir(const std::string& name);

// The shared registered avatars (../shared/avatars beside the checkout), or an
// empty path when that folder is absent; tests then skip with a message.
std::filesystem::path shared_avatars_dir();

std::filesystem::path source_dir();

}  // namespace gp::testing
