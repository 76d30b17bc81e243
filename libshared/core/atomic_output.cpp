#include "core/atomic_output.h"

#include <dirent.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <csignal>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>

#include "core/error.h"
#include "core/log.h"

namespace fs = std::filesystem;

namespace df {
namespace {

// Pending temporaries, readable from a signal handler: fixed slots, no allocation.
struct Slot {
  std::atomic<bool> used{false};
  bool is_dir = false;
  char path[4096] = {};
};
constexpr int kSlots = 64;
std::array<Slot, kSlots> g_slots;
std::mutex g_slot_mutex;
std::atomic<unsigned> g_counter{0};

int claim_slot(const fs::path& p, bool is_dir) {
  std::lock_guard lock(g_slot_mutex);
  const std::string s = p.string();
  if (s.size() >= sizeof(Slot::path)) return -1;
  for (int i = 0; i < kSlots; ++i) {
    if (!g_slots[i].used.load()) {
      std::memcpy(g_slots[i].path, s.c_str(), s.size() + 1);
      g_slots[i].is_dir = is_dir;
      g_slots[i].used.store(true);
      return i;
    }
  }
  return -1;
}

void release_slot(int i) {
  if (i >= 0) g_slots[i].used.store(false);
}

// Async-signal-safe removal of a directory's plain entries: raw getdents64 + unlinkat, no
// malloc.
void empty_dir_signal_safe(const char* path) {
  int fd = open(path, O_RDONLY | O_DIRECTORY);
  if (fd >= 0) {
    alignas(8) char buf[8192];
    for (;;) {
      long n = syscall(SYS_getdents64, fd, buf, sizeof buf);
      if (n <= 0) break;
      for (long off = 0; off < n;) {
        struct Dirent64 {
          unsigned long long ino;
          long long off;
          unsigned short reclen;
          unsigned char type;
          char name[1];
        };
        auto* d = reinterpret_cast<Dirent64*>(buf + off);
        const char* name = d->name;
        if (!(name[0] == '.' && (name[1] == 0 || (name[1] == '.' && name[2] == 0))))
          unlinkat(fd, name, 0);
        off += d->reclen;
      }
    }
    close(fd);
  }
}

// Other threads may still be creating files while the handler runs: empty and retry until the
// directory is gone.
void remove_dir_signal_safe(const char* path) {
  for (int attempt = 0; attempt < 1000; ++attempt) {
    empty_dir_signal_safe(path);
    if (rmdir(path) == 0 || errno == ENOENT) return;
  }
}

extern "C" void cleanup_and_die(int sig) {
  for (auto& s : g_slots) {
    if (!s.used.load()) continue;
    if (s.is_dir)
      remove_dir_signal_safe(s.path);
    else
      unlink(s.path);
  }
  signal(sig, SIG_DFL);
  raise(sig);
}

std::atomic<int> g_stop_signal{0};

extern "C" void request_stop(int sig) {
  int none = 0;
  if (!g_stop_signal.compare_exchange_strong(none, sig) && sig == SIGTERM) cleanup_and_die(sig);
}

// --- claims ----------------------------------------------------------------------------------

// The claims this process holds, by lock file: its descriptor (holding the flock), how many
// OutputClaims share it, and its signal-handler slot (the lock file is removed on a signal too).
struct Held {
  int fd = -1;
  int count = 0;
  int slot = -1;
};
std::mutex g_claim_mutex;
std::map<std::string, Held>& held_claims() {
  static std::map<std::string, Held> m;
  return m;
}

// The PID written in a lock file by its holder ("" if none yet).
std::string holder_of(int fd) {
  char buf[32] = {};
  const ssize_t n = pread(fd, buf, sizeof buf - 1, 0);
  std::string s(buf, n > 0 ? static_cast<std::size_t>(n) : 0);
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

// An exclusive lock on `lock` (created if missing), or IOError naming `output` when another
// process holds it. A holder removes its lock file on release, so a file opened just before
// that is locked in vain: the lock counts only while the path still names the locked file.
int lock_exclusively(const fs::path& lock, const fs::path& output) {
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int fd = open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0)
      throw IOError(
          fmt::format("cannot create a file in the output's directory: {}", std::strerror(errno)),
          lock.parent_path().string());
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int e = errno;
      const std::string holder = holder_of(fd);
      close(fd);
      if (e == EWOULDBLOCK)
        throw IOError(
            fmt::format("another process{} is writing this output; wait for it to end or choose "
                        "another output",
                        holder.empty() ? "" : " (PID " + holder + ")"),
            output.string());
      throw IOError(fmt::format("cannot lock the output: {}", std::strerror(e)), lock.string());
    }
    struct stat opened {
    }, named{};
    if (fstat(fd, &opened) == 0 && stat(lock.c_str(), &named) == 0 &&
        opened.st_dev == named.st_dev && opened.st_ino == named.st_ino) {
      const std::string pid = std::to_string(getpid()) + "\n";
      if (ftruncate(fd, 0) != 0 || pwrite(fd, pid.data(), pid.size(), 0) < 0) {
        // the PID only improves a rival's message; the lock holds without it
      }
      return fd;
    }
    close(fd);  // removed (and maybe re-created) by the previous holder in between: again
  }
  throw IOError("cannot lock the output: its lock file keeps changing", lock.string());
}

// The PID in a temporary's name `.NAME.tmp-PID-N` of `output`, or 0 if `name` is not one.
pid_t temporary_owner(const std::string& name, const std::string& prefix) {
  if (name.compare(0, prefix.size(), prefix) != 0) return 0;
  const char* first = name.data() + prefix.size();
  const char* last = name.data() + name.size();
  long pid = 0;
  const auto [ptr, ec] = std::from_chars(first, last, pid);
  if (ec != std::errc() || ptr == last || *ptr != '-' || pid <= 0) return 0;
  return static_cast<pid_t>(pid);
}

// Removes the temporaries of `output` that a process no longer running left (SIGKILL, power
// loss). Called with the claim held: every live writer of `output` holds it too.
void remove_stale_temporaries(const fs::path& output) {
  const fs::path dir = output.parent_path().empty() ? fs::path(".") : output.parent_path();
  const std::string prefix = "." + output.filename().string() + ".tmp-";
  std::error_code ec;
  std::vector<std::pair<fs::path, pid_t>> stale;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const pid_t pid = temporary_owner(it->path().filename().string(), prefix);
    if (pid == 0 || pid == getpid()) continue;
    if (kill(pid, 0) == 0 || errno != ESRCH) continue;  // running (or not ours to ask)
    stale.emplace_back(it->path(), pid);
  }
  for (const auto& [path, pid] : stale) {
    std::error_code rm;
    fs::remove_all(path, rm);
    if (rm)
      log::warn("cannot remove {}, a temporary left by process {} that no longer runs: {}",
                path.string(), pid, rm.message());
    else
      log::info("removed {}, a temporary left by process {} that no longer runs", path.string(),
                pid);
  }
}

fs::path temp_name_for(const fs::path& final_path) {
  unsigned n = g_counter.fetch_add(1);
  std::string name(".");
  name.append(final_path.filename().string()).append(".tmp-");
  name.append(std::to_string(getpid())).append("-").append(std::to_string(n));
  return final_path.parent_path() / name;
}

}  // namespace

void install_cleanup_handlers() {
  struct sigaction sa {};
  sa.sa_handler = cleanup_and_die;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
}

void install_stop_request_handlers() {
  struct sigaction sa {};
  sa.sa_handler = request_stop;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGTERM, SIGUSR1}) sigaction(sig, &sa, nullptr);
}

int stop_requested() {
  return g_stop_signal.load();
}

void check_not_an_input(const fs::path& output, const std::vector<fs::path>& inputs) {
  std::error_code ec;
  for (const auto& in : inputs) {
    if (fs::exists(in, ec) && fs::exists(output, ec) && fs::equivalent(in, output, ec))
      throw IOError("refusing to overwrite an input with the output", output.string());
  }
}

fs::path OutputClaim::lock_path(const fs::path& output) {
  return output.parent_path() / ("." + output.filename().string() + ".lock");
}

OutputClaim::OutputClaim(const fs::path& output) {
  std::error_code ec;
  const fs::path dir = output.parent_path().empty() ? fs::path(".") : output.parent_path();
  const fs::path lock =
      fs::weakly_canonical(fs::absolute(dir, ec), ec) / lock_path(output).filename();
  std::lock_guard guard(g_claim_mutex);
  auto& held = held_claims();
  if (auto it = held.find(lock.string()); it != held.end()) {
    ++it->second.count;
    key_ = it->first;
    return;
  }
  if (!fs::is_directory(dir, ec))
    throw IOError("the output's directory does not exist", dir.string());
  if (access(dir.c_str(), W_OK) != 0)
    throw IOError(fmt::format("cannot write in the output's directory: {}", std::strerror(errno)),
                  dir.string());
  Held h;
  h.fd = lock_exclusively(lock, output);
  h.count = 1;
  h.slot = claim_slot(lock, false);
  key_ = lock.string();
  held.emplace(key_, h);
  remove_stale_temporaries(output);
}

OutputClaim::~OutputClaim() {
  if (key_.empty()) return;
  std::lock_guard guard(g_claim_mutex);
  auto& held = held_claims();
  auto it = held.find(key_);
  if (it == held.end() || --it->second.count > 0) return;
  unlink(key_.c_str());  // while still locked: a rival that opened it retries on the new file
  close(it->second.fd);
  release_slot(it->second.slot);
  held.erase(it);
}

namespace {
// The output path as given, checked before anything is claimed: "dir/" names "dir".
fs::path output_path(fs::path p) {
  if (p.empty()) throw UsageError("no output path given (-o)");
  if (!p.has_filename()) p = p.parent_path();
  std::error_code ec;
  const fs::path parent = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  if (!fs::is_directory(parent, ec))
    throw IOError("the output's directory does not exist", parent.string());
  return p;
}
}  // namespace

namespace {
// What may not be replaced by `output`: an existing output without `force`, an input, a
// directory holding an input, a file of the other kind.
void check_replaceable(const fs::path& output, AtomicOutput::Kind kind, bool force,
                       const std::vector<fs::path>& inputs) {
  std::error_code ec;
  check_not_an_input(output, inputs);
  if (kind == AtomicOutput::Kind::directory && fs::is_directory(output, ec)) {
    for (const auto& in : inputs) {
      fs::path a = fs::weakly_canonical(in, ec), d = fs::weakly_canonical(output, ec);
      auto [m, _] = std::mismatch(d.begin(), d.end(), a.begin(), a.end());
      if (m == d.end())
        throw IOError("refusing to replace a directory that holds an input", output.string());
    }
  }
  if (fs::exists(output, ec) && !force)
    throw IOError("output exists; use --force to overwrite it", output.string());
  if (fs::exists(output, ec) &&
      (kind == AtomicOutput::Kind::directory) != fs::is_directory(output, ec))
    throw IOError(kind == AtomicOutput::Kind::directory ? "output exists and is not a directory"
                                                        : "output exists and is a directory",
                  output.string());
}
}  // namespace

OutputClaim claim_output(const fs::path& path, bool force, const std::vector<fs::path>& inputs,
                         AtomicOutput::Kind kind) {
  const fs::path output = output_path(path);
  OutputClaim claim(output);
  check_replaceable(output, kind, force, inputs);
  return claim;
}

std::vector<OutputClaim> claim_outputs(const std::vector<fs::path>& paths, bool force,
                                       const std::vector<fs::path>& inputs) {
  std::vector<OutputClaim> claims;
  for (const auto& p : paths)
    if (!p.empty() && p != "-") claims.push_back(claim_output(p, force, inputs));
  return claims;
}

void write_text_output(const fs::path& path, std::string_view text, bool force,
                       const std::vector<fs::path>& inputs) {
  AtomicOutput out(path, AtomicOutput::Kind::file, force, inputs);
  {
    std::ofstream f(out.temp_path(), std::ios::binary);
    f.write(text.data(), static_cast<std::streamsize>(text.size()));
    f.close();
    if (!f) throw IOError("cannot write", path.string());
  }
  out.commit();
}

AtomicOutput::AtomicOutput(fs::path final_path, Kind kind, bool force,
                           const std::vector<fs::path>& inputs)
    : final_(output_path(std::move(final_path))), kind_(kind), claim_(final_) {
  std::error_code ec;
  check_replaceable(final_, kind_, force, inputs);

  temp_ = temp_name_for(final_);
  slot_ = claim_slot(temp_, kind_ == Kind::directory);
  if (kind_ == Kind::directory) {
    if (!fs::create_directory(temp_, ec) || ec) {
      release_slot(slot_);
      throw IOError("cannot create a temporary directory: " + ec.message(), temp_.string());
    }
  }
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(temp_, ec);
  }
  release_slot(slot_);
}

void AtomicOutput::commit() {
  std::error_code ec;
  if (!fs::exists(temp_, ec)) throw IOError("nothing was written", final_.string());
  if (kind_ == Kind::directory && fs::exists(final_, ec)) {
    // Move the old directory aside first so that no moment exists without a complete output.
    fs::path old = temp_name_for(final_);
    fs::rename(final_, old, ec);
    if (ec) throw IOError("cannot replace the old output: " + ec.message(), final_.string());
    fs::rename(temp_, final_, ec);
    if (ec) {
      fs::rename(old, final_);
      throw IOError("cannot move the output into place: " + ec.message(), final_.string());
    }
    fs::remove_all(old, ec);
  } else {
    fs::rename(temp_, final_, ec);  // atomic replace of a file
    if (ec) throw IOError("cannot move the output into place: " + ec.message(), final_.string());
  }
  committed_ = true;
  release_slot(slot_);
  slot_ = -1;
}

}  // namespace df
