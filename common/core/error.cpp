#include "core/error.h"

namespace gp {

const char* category_name(ExitCode code) {
  switch (code) {
    case ExitCode::ok: return "ok";
    case ExitCode::internal: return "internal";
    case ExitCode::usage: return "usage";
    case ExitCode::input: return "input";
    case ExitCode::spec: return "spec";
    case ExitCode::geometry: return "geometry";
    case ExitCode::numerical: return "numerical";
    case ExitCode::output: return "output";
    case ExitCode::check_failed: return "check";
  }
  return "internal";
}

std::string Error::message() const {
  if (where_.empty()) return what();
  return std::string(what()) + " (" + where_ + ")";
}

}  // namespace gp
