#include "spec/spec_object.h"

#include <cmath>
#include <sstream>

#include "core/error.h"

namespace gp {
namespace {

// JSON pointer escaping (RFC 6901): '~' -> "~0", '/' -> "~1".
std::string escape_pointer_token(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

std::string format_number(double v) {
  std::ostringstream s;
  s.precision(12);
  s << v;
  return s.str();
}

}  // namespace

std::string json_type_name(const Json& j) {
  switch (j.type()) {
    case Json::value_t::null: return "null";
    case Json::value_t::object: return "object";
    case Json::value_t::array: return "array";
    case Json::value_t::string: return "string";
    case Json::value_t::boolean: return "boolean";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float: return "number";
    default: return "value";
  }
}

SpecObject::SpecObject(const Json& j, std::string file, std::string pointer)
    : j_(&j), file_(std::move(file)), pointer_(std::move(pointer)) {
  if (!j.is_object())
    throw SpecError("expected an object, found " + json_type_name(j), where());
}

std::string SpecObject::where(const std::string& key) const {
  std::string p = pointer_;
  if (!key.empty()) p += "/" + escape_pointer_token(key);
  if (p.empty()) p = "/";
  return file_ + ": " + p;
}

const Json* SpecObject::find(const std::string& key) const {
  const auto it = j_->find(key);
  if (it == j_->end()) return nullptr;
  read_.insert(key);
  return &*it;
}

const Json& SpecObject::field(const std::string& key) const {
  const Json* v = find(key);
  if (!v) throw SpecError("missing required field '" + key + "'", where(key));
  return *v;
}

bool SpecObject::has(const std::string& key) const { return j_->contains(key); }
void SpecObject::allow(const std::string& key) const { read_.insert(key); }
const Json* SpecObject::raw(const std::string& key) const { return find(key); }

double SpecObject::checked_number(const std::string& key, const Json& v, Range range) const {
  if (!v.is_number()) throw SpecError("expected a number, found " + json_type_name(v), where(key));
  const double x = v.get<double>();
  if (!std::isfinite(x)) throw SpecError("number is not finite", where(key));
  if (x < range.min || x > range.max) {
    std::string bound;
    if (range.min == Range::positive().min) bound = "must be positive";
    else if (range.max >= 1e300) bound = "must be at least " + format_number(range.min);
    else if (range.min <= -1e300) bound = "must be at most " + format_number(range.max);
    else bound = "must lie in [" + format_number(range.min) + ", " + format_number(range.max) + "]";
    throw SpecError("value " + format_number(x) + " out of range: " + bound, where(key));
  }
  return x;
}

double SpecObject::number(const std::string& key, double fallback, Range range) const {
  const Json* v = find(key);
  return v ? checked_number(key, *v, range) : fallback;
}

double SpecObject::required_number(const std::string& key, Range range) const {
  return checked_number(key, field(key), range);
}

long long SpecObject::integer(const std::string& key, long long fallback, Range range) const {
  const Json* v = find(key);
  if (!v) return fallback;
  if (!v->is_number_integer() && !v->is_number_unsigned())
    throw SpecError("expected an integer, found " + json_type_name(*v), where(key));
  return static_cast<long long>(checked_number(key, *v, range));
}

long long SpecObject::required_integer(const std::string& key, Range range) const {
  field(key);
  return integer(key, 0, range);
}

bool SpecObject::boolean(const std::string& key, bool fallback) const {
  const Json* v = find(key);
  if (!v) return fallback;
  if (!v->is_boolean()) throw SpecError("expected true or false, found " + json_type_name(*v), where(key));
  return v->get<bool>();
}

std::string SpecObject::string(const std::string& key, const std::string& fallback) const {
  const Json* v = find(key);
  if (!v) return fallback;
  if (!v->is_string()) throw SpecError("expected a string, found " + json_type_name(*v), where(key));
  return v->get<std::string>();
}

std::string SpecObject::required_string(const std::string& key) const {
  field(key);
  return string(key, "");
}

std::string SpecObject::choice(const std::string& key, const std::string& fallback,
                               const std::vector<std::string>& choices) const {
  const std::string s = string(key, fallback);
  for (const std::string& c : choices)
    if (c == s) return s;
  std::string list;
  for (const std::string& c : choices) list += (list.empty() ? "" : ", ") + c;
  throw SpecError("unknown value '" + s + "' (one of: " + list + ")", where(key));
}

std::vector<double> SpecObject::numbers(const std::string& key, std::optional<size_t> exact_size,
                                        Range range) const {
  const Json& v = field(key);
  if (!v.is_array()) throw SpecError("expected an array of numbers, found " + json_type_name(v), where(key));
  if (exact_size && v.size() != *exact_size)
    throw SpecError("expected " + std::to_string(*exact_size) + " numbers, found " +
                        std::to_string(v.size()),
                    where(key));
  std::vector<double> out;
  for (size_t i = 0; i < v.size(); ++i)
    out.push_back(checked_number(key + "/" + std::to_string(i), v[i], range));
  return out;
}

std::optional<SpecObject> SpecObject::optional_object(const std::string& key) const {
  const Json* v = find(key);
  if (!v) return std::nullopt;
  return SpecObject(*v, file_, pointer_ + "/" + escape_pointer_token(key));
}

SpecObject SpecObject::object(const std::string& key) const {
  return SpecObject(field(key), file_, pointer_ + "/" + escape_pointer_token(key));
}

std::optional<SpecArray> SpecObject::optional_array(const std::string& key) const {
  const Json* v = find(key);
  if (!v) return std::nullopt;
  return SpecArray(*v, file_, pointer_ + "/" + escape_pointer_token(key));
}

SpecArray SpecObject::array(const std::string& key) const {
  return SpecArray(field(key), file_, pointer_ + "/" + escape_pointer_token(key));
}

void SpecObject::finish() const {
  for (auto it = j_->begin(); it != j_->end(); ++it)
    if (!read_.count(it.key())) throw SpecError("unknown field '" + it.key() + "'", where(it.key()));
}

SpecArray::SpecArray(const Json& j, std::string file, std::string pointer)
    : j_(&j), file_(std::move(file)), pointer_(std::move(pointer)) {
  if (!j.is_array())
    throw SpecError("expected an array, found " + json_type_name(j), file_ + ": " + pointer_);
}

SpecObject SpecArray::object(size_t i) const {
  return SpecObject((*j_)[i], file_, pointer_ + "/" + std::to_string(i));
}

std::string SpecArray::where(size_t i) const {
  return file_ + ": " + pointer_ + "/" + std::to_string(i);
}

}  // namespace gp
