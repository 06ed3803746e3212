#include "io/gltf_writer.h"

#include <cmath>
#include <cstring>

#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"

namespace gp {
namespace {

using Json = nlohmann::ordered_json;

constexpr int kFloat = 5126, kUnsignedShort = 5123, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

float srgb_to_linear(float c) {
  c = std::min(1.0f, std::max(0.0f, c));
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

// The binary chunk and the JSON that describes it, grown accessor by accessor.
class Builder {
 public:
  // Appends `bytes` as a buffer view and an accessor; returns the accessor index.
  int add(const void* data, size_t bytes, int component, size_t count, const char* type, int target,
          const Json& min = {}, const Json& max = {}) {
    while (bin_.size() % 4 != 0) bin_.push_back(0);
    const size_t offset = bin_.size();
    bin_.resize(offset + bytes);
    std::memcpy(bin_.data() + offset, data, bytes);
    views_.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}, {"target", target}});
    Json a = {{"bufferView", views_.size() - 1}, {"componentType", component}, {"count", count}, {"type", type}};
    if (!min.is_null()) a["min"] = min;
    if (!max.is_null()) a["max"] = max;
    accessors_.push_back(a);
    return static_cast<int>(accessors_.size() - 1);
  }
  std::vector<std::uint8_t>& bin() { return bin_; }
  Json& views() { return views_; }
  Json& accessors() { return accessors_; }

 private:
  std::vector<std::uint8_t> bin_;
  Json views_ = Json::array();
  Json accessors_ = Json::array();
};

void check_mesh(const GltfMesh& m) {
  const std::string where = "mesh '" + m.name + "'";
  if (m.V.cols() != 3 || m.F.cols() != 3 || m.V.rows() == 0 || m.F.rows() == 0)
    throw UsageError("a glTF mesh needs #V by 3 vertices and #F by 3 faces, none empty", where);
  if (!m.V.allFinite()) throw UsageError("non-finite vertex positions", where);
  if (m.F.minCoeff() < 0 || m.F.maxCoeff() >= m.V.rows()) throw UsageError("a face index is out of range", where);
  if (m.N.size() > 0 && (m.N.rows() != m.V.rows() || m.N.cols() != 3)) throw UsageError("normals must be #V by 3", where);
  if (m.colours.size() > 0 && (m.colours.rows() != m.V.rows() || m.colours.cols() != 3))
    throw UsageError("colours must be #V by 3", where);
  for (const GltfAttribute& a : m.attributes) {
    if (a.values.size() != m.V.rows()) throw UsageError("attribute '" + a.name + "' must have #V values", where);
    if (a.name.empty()) throw UsageError("an attribute needs a name", where);
    for (char c : a.name)
      if (!((c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_'))
        throw UsageError("attribute names are made of A-Z, 0-9 and '_': '" + a.name + "'", where);
  }
}

}  // namespace

std::vector<std::uint8_t> glb_bytes(const std::vector<GltfMesh>& meshes, const std::string& generator) {
  Builder b;
  Json nodes = Json::array(), gmeshes = Json::array(), materials = Json::array(), scene_nodes = Json::array();
  for (const GltfMesh& m : meshes) {
    check_mesh(m);
    const size_t n = static_cast<size_t>(m.V.rows());
    Json attributes = Json::object();
    // Positions with their exact float bounds (the validator compares them).
    std::vector<float> p(3 * n);
    Json lo = Json::array(), hi = Json::array();
    for (int c = 0; c < 3; ++c) {
      float mn = INFINITY, mx = -INFINITY;
      for (size_t v = 0; v < n; ++v) {
        p[3 * v + c] = static_cast<float>(m.V(static_cast<Eigen::Index>(v), c));
        mn = std::min(mn, p[3 * v + c]);
        mx = std::max(mx, p[3 * v + c]);
      }
      lo.push_back(static_cast<double>(mn));
      hi.push_back(static_cast<double>(mx));
    }
    attributes["POSITION"] = b.add(p.data(), p.size() * 4, kFloat, n, "VEC3", kArrayBuffer, lo, hi);
    if (m.N.size() > 0) {
      for (size_t v = 0; v < n; ++v) {
        Eigen::Vector3f q = m.N.row(static_cast<Eigen::Index>(v)).cast<float>();
        const float len = q.norm();
        // glTF normals must be unit length; a degenerate one points up.
        q = std::isfinite(len) && len > 1e-12f ? Eigen::Vector3f(q / len) : Eigen::Vector3f(0.0f, 1.0f, 0.0f);
        for (int c = 0; c < 3; ++c) p[3 * v + c] = q(c);
      }
      attributes["NORMAL"] = b.add(p.data(), p.size() * 4, kFloat, n, "VEC3", kArrayBuffer);
    }
    if (m.colours.size() > 0) {
      for (size_t v = 0; v < n; ++v)
        for (int c = 0; c < 3; ++c) p[3 * v + c] = srgb_to_linear(m.colours(static_cast<Eigen::Index>(v), c));
      attributes["COLOR_0"] = b.add(p.data(), p.size() * 4, kFloat, n, "VEC3", kArrayBuffer);
    }
    for (const GltfAttribute& a : m.attributes)
      attributes["_" + a.name] = b.add(a.values.data(), n * 4, kFloat, n, "SCALAR", kArrayBuffer);
    int indices = 0;
    const size_t ni = 3 * static_cast<size_t>(m.F.rows());
    // Unsigned shorts where they suffice (65535 is the restart value, excluded).
    if (n < 65535) {
      std::vector<std::uint16_t> idx(ni);
      for (size_t i = 0; i < ni; ++i) idx[i] = static_cast<std::uint16_t>(m.F(static_cast<Eigen::Index>(i / 3), i % 3));
      indices = b.add(idx.data(), ni * 2, kUnsignedShort, ni, "SCALAR", kElementArrayBuffer);
    } else {
      std::vector<std::uint32_t> idx(ni);
      for (size_t i = 0; i < ni; ++i) idx[i] = static_cast<std::uint32_t>(m.F(static_cast<Eigen::Index>(i / 3), i % 3));
      indices = b.add(idx.data(), ni * 4, kUnsignedInt, ni, "SCALAR", kElementArrayBuffer);
    }
    const Json base = {srgb_to_linear(m.base_colour[0]), srgb_to_linear(m.base_colour[1]),
                       srgb_to_linear(m.base_colour[2]), 1.0};
    materials.push_back({{"name", m.name},
                         {"pbrMetallicRoughness", {{"baseColorFactor", base}, {"metallicFactor", 0.0},
                                                   {"roughnessFactor", m.roughness}}},
                         {"doubleSided", m.double_sided}});
    gmeshes.push_back({{"name", m.name},
                       {"primitives", Json::array({{{"attributes", attributes},
                                                    {"indices", indices},
                                                    {"material", materials.size() - 1},
                                                    {"mode", 4}}})}});
    scene_nodes.push_back(nodes.size());
    nodes.push_back({{"name", m.name}, {"mesh", gmeshes.size() - 1}});
  }
  std::vector<std::uint8_t>& bin = b.bin();
  while (bin.size() % 4 != 0) bin.push_back(0);
  Json gltf = {{"asset", {{"version", "2.0"}, {"generator", generator}}},
               {"scene", 0},
               {"scenes", Json::array({{{"nodes", scene_nodes}}})},
               {"nodes", nodes},
               {"meshes", gmeshes},
               {"materials", materials},
               {"accessors", b.accessors()},
               {"bufferViews", b.views()},
               {"buffers", Json::array({{{"byteLength", bin.size()}}})}};
  std::string json = gltf.dump();
  while (json.size() % 4 != 0) json += ' ';
  const std::uint32_t total = static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + bin.size());
  std::vector<std::uint8_t> out;
  out.reserve(total);
  auto u32 = [&out](std::uint32_t v) {
    for (int k = 0; k < 4; ++k) out.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
  };
  u32(0x46546C67);  // "glTF"
  u32(2);
  u32(total);
  u32(static_cast<std::uint32_t>(json.size()));
  u32(0x4E4F534A);  // "JSON"
  out.insert(out.end(), json.begin(), json.end());
  u32(static_cast<std::uint32_t>(bin.size()));
  u32(0x004E4942);  // "BIN"
  out.insert(out.end(), bin.begin(), bin.end());
  return out;
}

void write_glb(const std::filesystem::path& path, const std::vector<GltfMesh>& meshes, const std::string& generator) {
  const std::vector<std::uint8_t> bytes = glb_bytes(meshes, generator);
  write_file_atomic(path, [&](std::ostream& s) {
    s.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  });
}

}  // namespace gp
