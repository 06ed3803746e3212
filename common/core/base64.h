#pragma once
// Base64 (RFC 4648, standard alphabet, '=' padding), for binary data embedded
// in text files (the fit report's 3D models in JavaScript).
#include <cstdint>
#include <string>
#include <vector>

namespace gp {

std::string base64_encode(const std::uint8_t* data, size_t size);
inline std::string base64_encode(const std::vector<std::uint8_t>& bytes) {
  return base64_encode(bytes.data(), bytes.size());
}

// Throws InputError for characters outside the alphabet or bad padding.
std::vector<std::uint8_t> base64_decode(const std::string& text);

}  // namespace gp
