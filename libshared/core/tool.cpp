#include "core/tool.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <cstdlib>
#include <exception>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <memory>
#include <new>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "core/provenance.h"

namespace df {
namespace {

// All cores, or the CPUs a Slurm job was given (its processes see every core of the node).
int default_threads() {
  if (const char* s = std::getenv("SLURM_CPUS_PER_TASK"))
    if (const int n = std::atoi(s); n > 0) return n;
  return tbb::info::default_concurrency();
}

}  // namespace

Tool::Tool(std::string name, std::string description)
    : name_(std::move(name)), app_(description, name_) {
  app_.set_version_flag("--version", name_ + " (deformflow) " DEFORMFLOW_VERSION);
  app_.add_flag("-q,--quiet", common_.quiet, "Print only warnings and errors (no progress)");
  app_.add_flag("-v,--verbose", common_.verbose, "Print details of the work (debug level)");
  // Every tool takes --threads, those that compute on one thread too: a script or a cluster
  // job can pass the same common options to any tool.
  app_.add_option(
          "--threads", common_.threads,
          "Worker threads (0 = all cores, or $SLURM_CPUS_PER_TASK in a Slurm job); results\n"
          "do not depend on it")
      ->default_val(0)
      ->check(CLI::NonNegativeNumber);
  app_.get_formatter()->column_width(34);
}

Tool& Tool::with_seed(std::uint64_t default_seed) {
  common_.seed = default_seed;
  app_.add_option("--seed", common_.seed, "Seed of every random choice (same seed, same output)")
      ->default_val(default_seed);
  return *this;
}

Tool& Tool::with_force() {
  app_.add_flag("-f,--force", common_.force, "Overwrite the output if it exists");
  return *this;
}

Tool& Tool::with_stop_requests() {
  stop_requests_ = true;
  return *this;
}

Tool& Tool::footer(const std::string& text) {
  app_.footer(text);
  return *this;
}

int Tool::run(int argc, char** argv, const std::function<void()>& body) {
  log::set_program(name_);
  provenance::set_command_line(argc, argv);
  try {
    app_.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app_.exit(e);  // --help, --version
    log::error("{}", e.what());
    log::write_line(log::Level::info, "run with --help for the options");
    return 2;
  }
  if (common_.quiet && common_.verbose) {
    log::error("--quiet and --verbose exclude each other");
    return 2;
  }
  log::set_level(common_.quiet     ? log::Level::warning
                 : common_.verbose ? log::Level::debug
                                   : log::Level::info);
  int threads = common_.threads > 0 ? common_.threads : default_threads();
  tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism,
                                  static_cast<std::size_t>(threads));
  install_cleanup_handlers();
  if (stop_requests_) install_stop_request_handlers();
#if defined(__GLIBC__)
  // Per-frame buffers of 0.1-10 MB and training activations of 10-120 MB would otherwise each be
  // a fresh mmap (page faults and zeroing every time: ~25% of acap2obj's time, ~35% of an MSAE
  // step); keep every block in the heap instead. (M_MMAP_THRESHOLD cannot go above 32 MB, so
  // mmap is switched off altogether.)
  mallopt(M_MMAP_MAX, 0);
  // Never give freed heap back to the kernel: a training iteration frees and re-allocates
  // gigabytes of activations, and trimming made every iteration page-fault them in again
  // (40% of a BD-LSTM step). Peak memory is unchanged; batch tools exit soon after.
  mallopt(M_TRIM_THRESHOLD, -1);
#endif
  try {
    body();
    return 0;
  } catch (const Stopped& e) {
    log::warn("{}", e.message());
    return kExitStopped;
  } catch (const UsageError& e) {
    log::error("{}", e.message());
    return 2;
  } catch (const Error& e) {
    log::error("{}", e.message());
  } catch (const std::bad_alloc&) {
    log::error("out of memory");
  } catch (const std::exception& e) {
    log::error("{}", e.what());
  }
  return 1;
}

}  // namespace df
