// PLY reader and writer (Greg Turk's format, as documented by Paul Bourke:
// http://paulbourke.net/dataformats/ply/). The reader keeps the vertex order of
// the file and loads every scalar property besides x, y, z as a named field.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "io/face_builder.h"
#include "io/mesh_io.h"

namespace gp {
namespace {

enum class PlyType { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

bool parse_type(const std::string& s, PlyType& t) {
  static const std::pair<const char*, PlyType> names[] = {
      {"char", PlyType::int8},     {"int8", PlyType::int8},      {"uchar", PlyType::uint8},
      {"uint8", PlyType::uint8},   {"short", PlyType::int16},    {"int16", PlyType::int16},
      {"ushort", PlyType::uint16}, {"uint16", PlyType::uint16},  {"int", PlyType::int32},
      {"int32", PlyType::int32},   {"uint", PlyType::uint32},    {"uint32", PlyType::uint32},
      {"float", PlyType::float32}, {"float32", PlyType::float32}, {"double", PlyType::float64},
      {"float64", PlyType::float64}};
  for (const auto& [name, type] : names)
    if (s == name) {
      t = type;
      return true;
    }
  return false;
}

int type_size(PlyType t) {
  switch (t) {
    case PlyType::int8: case PlyType::uint8: return 1;
    case PlyType::int16: case PlyType::uint16: return 2;
    case PlyType::int32: case PlyType::uint32: case PlyType::float32: return 4;
    case PlyType::float64: return 8;
  }
  return 0;
}

struct Property {
  std::string name;
  PlyType type = PlyType::float32;
  bool is_list = false;
  PlyType count_type = PlyType::uint8;
};

struct Element {
  std::string name;
  long long count = 0;
  std::vector<Property> properties;
};

enum class Encoding { ascii, binary_le, binary_be };

bool host_is_little_endian() {
  const uint16_t probe = 1;
  unsigned char first;
  std::memcpy(&first, &probe, 1);
  return first == 1;
}

// Reads values of one element instance from either encoding.
class ValueReader {
 public:
  ValueReader(std::istream& in, Encoding enc, std::string file)
      : in_(in), enc_(enc), file_(std::move(file)) {}

  double read(PlyType t, const std::string& where) {
    if (enc_ == Encoding::ascii) return read_ascii(where);
    unsigned char buf[8];
    const int n = type_size(t);
    in_.read(reinterpret_cast<char*>(buf), n);
    if (in_.gcount() != n) throw InputError("file ends early (truncated binary PLY)", file_ + ": " + where);
    const bool swap = (enc_ == Encoding::binary_be) == host_is_little_endian();
    if (swap) std::reverse(buf, buf + n);
    switch (t) {
      case PlyType::int8: { int8_t v; std::memcpy(&v, buf, 1); return v; }
      case PlyType::uint8: { uint8_t v; std::memcpy(&v, buf, 1); return v; }
      case PlyType::int16: { int16_t v; std::memcpy(&v, buf, 2); return v; }
      case PlyType::uint16: { uint16_t v; std::memcpy(&v, buf, 2); return v; }
      case PlyType::int32: { int32_t v; std::memcpy(&v, buf, 4); return v; }
      case PlyType::uint32: { uint32_t v; std::memcpy(&v, buf, 4); return v; }
      case PlyType::float32: { float v; std::memcpy(&v, buf, 4); return v; }
      case PlyType::float64: { double v; std::memcpy(&v, buf, 8); return v; }
    }
    return 0;
  }

  // In ASCII files each element instance is one line.
  void end_instance() {
    have_line_ = false;
    pos_ = 0;
  }

 private:
  double read_ascii(const std::string& where) {
    // Each element instance is one line; blank lines between instances are skipped.
    while (!have_line_) {
      if (!std::getline(in_, line_))
        throw InputError("file ends early (truncated ASCII PLY)", file_ + ": " + where);
      pos_ = 0;
      while (pos_ < line_.size() && std::isspace(static_cast<unsigned char>(line_[pos_]))) ++pos_;
      have_line_ = pos_ < line_.size();
    }
    while (pos_ < line_.size() && std::isspace(static_cast<unsigned char>(line_[pos_]))) ++pos_;
    if (pos_ >= line_.size()) throw InputError("line has too few values", file_ + ": " + where);
    const char* begin = line_.c_str() + pos_;
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (end == begin) {
      std::string token = line_.substr(pos_, line_.find_first_of(" \t\r", pos_) - pos_);
      throw InputError("expected a number, found '" + token + "'", file_ + ": " + where);
    }
    pos_ += static_cast<size_t>(end - begin);
    return v;
  }

  std::istream& in_;
  Encoding enc_;
  std::string file_;
  std::string line_;
  size_t pos_ = 0;
  bool have_line_ = false;
};

bool is_integer_type(PlyType t) { return t != PlyType::float32 && t != PlyType::float64; }

}  // namespace

namespace {

struct PlyHeader {
  Encoding enc = Encoding::ascii;
  std::vector<Element> elements;
};

// The header after the "ply" line, up to end_header; `in` is left at the body.
PlyHeader read_header(std::istream& in, const std::string& file) {
  PlyHeader h;
  std::string line;
  bool have_format = false;
  long long line_no = 1;
  while (true) {
    if (!std::getline(in, line)) throw InputError("header has no end_header line", file);
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    const std::string where = file + ": header line " + std::to_string(line_no);
    if (key == "end_header") break;
    if (key.empty() || key == "comment" || key == "obj_info") continue;
    if (key == "format") {
      std::string fmt, version;
      ls >> fmt >> version;
      if (fmt == "ascii") h.enc = Encoding::ascii;
      else if (fmt == "binary_little_endian") h.enc = Encoding::binary_le;
      else if (fmt == "binary_big_endian") h.enc = Encoding::binary_be;
      else throw InputError("unknown PLY format '" + fmt + "'", where);
      have_format = true;
    } else if (key == "element") {
      Element e;
      if (!(ls >> e.name >> e.count) || e.count < 0)
        throw InputError("malformed element line '" + line + "'", where);
      h.elements.push_back(e);
    } else if (key == "property") {
      if (h.elements.empty()) throw InputError("property before any element", where);
      Property p;
      std::string type;
      ls >> type;
      if (type == "list") {
        std::string count_type, item_type;
        ls >> count_type >> item_type >> p.name;
        if (!parse_type(count_type, p.count_type) || !parse_type(item_type, p.type) ||
            !is_integer_type(p.count_type) || p.name.empty())
          throw InputError("malformed list property '" + line + "'", where);
        p.is_list = true;
      } else {
        ls >> p.name;
        if (!parse_type(type, p.type) || p.name.empty())
          throw InputError("malformed property '" + line + "'", where);
      }
      h.elements.back().properties.push_back(p);
    } else {
      throw InputError("unknown header keyword '" + key + "'", where);
    }
  }
  if (!have_format) throw InputError("header has no format line", file);
  return h;
}

// Every instance of an element with properties takes at least one byte, so
// a count beyond the bytes after the header is a corrupt file, not a
// reason to allocate or loop that often; an element without properties
// would be read without consuming anything. Also: a vertex element with
// scalar x, y, z.
void check_elements(std::istream& in, const std::vector<Element>& elements, const std::string& file) {
  const std::streamoff body_start = in.tellg();
  in.seekg(0, std::ios::end);
  const std::streamoff body_bytes = in.tellg() - body_start;
  in.seekg(body_start);
  for (const Element& e : elements) {
    if (e.count > 0 && e.properties.empty())
      throw InputError("element '" + e.name + "' has " + std::to_string(e.count) + " instances but no properties",
                       file);
    if (e.count > body_bytes)
      throw InputError("element '" + e.name + "' declares " + std::to_string(e.count) +
                           " instances, more than the " + std::to_string(body_bytes) + " bytes after the header",
                       file);
  }
  const Element* vertex_el = nullptr;
  for (const Element& e : elements)
    if (e.name == "vertex") vertex_el = &e;
  if (!vertex_el) throw InputError("no 'vertex' element", file);
  for (const char* axis : {"x", "y", "z"}) {
    bool found = false;
    for (const Property& p : vertex_el->properties) found |= (p.name == axis && !p.is_list);
    if (!found) throw InputError(std::string("vertex element has no scalar property '") + axis + "'", file);
  }
}

// The vertex element: positions, and every other scalar property as a field.
void read_vertices(ValueReader& reader, const Element& e, Mesh& mesh) {
  mesh.V.resize(e.count, 3);
  std::vector<int> field_of(e.properties.size(), -1);
  for (size_t k = 0; k < e.properties.size(); ++k) {
    const Property& p = e.properties[k];
    if (p.is_list || p.name == "x" || p.name == "y" || p.name == "z") continue;
    field_of[k] = static_cast<int>(mesh.vertex_fields.size());
    mesh.vertex_fields.push_back({p.name, Eigen::VectorXd(e.count)});
  }
  for (long long i = 0; i < e.count; ++i) {
    const std::string where = "vertex " + std::to_string(i);
    for (size_t k = 0; k < e.properties.size(); ++k) {
      const Property& p = e.properties[k];
      if (p.is_list) {
        const long long n = static_cast<long long>(reader.read(p.count_type, where));
        for (long long j = 0; j < n; ++j) reader.read(p.type, where);
        continue;
      }
      const double v = reader.read(p.type, where);
      if (p.name == "x") mesh.V(i, 0) = v;
      else if (p.name == "y") mesh.V(i, 1) = v;
      else if (p.name == "z") mesh.V(i, 2) = v;
      else mesh.vertex_fields[field_of[k]].values(i) = v;
    }
    reader.end_instance();
  }
}

// The face element: corners into `faces` (triangulated there), and every
// scalar property as a field with one value per triangle added.
void read_faces(ValueReader& reader, const Element& e, FaceBuilder& faces, const std::string& file,
                std::vector<std::string>& scalar_names, std::vector<std::vector<double>>& scalar_values) {
  const Property* list = nullptr;
  for (const Property& p : e.properties)
    if (p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index")) list = &p;
  if (!list) throw InputError("face element has no 'vertex_indices' list", file);
  for (const Property& p : e.properties)
    if (!p.is_list) scalar_names.push_back(p.name);
  scalar_values.assign(scalar_names.size(), {});
  std::vector<long long> corners;
  std::vector<double> scalars(scalar_names.size());
  for (long long f = 0; f < e.count; ++f) {
    const std::string where = "face " + std::to_string(f);
    size_t s = 0;
    int added = 0;
    for (const Property& p : e.properties) {
      if (p.is_list) {
        const double n = reader.read(p.count_type, where);
        if (n < 0 || n > 1e6) throw InputError("implausible corner count", file + ": " + where);
        corners.resize(static_cast<size_t>(n));
        for (auto& c : corners) {
          const double v = reader.read(p.type, where);
          c = static_cast<long long>(v);
        }
        if (&p == list) added = faces.add(corners, f);
      } else {
        scalars[s++] = reader.read(p.type, where);
      }
    }
    for (int t = 0; t < added; ++t)
      for (size_t k = 0; k < scalars.size(); ++k) scalar_values[k].push_back(scalars[k]);
    reader.end_instance();
  }
}

// Any other element: read and dropped.
void skip_element(ValueReader& reader, const Element& e) {
  for (long long i = 0; i < e.count; ++i) {
    const std::string where = e.name + " " + std::to_string(i);
    for (const Property& p : e.properties) {
      if (p.is_list) {
        const long long n = static_cast<long long>(reader.read(p.count_type, where));
        for (long long j = 0; j < n; ++j) reader.read(p.type, where);
      } else {
        reader.read(p.type, where);
      }
    }
    reader.end_instance();
  }
}

}  // namespace

MeshReadResult read_ply(const std::filesystem::path& path, const MeshReadOptions& options) {
  const std::string file = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open file", file);

  MeshReadResult result;
  std::string line;
  if (!std::getline(in, line)) throw InputError("empty file; expected a PLY header", file);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line != "ply") throw InputError("not a PLY file (first line is not 'ply')", file);

  const PlyHeader header = read_header(in, file);
  const Encoding enc = header.enc;
  const std::vector<Element>& elements = header.elements;
  check_elements(in, elements, file);
  result.format = enc == Encoding::ascii       ? "ply-ascii"
                  : enc == Encoding::binary_le ? "ply-binary-le"
                                               : "ply-binary-be";

  ValueReader reader(in, enc, file);
  FaceBuilder faces(file, options.triangulate);
  std::vector<std::vector<double>> face_scalar_values;
  std::vector<std::string> face_scalar_names;
  long long vertex_count = 0;
  std::vector<std::string> skipped_elements;
  for (const Element& e : elements) {
    if (e.name == "vertex") {
      vertex_count = e.count;
      read_vertices(reader, e, result.mesh);
    } else if (e.name == "face") {
      read_faces(reader, e, faces, file, face_scalar_names, face_scalar_values);
    } else {
      skipped_elements.push_back(e.name);
      skip_element(reader, e);
    }
  }

  result.mesh.F = faces.finish(vertex_count, result.warnings);
  for (size_t k = 0; k < face_scalar_names.size(); ++k)
    result.mesh.face_fields.push_back(
        {face_scalar_names[k],
         Eigen::Map<const Eigen::VectorXd>(face_scalar_values[k].data(),
                                           static_cast<Eigen::Index>(face_scalar_values[k].size()))});
  for (const std::string& name : skipped_elements)
    result.warnings.push_back(file + ": ignored PLY element '" + name + "'");
  return result;
}

void write_ply(const std::filesystem::path& path, const Mesh& mesh, const MeshWriteOptions& options) {
  for (const ScalarField& f : mesh.vertex_fields)
    if (f.values.size() != mesh.V.rows())
      throw OutputError("vertex field '" + f.name + "' has the wrong length", path.string());
  for (const ScalarField& f : mesh.face_fields)
    if (f.values.size() != mesh.F.rows())
      throw OutputError("face field '" + f.name + "' has the wrong length", path.string());
  if (!host_is_little_endian())
    throw OutputError("binary PLY writer needs a little-endian host", path.string());

  write_file_atomic(path, [&](std::ostream& out) {
    const char* pos_type = options.double_precision ? "double" : "float";
    out << "ply\nformat binary_little_endian 1.0\ncomment garment-pipeline mesh, metres, +y up\n";
    out << "element vertex " << mesh.V.rows() << "\n";
    out << "property " << pos_type << " x\nproperty " << pos_type << " y\nproperty " << pos_type
        << " z\n";
    for (const ScalarField& f : mesh.vertex_fields) out << "property double " << f.name << "\n";
    out << "element face " << mesh.F.rows() << "\n";
    out << "property list uchar int vertex_indices\n";
    for (const ScalarField& f : mesh.face_fields) out << "property double " << f.name << "\n";
    out << "end_header\n";

    std::vector<char> buf;
    auto put = [&buf](const void* p, size_t n) {
      const char* c = static_cast<const char*>(p);
      buf.insert(buf.end(), c, c + n);
    };
    for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
      for (int k = 0; k < 3; ++k) {
        if (options.double_precision) {
          const double v = mesh.V(i, k);
          put(&v, 8);
        } else {
          const float v = static_cast<float>(mesh.V(i, k));
          put(&v, 4);
        }
      }
      for (const ScalarField& f : mesh.vertex_fields) {
        const double v = f.values(i);
        put(&v, 8);
      }
    }
    for (Eigen::Index t = 0; t < mesh.F.rows(); ++t) {
      const unsigned char three = 3;
      put(&three, 1);
      for (int k = 0; k < 3; ++k) {
        const int32_t v = mesh.F(t, k);
        put(&v, 4);
      }
      for (const ScalarField& f : mesh.face_fields) {
        const double v = f.values(t);
        put(&v, 8);
      }
    }
    out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
  });
}

}  // namespace gp
