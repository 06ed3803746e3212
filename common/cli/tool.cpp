#include "cli/tool.h"

#include <dlfcn.h>
#include <unistd.h>

#include <chrono>
#include <iostream>

#include <Eigen/Core>

#include "linalg/dense_blocking.h"

namespace gp {

void Logger::info(const std::string& msg) const {
  if (!quiet_) std::cerr << tool_ << ": " << msg << '\n';
}
void Logger::warning(const std::string& msg) const {
  if (!quiet_) std::cerr << tool_ << ": warning: " << msg << '\n';
}
void Logger::error(ExitCode code, const std::string& msg) const {
  std::cerr << tool_ << ": error[" << category_name(code) << "]: " << msg << '\n';
}
void Logger::detail(const std::string& msg) const {
  if (verbose_ && !quiet_) std::cerr << tool_ << ": " << msg << '\n';
}
Logger::Logger(std::string tool) : tool_(std::move(tool)), terminal_(::isatty(STDERR_FILENO) == 1) {}

void Logger::progress(const std::string& msg, bool always) const {
  if (quiet_) return;
  if (terminal_) {
    std::cerr << '\r' << tool_ << ": " << msg << "\033[K" << std::flush;
    live_ = true;
    return;
  }
  const double now = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  if (!always && now - last_progress_ < progress_interval) return;
  last_progress_ = now;
  std::cerr << tool_ << ": " << msg << std::endl;
}
void Logger::progress_done() const {
  if (!quiet_ && live_) std::cerr << '\n';
  live_ = false;
}

Tool::Tool(std::string name, std::string description)
    : name_(std::move(name)), app_(std::move(description), name_), log_(name_) {
  fix_dense_blocking();
  app_.option_defaults()->always_capture_default();
  app_.get_formatter()->column_width(38);
}

void Tool::add_common_options(bool out_required) {
  auto* out = app_.add_option("-o,--out", common_.out_dir,
                              "Output folder (created; an existing one is replaced only with --force)");
  if (out_required) out->required();
  app_.add_flag("--force", common_.force, "Replace an existing output folder");
  app_.add_option("--threads", common_.threads, "Threads of BLAS, CHOLMOD and Eigen [count]")
      ->capture_default_str()->check(CLI::Range(1, 256));
  app_.add_flag("-q,--quiet", common_.quiet, "Print errors only");
  app_.add_flag("-v,--verbose", common_.verbose, "Print extra detail");
}

int Tool::run(int argc, char** argv, const std::function<int()>& body) {
  try {
    try {
      app_.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
      return app_.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
      return app_.exit(e);
    } catch (const CLI::ParseError& e) {
      throw UsageError(e.what(), "see --help");
    }
    log_.set_level(common_.quiet, common_.verbose);
    set_thread_count(common_.threads);
    return body();
  } catch (const Error& e) {
    std::cerr << name_ << ": error[" << category_name(e.code()) << "]: " << e.message() << '\n';
    return static_cast<int>(e.code());
  } catch (const std::bad_alloc&) {
    std::cerr << name_ << ": error[internal]: out of memory\n";
    return static_cast<int>(ExitCode::internal);
  } catch (const std::exception& e) {
    std::cerr << name_ << ": error[internal]: " << e.what() << " (this is a bug; please report it)\n";
    return static_cast<int>(ExitCode::internal);
  }
}

void set_thread_count(int threads) {
  Eigen::setNbThreads(threads);
  // OpenBLAS reads its thread count from the environment when it is loaded,
  // which is before main(); its setter is looked up at run time so that the
  // project still links against any BLAS.
  using SetThreads = void (*)(int);
  if (auto* set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads")))
    set(threads);
  // CHOLMOD's own OpenMP loops always run on the calling thread
  // (common/linalg/cholmod_serial_openmp.cpp), whatever the count.
}

}  // namespace gp
