// Progress of long work on stderr: redrawn in place (`\r`) on a terminal, a plain line every
// ~10% (at most every 2 s) when stderr is redirected so Make logs stay readable, nothing with
// --quiet. Thread-safe: parallel loops call advance() from any thread.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace df {

class Progress {
 public:
  /// @param label  what is being done ("reading frames")
  /// @param total  number of work items (0 = unknown)
  Progress(std::string label, std::size_t total);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// Marks n more items done.
  void advance(std::size_t n = 1);
  /// Prints the final line (also done by the destructor if not called, unless it runs
  /// because of an exception).
  void finish();
  std::size_t done() const { return done_.load(); }

  /// How progress is shown; chosen from the log level and isatty(stderr) unless forced.
  enum class Mode { silent, terminal, lines };
  static void force_mode(Mode mode);

 private:
  void draw(std::size_t done, bool final);

  std::string label_;
  std::size_t total_;
  std::atomic<std::size_t> done_{0};
  Mode mode_;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_, last_draw_;
  int last_decile_ = -1;
  bool finished_ = false;
};

}  // namespace df
