#include "report/svg_to_png.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"

extern char** environ;

namespace gp::report {
namespace {

std::filesystem::path find_on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "/usr/bin:/bin");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const std::filesystem::path candidate = std::filesystem::path(dir.empty() ? "." : dir) / program;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return {};
}

}  // namespace

void svg_to_png(const std::filesystem::path& svg, const std::filesystem::path& png, int width_px) {
  const std::filesystem::path program = find_on_path("rsvg-convert");
  if (program.empty())
    throw InputError("rsvg-convert not found on PATH; install Debian's librsvg2-bin (make deps)", "rsvg-convert");
  std::vector<std::string> args = {program.string(), "--width", std::to_string(width_px), "--keep-aspect-ratio",
                                   "--background-color", "white", "--output", png.string(),
                                   svg.string()};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, program.c_str(), nullptr, nullptr, argv.data(), environ) != 0)
    throw OutputError("cannot start rsvg-convert", program.string());
  int status = 0;
  if (waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw OutputError("rsvg-convert failed to draw the pattern", svg.string());
}

}  // namespace gp::report
