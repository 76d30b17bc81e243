#include "core/log.h"

#include <cstdio>
#include <mutex>

namespace df::log {
namespace {
std::string g_program = "deformflow";
Level g_level = Level::info;
std::mutex g_mutex;
}  // namespace

void set_program(std::string name) {
  g_program = std::move(name);
}
const std::string& program() {
  return g_program;
}
void set_level(Level level) {
  g_level = level;
}
Level level() {
  return g_level;
}

void write_line(Level level, std::string_view text) {
  std::string line = g_program + ": ";
  if (level == Level::error) line += "error: ";
  if (level == Level::warning) line += "warning: ";
  line += text;
  line += '\n';
  std::lock_guard lock(g_mutex);
  std::fputs(line.c_str(), stderr);
  std::fflush(stderr);
}

}  // namespace df::log
