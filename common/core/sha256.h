#pragma once
// SHA-256 (FIPS 180-4) of files and byte strings, used for the checksums that
// manifests record so that a later stage can tell whether its inputs changed.
#include <cstdint>
#include <filesystem>
#include <string>

namespace gp {

// Lower-case hex digest of `data`.
std::string sha256_hex(const std::string& data);

// Lower-case hex digest of a file's bytes; throws InputError if unreadable.
std::string sha256_file_hex(const std::filesystem::path& path);

}  // namespace gp
