#include "core/progress.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <exception>
#include <optional>

#include "core/log.h"

namespace df {
namespace {
std::optional<Progress::Mode> g_forced;

Progress::Mode default_mode() {
  if (g_forced) return *g_forced;
  if (!log::enabled(log::Level::info)) return Progress::Mode::silent;
  return isatty(STDERR_FILENO) ? Progress::Mode::terminal : Progress::Mode::lines;
}
}  // namespace

void Progress::force_mode(Mode mode) {
  g_forced = mode;
}

Progress::Progress(std::string label, std::size_t total)
    : label_(std::move(label)),
      total_(total),
      mode_(default_mode()),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

Progress::~Progress() {
  if (std::uncaught_exceptions() == 0) {
    finish();
    return;
  }
  // Unwinding from an error: no "done" line; just end a redrawn terminal line.
  std::lock_guard lock(mutex_);
  if (!finished_ && mode_ == Mode::terminal && done_.load() > 0) std::fputs("\n", stderr);
  finished_ = true;
}

void Progress::advance(std::size_t n) {
  std::size_t done = done_.fetch_add(n) + n;
  if (mode_ == Mode::silent) return;
  auto now = std::chrono::steady_clock::now();
  if (mode_ == Mode::terminal) {
    if (now - last_draw_ < std::chrono::milliseconds(100)) return;
  } else {
    int decile = total_ ? static_cast<int>(10 * done / total_) : -1;
    bool new_decile = total_ && decile > last_decile_;
    if (!new_decile || now - last_draw_ < std::chrono::seconds(2)) {
      if (!(total_ == 0 && now - last_draw_ >= std::chrono::seconds(10))) return;
    }
  }
  std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock() || finished_) return;
  draw(done, false);
}

void Progress::finish() {
  std::lock_guard lock(mutex_);
  if (finished_) return;
  finished_ = true;
  if (mode_ != Mode::silent) draw(done_.load(), true);
}

void Progress::draw(std::size_t done, bool final) {
  auto now = std::chrono::steady_clock::now();
  last_draw_ = now;
  double secs = std::chrono::duration<double>(now - start_).count();
  std::string text;
  if (total_) {
    last_decile_ = static_cast<int>(10 * done / total_);
    text = fmt::format("{}: {}/{} ({:.0f}%) {:.1f}s", label_, done, total_,
                       100.0 * static_cast<double>(done) / static_cast<double>(total_), secs);
  } else {
    text = fmt::format("{}: {} {:.1f}s", label_, done, secs);
  }
  if (final) text += " done";
  std::string line = log::program() + ": " + text;
  if (mode_ == Mode::terminal) {
    line = "\r" + line + "\033[K";
    if (final) line += "\n";
  } else {
    line += "\n";
  }
  std::fputs(line.c_str(), stderr);
  std::fflush(stderr);
}

}  // namespace df
