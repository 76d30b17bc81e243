// "File exists => file is complete": outputs are written under a temporary name in the same
// directory and renamed into place by commit(). The temporary is removed when the object dies
// uncommitted (exception) and by the SIGINT/SIGTERM/SIGHUP handler that the tool wrapper
// installs (see install_cleanup_handlers), so Make rules can trust any file they find.
// "One writer per output": every output is claimed (OutputClaim) before any work, so a second
// process writing the same path fails at once instead of silently replacing the first's file.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace df {

/// Claims an output path for this process while the object lives: an exclusive lock (flock) on
/// a hidden file `.NAME.lock` beside the output, created when the claim is taken and removed
/// when it is released (a lock file left by a killed process is taken over: the lock died with
/// it). Taking the first claim of a path:
///  - checks that the output's directory can be written (the lock file is created there), so a
///    read-only directory fails before any work, not after hours of training;
///  - fails at once when another process holds the claim, naming its PID;
///  - removes the temporaries of this output (`.NAME.tmp-PID-N`) whose process no longer runs
///    (left by a SIGKILL), saying so.
/// Claims of one path within a process nest (a trainer claims its output at the start; the
/// AtomicOutput that writes it at the end claims it again).
/// @throws IOError naming the output (or its directory)
class OutputClaim {
 public:
  explicit OutputClaim(const std::filesystem::path& output);
  ~OutputClaim();
  OutputClaim(OutputClaim&& other) noexcept : key_(std::move(other.key_)) { other.key_.clear(); }
  OutputClaim& operator=(OutputClaim&&) = delete;
  OutputClaim(const OutputClaim&) = delete;
  OutputClaim& operator=(const OutputClaim&) = delete;

  /// The hidden lock file of `output` (`DIR/.NAME.lock`).
  static std::filesystem::path lock_path(const std::filesystem::path& output);

 private:
  std::string key_;  // the lock file's path; empty once moved from
};

class AtomicOutput {
 public:
  enum class Kind { file, directory };

  /// Checks that `final_path` may be written, claims it (OutputClaim) and reserves a temporary
  /// beside it.
  /// @throws IOError if it exists and !force, if its directory is missing or cannot be written,
  ///         if another process is writing it, or if it would overwrite (or, for a directory,
  ///         contain) one of `inputs`.
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
  OutputClaim claim_;
  int slot_ = -1;
  bool committed_ = false;
};

/// AtomicOutput's checks, made before a long job rather than when its result is written: claims
/// `path` (OutputClaim) and fails if it exists without `force`, is one of `inputs` or is of the
/// other kind. Hold the claim until the AtomicOutput that writes the file exists.
/// @throws IOError as AtomicOutput's constructor
OutputClaim claim_output(const std::filesystem::path& path, bool force,
                         const std::vector<std::filesystem::path>& inputs = {},
                         AtomicOutput::Kind kind = AtomicOutput::Kind::file);

/// claim_output for each path given: empty paths and "-" (standard output) are skipped.
std::vector<OutputClaim> claim_outputs(const std::vector<std::filesystem::path>& paths, bool force,
                                       const std::vector<std::filesystem::path>& inputs = {});

/// Writes `text` (a JSON report, a TSV table) to `path` atomically, as every output is written.
/// @throws IOError as AtomicOutput's constructor, or when the text cannot be written
void write_text_output(const std::filesystem::path& path, std::string_view text, bool force,
                       const std::vector<std::filesystem::path>& inputs = {});

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
