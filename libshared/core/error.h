// The project's exception types. Every failure a user can cause ends as one of these, and the
// shared main() (core/tool.h) prints it as one line: `TOOL: error: WHAT (WHERE)`.
#pragma once

#include <stdexcept>
#include <string>

namespace df {

/// Base of all deformflow errors. `what()` is the message alone; `where()` names the file,
/// and optionally the line or HDF5 object (`horse/17.obj:2203`, `in.h5/frames/positions`).
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what, std::string where = {})
      : std::runtime_error(what), where_(std::move(where)) {}
  /// Chains context in front of an earlier error, keeping its location:
  /// Error(e, "reading frame 17") -> "reading frame 17: <e.what()>".
  Error(const Error& previous, const std::string& context)
      : std::runtime_error(context + ": " + previous.what()), where_(previous.where()) {}

  const std::string& where() const { return where_; }
  /// "WHAT (WHERE)" or "WHAT" when no location is known.
  std::string message() const;

 private:
  std::string where_;
};

/// The input is not what the tool can work on (bad mesh, wrong file kind, NaN features, ...).
class InvalidInput : public Error {
  using Error::Error;
};

/// A file could not be read, written, renamed or removed.
class IOError : public Error {
  using Error::Error;
};

/// A bad combination of options that the option parser cannot catch; exits with code 2.
class UsageError : public Error {
  using Error::Error;
};

/// Thrown to stop work after SIGINT/SIGTERM once the temporaries are gone.
class Interrupted : public Error {
  using Error::Error;
};

/// Thrown when a requested stop (SIGTERM, SIGUSR1) was honoured: the work so far is saved where
/// the message says and a rerun with --resume continues it. The tool exits with kExitStopped.
class Stopped : public Error {
  using Error::Error;
};

/// Exit status after a Stopped (EX_TEMPFAIL of sysexits.h: "try again later").
inline constexpr int kExitStopped = 75;

}  // namespace df
