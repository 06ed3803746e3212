#pragma once
// Small file helpers for tests.
#include <filesystem>
#include <string>

namespace gp::testing {

// The whole file as bytes (empty if it cannot be read).
std::string read_file(const std::filesystem::path& path);

// Writes `text` to `path` (replacing it) and returns the path.
std::filesystem::path write_file(const std::filesystem::path& path, const std::string& text);

}  // namespace gp::testing
