#include "core/atomic_output.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <atomic>
#include <csignal>
#include <cstring>
#include <mutex>

#include "core/error.h"

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

int stop_requested() { return g_stop_signal.load(); }

void check_not_an_input(const fs::path& output, const std::vector<fs::path>& inputs) {
  std::error_code ec;
  for (const auto& in : inputs) {
    if (fs::exists(in, ec) && fs::exists(output, ec) && fs::equivalent(in, output, ec))
      throw IOError("refusing to overwrite an input with the output", output.string());
  }
}

AtomicOutput::AtomicOutput(fs::path final_path, Kind kind, bool force,
                           const std::vector<fs::path>& inputs)
    : final_(std::move(final_path)), kind_(kind) {
  if (final_.empty()) throw UsageError("no output path given (-o)");
  if (!final_.has_filename()) final_ = final_.parent_path();  // "dir/" -> "dir"
  std::error_code ec;
  fs::path parent = final_.parent_path().empty() ? fs::path(".") : final_.parent_path();
  if (!fs::is_directory(parent, ec))
    throw IOError("the output's directory does not exist", parent.string());
  check_not_an_input(final_, inputs);
  if (kind_ == Kind::directory && fs::is_directory(final_, ec)) {
    for (const auto& in : inputs) {
      fs::path a = fs::weakly_canonical(in, ec), d = fs::weakly_canonical(final_, ec);
      auto [m, _] = std::mismatch(d.begin(), d.end(), a.begin(), a.end());
      if (m == d.end()) throw IOError("refusing to replace a directory that holds an input", final_.string());
    }
  }
  if (fs::exists(final_, ec) && !force)
    throw IOError("output exists; use --force to overwrite it", final_.string());
  if (fs::exists(final_, ec) && (kind_ == Kind::directory) != fs::is_directory(final_, ec))
    throw IOError(kind_ == Kind::directory ? "output exists and is not a directory"
                                           : "output exists and is a directory",
                  final_.string());

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
