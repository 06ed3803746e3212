#include "core/atomic_file.h"

#include <fstream>
#include <system_error>
#include <unistd.h>

#include "core/error.h"

namespace fs = std::filesystem;

namespace gp {
namespace {

// A temporary name in the same folder (so that rename is atomic), unique per
// process so that parallel make jobs do not collide.
fs::path temporary_sibling(const fs::path& path, const char* tag) {
  fs::path parent = path.parent_path();
  std::string name = "." + path.filename().string() + "." + tag + "." +
                     std::to_string(static_cast<long>(::getpid()));
  return parent.empty() ? fs::path(name) : parent / name;
}

}  // namespace

void write_file_atomic(const fs::path& path, const std::function<void(std::ostream&)>& write,
                       bool binary) {
  const fs::path tmp = temporary_sibling(path, "tmp");
  try {
    {
      std::ofstream out(tmp, binary ? std::ios::binary | std::ios::trunc : std::ios::trunc);
      if (!out) throw OutputError("cannot create file", tmp.string());
      write(out);
      out.flush();
      if (!out) throw OutputError("write failed (disk full?)", tmp.string());
    }
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) throw OutputError("cannot rename into place: " + ec.message(), path.string());
  } catch (...) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw;
  }
}

StagedOutputDir::StagedOutputDir(const fs::path& final_dir, bool force)
    : final_(final_dir), force_(force) {
  if (final_.empty()) throw UsageError("empty output folder name", "--out");
  std::error_code ec;
  if (fs::exists(final_, ec) && !force_)
    throw UsageError("output folder exists; pass --force to replace it", final_.string());
  fs::path parent = final_.parent_path();
  if (!parent.empty()) {
    fs::create_directories(parent, ec);
    if (ec) throw OutputError("cannot create folder: " + ec.message(), parent.string());
  }
  staging_ = temporary_sibling(final_, "staging");
  fs::remove_all(staging_, ec);
  fs::create_directory(staging_, ec);
  if (ec) throw OutputError("cannot create staging folder: " + ec.message(), staging_.string());
}

StagedOutputDir::~StagedOutputDir() {
  if (!committed_) {
    std::error_code ignored;
    fs::remove_all(staging_, ignored);
  }
}

void StagedOutputDir::commit() {
  std::error_code ec;
  if (fs::exists(final_, ec)) {
    if (!force_) throw UsageError("output folder exists; pass --force to replace it", final_.string());
    // Move the old folder aside first so that the final name is never empty
    // for longer than two renames, and never holds a mix of old and new files.
    const fs::path old = temporary_sibling(final_, "old");
    fs::remove_all(old, ec);
    fs::rename(final_, old, ec);
    if (ec) throw OutputError("cannot replace existing folder: " + ec.message(), final_.string());
    fs::rename(staging_, final_, ec);
    if (ec) {
      std::error_code ignored;
      fs::rename(old, final_, ignored);
      throw OutputError("cannot move output into place: " + ec.message(), final_.string());
    }
    fs::remove_all(old, ec);
  } else {
    fs::rename(staging_, final_, ec);
    if (ec) throw OutputError("cannot move output into place: " + ec.message(), final_.string());
  }
  committed_ = true;
}

}  // namespace gp
