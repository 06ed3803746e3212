#pragma once
// Options written once. An options struct lists its fields in one function
// template, `fields(Options&, Fields&)`, calling for each field one of
//   f.number(key, double&, Range)       f.integer(key, int or long&, Range)
//   f.flag(key, bool&)                  f.names(key, bool&, "if true", "if false")
//   f.text(key, std::string&)
//   f.choice(key, Enum&, {{Enum::a, "a"}, ...})
//   f.optional_choice(key, Enum&, names, Enum absent)   written only when not `absent`, which a
//                                       missing key means (reports from before the key stay readable)
//   f.group(key, Sub&, SubFields{})     a nested options struct, as an object
// and the generic writer and strict reader below serialise it: a report
// records the options under the same keys, in the same order, that a reader
// of the report accepts, and no tool lists the keys by hand.
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/error.h"
#include "spec/json_file.h"
#include "spec/spec_object.h"

namespace gp {

template <class Enum>
using ChoiceNames = std::vector<std::pair<Enum, const char*>>;

template <class Options, class FieldList>
OrderedJson write_options(const Options& options, FieldList fields);
template <class Options, class FieldList>
void read_options(const SpecObject& in, bool required, Options& options, FieldList fields);

// Writes every field into an ordered JSON object.
class OptionsWriter {
 public:
  explicit OptionsWriter(OrderedJson& out) : out_(out) {}
  void number(const char* key, double v, Range = {}) { out_[key] = v; }
  template <class Int>
  void integer(const char* key, Int v, Range = {}) {
    static_assert(std::is_integral_v<Int>);
    out_[key] = v;
  }
  void flag(const char* key, bool v) { out_[key] = v; }
  void text(const char* key, const std::string& v) { out_[key] = v; }
  void names(const char* key, bool v, const char* if_true, const char* if_false) {
    out_[key] = v ? if_true : if_false;
  }
  template <class Enum>
  void choice(const char* key, Enum v, const ChoiceNames<Enum>& names) {
    for (const auto& [value, name] : names) {
      if (value == v) {
        out_[key] = name;
        return;
      }
    }
    out_[key] = nullptr;  // not reached while every enumerator is named
  }
  template <class Enum>
  void optional_choice(const char* key, Enum v, const ChoiceNames<Enum>& names, Enum absent) {
    if (v != absent) choice(key, v, names);
  }
  template <class Sub, class SubFields>
  void group(const char* key, const Sub& v, SubFields fields) {
    out_[key] = write_options(v, fields);
  }

 private:
  OrderedJson& out_;
};

// Reads every field from a spec object. Strict: with `required`, a missing
// field is an error (a report written by OptionsWriter has them all);
// otherwise it keeps the value it had. Types and ranges are checked and an
// error names the file and the field's JSON pointer (SpecError). Fields the
// list does not name are left for the caller (SpecObject::finish rejects
// them where the object holds options only).
class OptionsReader {
 public:
  OptionsReader(const SpecObject& in, bool required) : in_(in), required_(required) {}
  void number(const char* key, double& v, Range range = {}) {
    if (present(key)) v = in_.number(key, v, range);
  }
  template <class Int>
  void integer(const char* key, Int& v, Range range = {}) {
    static_assert(std::is_integral_v<Int>);
    if (present(key)) v = static_cast<Int>(in_.integer(key, v, range));
  }
  void flag(const char* key, bool& v) {
    if (present(key)) v = in_.boolean(key, v);
  }
  void text(const char* key, std::string& v) {
    if (present(key)) v = in_.string(key, v);
  }
  void names(const char* key, bool& v, const char* if_true, const char* if_false) {
    if (present(key)) v = in_.choice(key, v ? if_true : if_false, {if_true, if_false}) == if_true;
  }
  template <class Enum>
  void choice(const char* key, Enum& v, const ChoiceNames<Enum>& names) {
    if (!present(key)) return;
    std::vector<std::string> all;
    for (const auto& n : names) all.emplace_back(n.second);
    const std::string name = in_.choice(key, all.front(), all);
    for (const auto& [value, n] : names) {
      if (name == n) v = value;
    }
  }
  // Missing: `absent` where every field is required (a report that omitted it at that value), the
  // value it had otherwise.
  template <class Enum>
  void optional_choice(const char* key, Enum& v, const ChoiceNames<Enum>& names, Enum absent) {
    if (in_.has(key)) {
      choice(key, v, names);
    } else if (required_) {
      v = absent;
    }
  }
  template <class Sub, class SubFields>
  void group(const char* key, Sub& v, SubFields fields) {
    if (present(key)) read_options(in_.object(key), required_, v, fields);
  }

 private:
  bool present(const char* key) const {
    if (in_.has(key)) return true;
    if (required_) throw SpecError("missing field", in_.where(key));
    return false;
  }
  const SpecObject& in_;
  bool required_;
};

// The options' fields as an ordered JSON object.
template <class Options, class FieldList>
OrderedJson write_options(const Options& options, FieldList fields) {
  OrderedJson out = OrderedJson::object();
  OptionsWriter writer(out);
  Options copy = options;  // the field list takes a mutable struct, to serve the reader too
  fields(copy, writer);
  return out;
}

// Reads the options' fields from `in` into `options` (see OptionsReader).
template <class Options, class FieldList>
void read_options(const SpecObject& in, bool required, Options& options, FieldList fields) {
  OptionsReader reader(in, required);
  fields(options, reader);
}

}  // namespace gp
