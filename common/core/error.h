#pragma once
// Typed errors thrown by library code. Only a tool's main() turns them into a message and an exit
// code, so that library functions stay silent and every stage reports failures the same way (exit
// codes: README.md, "Conventions shared by every stage").
#include <stdexcept>
#include <string>

namespace gp {

// Exit codes shared by every stage; scripts branch on them.
enum class ExitCode : int {
  ok = 0,
  internal = 1,      // a bug
  usage = 2,         // unknown flag, missing argument
  input = 3,         // missing, unreadable or malformed input file
  spec = 4,          // wrong schema or version; unknown, missing, mistyped or out-of-range field
  geometry = 5,      // non-manifold, poses not in correspondence, open loop, ...
  numerical = 6,     // solver failed, NaN detected and not recoverable
  output = 7,        // output cannot be written
  check_failed = 8,  // a check's verdict is "fail" (its report is still written)
};

// The word printed in "<tool>: error[<category>]: ...".
const char* category_name(ExitCode code);

// Base of all errors. what() is the message without location; where() names
// the file, element or JSON path the error is about (may be empty).
class Error : public std::runtime_error {
 public:
  Error(ExitCode code, const std::string& what, const std::string& where = "")
      : std::runtime_error(what), code_(code), where_(where) {}
  ExitCode code() const { return code_; }
  const std::string& where() const { return where_; }
  // "<what> (<where>)", or just "<what>" when there is no location.
  std::string message() const;

 private:
  ExitCode code_;
  std::string where_;
};

struct UsageError : Error {
  explicit UsageError(const std::string& what, const std::string& where = "")
      : Error(ExitCode::usage, what, where) {}
};
struct InputError : Error {
  explicit InputError(const std::string& what, const std::string& where = "")
      : Error(ExitCode::input, what, where) {}
};
struct SpecError : Error {
  explicit SpecError(const std::string& what, const std::string& where = "")
      : Error(ExitCode::spec, what, where) {}
};
struct GeometryError : Error {
  explicit GeometryError(const std::string& what, const std::string& where = "")
      : Error(ExitCode::geometry, what, where) {}
};
struct NumericalError : Error {
  explicit NumericalError(const std::string& what, const std::string& where = "")
      : Error(ExitCode::numerical, what, where) {}
};
struct OutputError : Error {
  explicit OutputError(const std::string& what, const std::string& where = "")
      : Error(ExitCode::output, what, where) {}
};

}  // namespace gp
