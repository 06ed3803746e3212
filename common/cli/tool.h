#pragma once
// What every stage shares on the command line (README.md, "Conventions shared by every stage"):
// --out/--force, --threads, --quiet/--verbose, --help with defaults and units, and one place that
// turns typed errors into the line
//   <tool>: error[<category>]: <what> (<where>)
// on stderr and the category's exit code.
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "core/error.h"

namespace gp {

struct CommonOptions {
  std::string out_dir;   // --out: output folder (created; replaced only with --force)
  bool force = false;    // --force: replace an existing output folder
  int threads = 1;       // --threads: threads of BLAS, CHOLMOD and Eigen
  bool quiet = false;    // --quiet: errors only
  bool verbose = false;  // --verbose: extra detail on stderr
};

// Messages on stderr, prefixed with the tool's name. Library code never prints;
// tools report through this.
class Logger {
 public:
  explicit Logger(std::string tool);
  void set_level(bool quiet, bool verbose) {
    quiet_ = quiet;
    verbose_ = verbose;
  }
  void info(const std::string& msg) const;     // hidden by --quiet
  void warning(const std::string& msg) const;  // hidden by --quiet
  void detail(const std::string& msg) const;   // shown only with --verbose
  // The one error line of a run that ends with `code` though nothing was
  // thrown (a check's verdict): "<tool>: error[<category>]: <msg>", always shown.
  void error(ExitCode code, const std::string& msg) const;
  // A progress line. On a terminal it is rewritten in place ("\r") and
  // finished by progress_done(); otherwise (a log file, CI) it is a plain line,
  // at most one per progress_interval seconds unless `always`. Hidden by --quiet.
  void progress(const std::string& msg, bool always = false) const;
  void progress_done() const;
  static constexpr double progress_interval = 10.0;  // seconds between plain progress lines
  bool verbose() const { return verbose_; }

 private:
  std::string tool_;
  bool quiet_ = false;
  bool verbose_ = false;
  bool terminal_ = false;                  // stderr is a terminal
  mutable bool live_ = false;              // a live line is on the terminal
  mutable double last_progress_ = -1e300;  // steady-clock seconds of the last plain line
};

class Tool {
 public:
  Tool(std::string name, std::string description);

  CLI::App& app() { return app_; }
  CommonOptions& common() { return common_; }
  Logger& log() { return log_; }
  const std::string& name() const { return name_; }

  // Adds --out (required unless `out_required` is false), --force, --threads,
  // --quiet and --verbose.
  void add_common_options(bool out_required = true);

  // Parses the command line and runs `body`, whose return value is the exit
  // code. Maps CLI11 errors to usage (2), gp::Error to its category, and any
  // other exception to internal (1).
  int run(int argc, char** argv, const std::function<int()>& body);

 private:
  std::string name_;
  CLI::App app_;
  CommonOptions common_;
  Logger log_;
};

// Sets the number of threads for Eigen and for OpenBLAS, where it is loaded.
void set_thread_count(int threads);

}  // namespace gp
