#include "spec/json_file.h"

#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"

namespace gp {

Json read_json_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open file", path.string());
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    throw InputError("empty file; expected JSON", path.string());
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& e) {
    // Report line and column rather than nlohmann's byte offset alone.
    size_t line = 1, col = 1;
    for (size_t i = 0; i + 1 < e.byte && i < text.size(); ++i) {
      if (text[i] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    std::string what = e.what();
    const size_t colon = what.rfind(": ");
    if (colon != std::string::npos) what = what.substr(colon + 2);
    throw InputError("malformed JSON: " + what,
                     path.string() + ":" + std::to_string(line) + ":" + std::to_string(col));
  } catch (const Json::exception& e) {
    // Other parser failures, e.g. a number too large for a double.
    std::string what = e.what();
    const size_t bracket = what.find("] ");
    if (bracket != std::string::npos) what = what.substr(bracket + 2);
    throw InputError("malformed JSON: " + what, path.string());
  }
}

void write_json_file(const std::filesystem::path& path, const OrderedJson& j) {
  write_file_atomic(
      path, [&](std::ostream& out) { out << j.dump(2) << '\n'; }, false);
}

std::string schema_tag(const std::string& name, int version) {
  return name + "/" + std::to_string(version);
}

int check_schema(const Json& j, const std::string& name, std::initializer_list<int> supported,
                 const std::string& file) {
  if (!j.is_object()) throw SpecError("expected a JSON object", file + ": /");
  const auto it = j.find("schema");
  if (it == j.end())
    throw SpecError("missing field 'schema' (expected \"" + name + "/<version>\")", file + ": /schema");
  if (!it->is_string()) throw SpecError("'schema' must be a string", file + ": /schema");
  const std::string tag = it->get<std::string>();
  const size_t slash = tag.rfind('/');
  if (slash == std::string::npos || tag.substr(0, slash) != name)
    throw SpecError("schema is \"" + tag + "\", expected \"" + name + "/<version>\"", file + ": /schema");
  int version = -1;
  try {
    size_t used = 0;
    version = std::stoi(tag.substr(slash + 1), &used);
    if (used != tag.size() - slash - 1) version = -1;
  } catch (const std::exception&) {
    version = -1;
  }
  for (int v : supported)
    if (v == version) return version;
  std::string known;
  for (int v : supported) known += (known.empty() ? "" : ", ") + schema_tag(name, v);
  throw SpecError("unsupported schema version \"" + tag + "\" (this build reads " + known + ")",
                  file + ": /schema");
}

}  // namespace gp
