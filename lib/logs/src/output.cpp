// OutputStage: a run's output files, all or nothing (see output.hpp).
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <string>
#include <system_error>

#include "epuck2/logs/output.hpp"

namespace epuck2::logs {

namespace {
namespace fs = std::filesystem;

// The temporaries a signal handler removes. Fixed storage, no allocation: the handler only reads
// the table and calls unlink (async-signal-safe). A slot is published by storing `used` after
// its path is written, and withdrawn by clearing `used`.
constexpr int kSlots = 256;
constexpr std::size_t kPathMax = 4096;
char g_paths[kSlots][kPathMax];
std::atomic<bool> g_used[kSlots];
std::mutex g_slots_mutex;
std::once_flag g_handlers_installed;
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler reads these flags");

extern "C" void remove_temporaries_and_reraise(int sig) {
  const int saved = errno;
  for (int i = 0; i < kSlots; ++i)
    if (g_used[i].load(std::memory_order_acquire)) ::unlink(g_paths[i]);
  errno = saved;
  // Default action again, then the same signal: the process ends as the sender meant it to (the
  // signal stays blocked until the handler returns, then is delivered).
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

void install_handlers() {
  for (int sig : {SIGINT, SIGTERM}) {
    struct sigaction old {};
    if (::sigaction(sig, nullptr, &old) != 0) continue;
    // An ignored signal (nohup, a background job) stays ignored; a handler someone else installed
    // is left alone.
    if ((old.sa_flags & SA_SIGINFO) || old.sa_handler != SIG_DFL) continue;
    struct sigaction sa {};
    sa.sa_handler = remove_temporaries_and_reraise;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;
    ::sigaction(sig, &sa, nullptr);
  }
}

/// Registers `path` for removal on SIGINT/SIGTERM; -1 when it cannot be (too long, table full:
/// the temporary is then still removed on failure, only not on a signal).
int register_temporary(const std::string& path) {
  std::call_once(g_handlers_installed, install_handlers);
  if (path.size() + 1 > kPathMax) return -1;
  std::lock_guard<std::mutex> lock(g_slots_mutex);
  for (int i = 0; i < kSlots; ++i) {
    if (g_used[i].load(std::memory_order_relaxed)) continue;
    std::memcpy(g_paths[i], path.c_str(), path.size() + 1);
    g_used[i].store(true, std::memory_order_release);
    return i;
  }
  return -1;
}

void unregister_temporary(int slot) {
  if (slot >= 0) g_used[slot].store(false, std::memory_order_release);
}

constexpr const char* kTag = ".epuck2-tmp.";

/// The file a write to `p` replaces: symlinks followed (relative links from their folder).
fs::path resolve_target(const fs::path& given) {
  fs::path p = given;
  for (int hops = 0; hops < 40; ++hops) {
    std::error_code ec;
    const fs::file_status st = fs::symlink_status(p, ec);
    if (ec || !fs::is_symlink(st)) return p;
    const fs::path link = fs::read_symlink(p, ec);
    if (ec) return p;
    p = link.is_absolute() ? link : p.parent_path() / link;
  }
  throw std::runtime_error(given.string() + ": too many levels of symbolic links");
}

fs::path folder_of(const fs::path& p) { return p.has_parent_path() ? p.parent_path() : fs::path("."); }

/// Removes `.NAME.epuck2-tmp.PID` files in `dir` left by processes that no longer run.
void sweep_stale(const fs::path& dir, const std::string& name) {
  const std::string prefix = "." + name + kTag;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string f = it->path().filename().string();
    if (f.size() <= prefix.size() || f.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string digits = f.substr(prefix.size());
    if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    const long pid = std::stol(digits);
    if (pid <= 0 || pid == static_cast<long>(::getpid())) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == -1 && errno == ESRCH) {
      std::error_code ignored;
      fs::remove(it->path(), ignored);
    }
  }
}

/// Creates (truncates) the temporary with the target's permission bits when the target exists,
/// and writes `content` (may be empty). Throws std::runtime_error naming `what`.
void create_temporary(const fs::path& tmp, const fs::path& resolved, const std::string& content, const std::string& what) {
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0) throw std::runtime_error(what + ": cannot create the temporary file " + tmp.string() + ": " + std::strerror(errno));
  auto fail = [&](const std::string& why) {
    const int e = errno;
    ::close(fd);
    ::unlink(tmp.c_str());
    throw std::runtime_error(what + ": " + why + ": " + std::strerror(e));
  };
  struct stat st {};
  if (::stat(resolved.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::fchmod(fd, st.st_mode & 07777) != 0)
    fail("cannot give the temporary file the target's mode");
  const char* p = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail("writing the temporary file failed");
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0 && errno != EINVAL) fail("writing the temporary file failed");
  if (::close(fd) != 0) {
    ::unlink(tmp.c_str());
    throw std::runtime_error(what + ": writing the temporary file failed: " + std::strerror(errno));
  }
}
}  // namespace

std::string temporary_name_for(const std::string& target, long pid) {
  const fs::path t(target);
  return (folder_of(t) / ("." + t.filename().string() + kTag + std::to_string(pid))).string();
}

OutputStage::~OutputStage() { discard(); }

OutputStage::Entry& OutputStage::stage(const std::string& path) {
  if (path.empty()) throw std::runtime_error("an output file name is empty");
  const fs::path resolved = resolve_target(fs::path(path));
  const fs::path dir = folder_of(resolved);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw std::runtime_error(path + ": the folder " + dir.string() + " does not exist");
  if (fs::is_directory(resolved, ec)) throw std::runtime_error(path + ": is a folder, not a file");
  const fs::path absolute = fs::absolute(resolved, ec).lexically_normal();
  for (const Entry& e : entries_)
    if (e.resolved == absolute.string())
      throw std::runtime_error(path + ": given for two outputs of the same run (" + e.target + ")");
  sweep_stale(dir, resolved.filename().string());
  Entry e;
  e.target = path;
  e.resolved = absolute.string();
  e.temporary = temporary_name_for(e.resolved, static_cast<long>(::getpid()));
  e.slot = register_temporary(e.temporary);
  entries_.push_back(e);
  return entries_.back();
}

void OutputStage::write(const std::string& path, const std::string& content) {
  Entry& e = stage(path);
  try {
    create_temporary(e.temporary, e.resolved, content, path);
  } catch (...) {
    unregister_temporary(e.slot);
    entries_.pop_back();
    throw;
  }
}

std::string OutputStage::reserve(const std::string& path) {
  Entry& e = stage(path);
  try {
    create_temporary(e.temporary, e.resolved, std::string(), path);
  } catch (...) {
    unregister_temporary(e.slot);
    entries_.pop_back();
    throw;
  }
  return e.temporary;
}

void OutputStage::commit() {
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    Entry& e = entries_[i];
    if (::rename(e.temporary.c_str(), e.resolved.c_str()) != 0) {
      const std::string why = std::strerror(errno);
      const std::string target = e.target;
      // The files before this one are in place; the rest are not replaced.
      entries_.erase(entries_.begin(), entries_.begin() + static_cast<std::ptrdiff_t>(i));
      discard();
      throw std::runtime_error(target + ": cannot rename the temporary file into place: " + why);
    }
    unregister_temporary(e.slot);
  }
  entries_.clear();
}

void OutputStage::discard() {
  for (const Entry& e : entries_) {
    ::unlink(e.temporary.c_str());
    unregister_temporary(e.slot);
  }
  entries_.clear();
}

std::vector<std::string> OutputStage::targets() const {
  std::vector<std::string> t;
  for (const Entry& e : entries_) t.push_back(e.target);
  return t;
}

void write_file_atomically(const std::string& path, const std::string& content) {
  OutputStage stage;
  stage.write(path, content);
  stage.commit();
}

}  // namespace epuck2::logs
