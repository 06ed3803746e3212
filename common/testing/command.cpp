#include "testing/command.h"

#include "testing/files.h"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <system_error>
#include <vector>
#include <sys/wait.h>
#include <unistd.h>

namespace gp::testing {
CommandResult run_command(const std::string& command_line) {
  static int counter = 0;
  const auto dir = std::filesystem::temp_directory_path();
  const std::string tag = std::to_string(::getpid()) + "_" + std::to_string(counter++);
  const auto out = dir / ("gp_cmd_out_" + tag), err = dir / ("gp_cmd_err_" + tag);
  const std::string full = command_line + " >'" + out.string() + "' 2>'" + err.string() + "' </dev/null";
  const int status = std::system(full.c_str());
  CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_file(out);
  r.err = read_file(err);
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return r;
}

std::string tool_path(const std::string& tool) {
  return "'" + std::string(GP_TOOLS_DIR) + "/" + tool + "'";
}

namespace {

// The folders fresh_temp_dir made in this process, removed at its exit.
class TempDirRegistry {
 public:
  ~TempDirRegistry() {
    if (std::getenv("GP_KEEP_TEST_DIRS") != nullptr) return;
    for (const auto& dir : dirs_) {
      std::error_code ignored;
      std::filesystem::remove_all(dir, ignored);
    }
  }
  void add(const std::filesystem::path& dir) { dirs_.push_back(dir); }

 private:
  std::vector<std::filesystem::path> dirs_;
};

TempDirRegistry& temp_dirs() {
  static TempDirRegistry registry;
  return registry;
}

}  // namespace

std::filesystem::path fresh_temp_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("gp_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  temp_dirs().add(dir);
  return dir;
}

std::filesystem::path shared_avatars_dir() {
  const std::filesystem::path p = GP_SHARED_AVATARS;
  std::error_code ec;
  if (std::filesystem::is_directory(p, ec)) return std::filesystem::canonical(p);
  return {};
}

std::filesystem::path source_dir() { return GP_SOURCE_DIR; }

}  // namespace gp::testing
