// "File exists => file is complete": outputs are written under a temporary name in the same
// directory and renamed into place by commit(). The temporary is removed when the object dies
// uncommitted (exception) and by the SIGINT/SIGTERM/SIGHUP handler that the tool wrapper
// installs (see install_cleanup_handlers), so Make rules can trust any file they find.
#pragma once

#include <filesystem>
#include <vector>

namespace df {

class AtomicOutput {
 public:
  enum class Kind { file, directory };

  /// Checks that `final_path` may be written and reserves a temporary beside it.
  /// @throws IOError if it exists and !force, if its directory is missing, or if it would
  ///         overwrite (or, for a directory, contain) one of `inputs`.
  AtomicOutput(std::filesystem::path final_path, Kind kind, bool force,
               const std::vector<std::filesystem::path>& inputs = {});
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  /// Where to write: a file path, or a directory that exists (kind == directory).
  const std::filesystem::path& temp_path() const { return temp_; }
  const std::filesystem::path& final_path() const { return final_; }
  /// Renames the temporary into place (replacing an existing output when forced).
  void commit();
  bool committed() const { return committed_; }

 private:
  std::filesystem::path final_, temp_;
  Kind kind_;
  int slot_ = -1;
  bool committed_ = false;
};

/// Installs handlers for SIGINT, SIGTERM and SIGHUP that remove every pending temporary and
/// then die of the same signal (exit status 128+signal). Called once by the tool wrapper.
void install_cleanup_handlers();

/// For tools that can stop at a checkpoint (the trainers): SIGTERM and SIGUSR1 (a scheduler's
/// preemption and Slurm's warning before a time limit) no longer kill at once but ask for a stop
/// at the next safe point, which stop_requested() reports; a second SIGTERM kills as
/// install_cleanup_handlers does. Call after it.
void install_stop_request_handlers();

/// The signal that asked for a stop (SIGTERM or SIGUSR1), or 0.
int stop_requested();

/// Throws IOError if `output` is the same file as any of `inputs` (paths that exist).
void check_not_an_input(const std::filesystem::path& output,
                        const std::vector<std::filesystem::path>& inputs);

}  // namespace df
