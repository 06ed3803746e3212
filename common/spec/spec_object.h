#pragma once
// Strict reading of a JSON spec object. Every field read is remembered, and
// finish() rejects any field that was not: a misspelt key is an error, never a
// silent fallback to a default. Every error names the file and the JSON
// pointer of the offending field, e.g. "shirt.json: /loops/2/points".
#include <optional>
#include <string>
#include <set>
#include <vector>

#include "spec/json_file.h"

namespace gp {

// Inclusive numeric bounds; a field outside them is a SpecError.
struct Range {
  double min = -1e300;
  double max = 1e300;
  static Range positive() { return {1e-300, 1e300}; }
  static Range non_negative() { return {0.0, 1e300}; }
  static Range between(double lo, double hi) { return {lo, hi}; }
};

class SpecArray;

class SpecObject {
 public:
  // `j` must be an object (SpecError at `pointer` otherwise).
  SpecObject(const Json& j, std::string file, std::string pointer = "");

  bool has(const std::string& key) const;
  // Marks `key` as known without reading it (e.g. "schema", checked elsewhere).
  void allow(const std::string& key) const;

  double number(const std::string& key, double fallback, Range range = {}) const;
  double required_number(const std::string& key, Range range = {}) const;
  long long integer(const std::string& key, long long fallback, Range range = {}) const;
  long long required_integer(const std::string& key, Range range = {}) const;
  bool boolean(const std::string& key, bool fallback) const;
  std::string string(const std::string& key, const std::string& fallback) const;
  std::string required_string(const std::string& key) const;
  // One of `choices`.
  std::string choice(const std::string& key, const std::string& fallback,
                     const std::vector<std::string>& choices) const;
  std::vector<double> numbers(const std::string& key, std::optional<size_t> exact_size = {},
                              Range range = {}) const;
  std::optional<SpecObject> optional_object(const std::string& key) const;
  SpecObject object(const std::string& key) const;
  std::optional<SpecArray> optional_array(const std::string& key) const;
  SpecArray array(const std::string& key) const;
  // The raw value (marks the key as read); nullptr if absent.
  const Json* raw(const std::string& key) const;

  // Throws SpecError naming the first field that was never read.
  void finish() const;

  // "file: /pointer/key", for errors raised by callers.
  std::string where(const std::string& key = "") const;
  const std::string& file() const { return file_; }
  const std::string& pointer() const { return pointer_; }
  const Json& json() const { return *j_; }

 private:
  const Json& field(const std::string& key) const;
  const Json* find(const std::string& key) const;
  double checked_number(const std::string& key, const Json& v, Range range) const;

  const Json* j_;
  std::string file_;
  std::string pointer_;
  mutable std::set<std::string> read_;
};

class SpecArray {
 public:
  SpecArray(const Json& j, std::string file, std::string pointer);
  size_t size() const { return j_->size(); }
  bool empty() const { return j_->empty(); }
  SpecObject object(size_t i) const;
  const Json& at(size_t i) const { return (*j_)[i]; }
  std::string where(size_t i) const;

 private:
  const Json* j_;
  std::string file_;
  std::string pointer_;
};

// Name of a JSON type for messages ("number", "string", ...).
std::string json_type_name(const Json& j);

}  // namespace gp
