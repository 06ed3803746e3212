#pragma once
// JSON files: reading with clear errors, writing atomically with stable key order, and the
// "schema": "<name>/<version>" tag that every spec and report carries (README.md, "Conventions
// shared by every stage").
#include <filesystem>
#include <initializer_list>
#include <string>

#include <nlohmann/json.hpp>

namespace gp {

using Json = nlohmann::json;
// Reports keep the order in which fields were added, which reads better than
// alphabetical order and is just as deterministic.
using OrderedJson = nlohmann::ordered_json;

// Parses a JSON file. Throws InputError naming the file and the byte offset of
// a syntax error, or the file if it cannot be read.
Json read_json_file(const std::filesystem::path& path);

// Writes `j` indented by two spaces with a final newline, atomically.
// Doubles are printed with enough digits to round-trip.
void write_json_file(const std::filesystem::path& path, const OrderedJson& j);

// Checks that `j` is an object whose "schema" field reads "<name>/<version>"
// with a version in `supported`; returns the version. Throws SpecError naming
// `file` and the field otherwise.
int check_schema(const Json& j, const std::string& name, std::initializer_list<int> supported,
                 const std::string& file);

// "<name>/<version>".
std::string schema_tag(const std::string& name, int version);

}  // namespace gp
