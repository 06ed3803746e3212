// Wavefront OBJ reader and writer. Only 'v' and 'f' records carry geometry;
// texture coordinates, normals, groups and materials are skipped. Vertex order
// is the order of the 'v' records.
#include <charconv>
#include <cstdlib>
#include <fstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "io/face_builder.h"
#include "io/mesh_io.h"

namespace gp {
namespace {

// Splits a line into whitespace-separated tokens (views into `line`).
std::vector<std::string_view> tokens_of(const std::string& line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    size_t j = i;
    while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
    if (j > i) out.emplace_back(line.data() + i, j - i);
    i = j;
  }
  return out;
}

double parse_double(std::string_view token, const std::string& where) {
  const std::string s(token);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size()) throw InputError("expected a number, found '" + s + "'", where);
  return v;
}

}  // namespace

MeshReadResult read_obj(const std::filesystem::path& path, const MeshReadOptions& options) {
  const std::string file = path.string();
  std::ifstream in(path);
  if (!in) throw InputError("cannot open file", file);

  MeshReadResult result;
  result.format = "obj";
  std::vector<double> coords;
  FaceBuilder faces(file, options.triangulate);
  long long face_index = 0, line_no = 0, skipped_lines = 0;
  std::string line;
  std::vector<long long> corners;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string where = file + ": line " + std::to_string(line_no);
    const auto tok = tokens_of(line);
    if (tok.empty() || tok[0][0] == '#') continue;
    if (tok[0] == "v") {
      if (tok.size() < 4) throw InputError("vertex needs three coordinates", where);
      for (int k = 1; k <= 3; ++k) coords.push_back(parse_double(tok[k], where));
    } else if (tok[0] == "f") {
      corners.clear();
      const long long nv = static_cast<long long>(coords.size() / 3);
      for (size_t k = 1; k < tok.size(); ++k) {
        // "v", "v/vt", "v//vn" or "v/vt/vn": the position index comes first.
        std::string_view ref = tok[k].substr(0, tok[k].find('/'));
        long long idx = 0;
        const auto [ptr, ec] = std::from_chars(ref.data(), ref.data() + ref.size(), idx);
        if (ec != std::errc() || ptr != ref.data() + ref.size() || idx == 0)
          throw InputError("malformed face corner '" + std::string(tok[k]) + "'", where);
        // 1-based; negative indices count back from the last vertex read so far.
        corners.push_back(idx > 0 ? idx - 1 : nv + idx);
      }
      faces.add(corners, face_index++);
    } else if (tok[0] == "vt" || tok[0] == "vn" || tok[0] == "vp" || tok[0] == "g" ||
               tok[0] == "o" || tok[0] == "s" || tok[0] == "usemtl" || tok[0] == "mtllib") {
      continue;
    } else {
      ++skipped_lines;
    }
  }
  if (in.bad()) throw InputError("read failed", file);
  if (coords.empty() && face_index == 0) throw InputError("no vertices and no faces (empty OBJ)", file);
  const long long nv = static_cast<long long>(coords.size() / 3);
  result.mesh.V.resize(nv, 3);
  for (long long i = 0; i < nv; ++i)
    for (int k = 0; k < 3; ++k) result.mesh.V(i, k) = coords[3 * i + k];
  result.mesh.F = faces.finish(nv, result.warnings);
  if (skipped_lines > 0)
    result.warnings.push_back(file + ": ignored " + std::to_string(skipped_lines) +
                              " lines with unsupported records (lines, curves, ...)");
  return result;
}

void write_obj(const std::filesystem::path& path, const Mesh& mesh) {
  write_file_atomic(
      path,
      [&](std::ostream& out) {
        out << "# garment-pipeline mesh, metres, +y up\n";
        // Shortest representation that reads back to the same double.
        char buf[32];
        std::string text;
        text.reserve(static_cast<size_t>(mesh.V.rows()) * 60);
        for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
          text += "v";
          for (int k = 0; k < 3; ++k) {
            const auto r = std::to_chars(buf, buf + sizeof buf, mesh.V(i, k));
            text += ' ';
            text.append(buf, r.ptr);
          }
          text += '\n';
        }
        for (Eigen::Index t = 0; t < mesh.F.rows(); ++t) {
          text += "f " + std::to_string(mesh.F(t, 0) + 1) + ' ' + std::to_string(mesh.F(t, 1) + 1) +
                  ' ' + std::to_string(mesh.F(t, 2) + 1) + '\n';
        }
        out << text;
      },
      false);
}

}  // namespace gp
