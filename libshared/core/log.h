// Leveled logging on stderr, prefixed with the tool's name. Library code logs through these
// functions; the tool's --quiet/--verbose decide what reaches the terminal.
#pragma once

#include <fmt/format.h>

#include <string>
#include <string_view>

namespace df::log {

enum class Level { error = 0, warning = 1, info = 2, debug = 3 };

/// Set once by the tool wrapper: the name printed before every line.
void set_program(std::string name);
const std::string& program();
/// error+warning with --quiet, +info by default, +debug with --verbose.
void set_level(Level level);
Level level();
inline bool enabled(Level l) {
  return static_cast<int>(l) <= static_cast<int>(level());
}

/// Writes one whole line atomically (threads never interleave inside a line).
void write_line(Level level, std::string_view text);

template <class... Args>
void error(fmt::format_string<Args...> f, Args&&... args) {
  write_line(Level::error, fmt::format(f, std::forward<Args>(args)...));
}
template <class... Args>
void warn(fmt::format_string<Args...> f, Args&&... args) {
  if (enabled(Level::warning))
    write_line(Level::warning, fmt::format(f, std::forward<Args>(args)...));
}
template <class... Args>
void info(fmt::format_string<Args...> f, Args&&... args) {
  if (enabled(Level::info)) write_line(Level::info, fmt::format(f, std::forward<Args>(args)...));
}
template <class... Args>
void debug(fmt::format_string<Args...> f, Args&&... args) {
  if (enabled(Level::debug)) write_line(Level::debug, fmt::format(f, std::forward<Args>(args)...));
}

}  // namespace df::log
