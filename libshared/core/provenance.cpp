#include "core/provenance.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <ctime>
#include <sstream>

namespace df::provenance {
namespace {
std::string g_command_line;

std::string shell_quote(const std::string& arg) {
  if (!arg.empty() && arg.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                            "0123456789-_./=:,@+%") == std::string::npos)
    return arg;
  std::string q = "'";
  for (char c : arg) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}
}  // namespace

void set_command_line(int argc, const char* const* argv) {
  std::string s;
  for (int i = 0; i < argc; ++i) {
    std::string a = argv[i];
    if (i == 0)
      a = a.substr(a.find_last_of('/') == std::string::npos ? 0 : a.find_last_of('/') + 1);
    if (i) s += ' ';
    s += shell_quote(a);
  }
  g_command_line = s;
}

const std::string& command_line() {
  return g_command_line;
}

std::string now_iso8601() {
  std::time_t t = std::time(nullptr);
  if (const char* e = std::getenv("SOURCE_DATE_EPOCH")) t = static_cast<std::time_t>(std::atoll(e));
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::vector<std::string> history_lines(const std::string& history) {
  std::vector<std::string> lines;
  std::istringstream in(history);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) lines.push_back(line);
  return lines;
}

std::string history(const std::vector<std::string>& inherited) {
  std::vector<std::string> lines{now_iso8601() + " " + g_command_line};
  for (const auto& h : inherited)
    for (auto& l : history_lines(h))
      if (std::find(lines.begin(), lines.end(), l) == lines.end()) lines.push_back(l);
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
}

}  // namespace df::provenance
