#pragma once
// Outputs are never left half written (README.md, "Conventions shared by every stage"): files are
// written beside their final name and renamed into place; a stage's output folder is staged as a
// whole and renamed last.
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

namespace gp {

// Calls write(stream) on a temporary file next to `path`, flushes, checks the
// stream and renames the file to `path`. On any failure the temporary file is
// removed and OutputError is thrown; an existing `path` is left untouched.
void write_file_atomic(const std::filesystem::path& path,
                       const std::function<void(std::ostream&)>& write,
                       bool binary = true);

// A stage's output folder, staged under a temporary sibling name. Files are
// written into staging_path(); commit() moves the folder into place. If the
// object is destroyed without commit() (an exception unwinds), the staging
// folder is removed, so no partial output is ever visible under the final name.
class StagedOutputDir {
 public:
  // Throws UsageError if `final_dir` exists and `force` is false, OutputError
  // if the staging folder cannot be created.
  StagedOutputDir(const std::filesystem::path& final_dir, bool force);
  ~StagedOutputDir();
  StagedOutputDir(const StagedOutputDir&) = delete;
  StagedOutputDir& operator=(const StagedOutputDir&) = delete;

  const std::filesystem::path& staging_path() const { return staging_; }
  const std::filesystem::path& final_path() const { return final_; }
  // Path of `name` inside the staging folder.
  std::filesystem::path file(const std::string& name) const { return staging_ / name; }
  // Replaces any existing final folder with the staged one.
  void commit();

 private:
  std::filesystem::path final_;
  std::filesystem::path staging_;
  bool force_;
  bool committed_ = false;
};

}  // namespace gp
