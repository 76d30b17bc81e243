// The shared main() of every deformflow tool (MRtrix's `core/command.h` idea): a tool file
// declares its options on a Tool and passes one function to run(); run() parses the command
// line, applies the common options, installs the temporary-file cleanup on signals, and turns
// every exception into one line `TOOL: error: WHAT (WHERE)`:
//   exit 0 success, 2 usage error (bad/missing option), 1 any other failure,
//   75 stopped on request (SIGTERM/SIGUSR1) with the work saved for --resume (trainers).
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <string>

#include "core/common_options.h"

namespace df {

class Tool {
 public:
  /// @param name         the executable's name, used as the prefix of every message
  /// @param description  first paragraph of --help (what it reads, what it writes)
  Tool(std::string name, std::string description);

  CLI::App& app() { return app_; }
  const CommonOptions& common() const { return common_; }
  const std::string& name() const { return name_; }

  /// Adds --seed with the given default (tools that draw random numbers).
  Tool& with_seed(std::uint64_t default_seed = 0);
  /// Adds -f/--force (tools that write an output).
  Tool& with_force();
  /// For trainers: SIGTERM and SIGUSR1 ask for a stop at the next checkpoint (exit status
  /// kExitStopped, 75) instead of killing; see install_stop_request_handlers.
  Tool& with_stop_requests();
  /// Text after the options in --help: references, examples.
  Tool& footer(const std::string& text);

  /// Parses argv and runs body; returns the process exit code.
  int run(int argc, char** argv, const std::function<void()>& body);

 private:
  std::string name_;
  CLI::App app_;
  CommonOptions common_;
  bool stop_requests_ = false;
};

}  // namespace df
