// OutputStage: a run's output files, all or nothing (see output.hpp).
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
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
  // SIGPIPE too: an output written in place to a FIFO or a pipe whose reader went away.
  for (int sig : {SIGINT, SIGTERM, SIGPIPE}) {
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

/// N when `text` is a descriptor number (digits only, at most 9), else -1.
int descriptor_number(const std::string& text) {
  if (text.empty() || text.size() > 9 || text.find_first_not_of("0123456789") != std::string::npos) return -1;
  return std::stoi(text);
}

/// The name of a target in messages: "standard output" for descriptor 1, else the path given.
std::string shown_target(const std::string& path, int descriptor) {
  return descriptor == STDOUT_FILENO ? "standard output" : path;
}

/// Writes every byte of `content` to `fd`; false (errno set) on the first failure.
bool write_all(int fd, const std::string& content) {
  const char* p = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = EIO;
      return false;
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  return true;
}

/// The whole content of the file `path` (a reserved temporary, filled by its writer).
std::string read_whole(const std::string& path, const std::string& what) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error(what + ": cannot read the temporary file " + path + ": " + std::strerror(errno));
  std::string out;
  char buf[65536];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int e = errno;
      ::close(fd);
      throw std::runtime_error(what + ": cannot read the temporary file " + path + ": " + std::strerror(e));
    }
    if (n == 0) break;
    out.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fd);
  return out;
}

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

OutputTarget output_target(const std::string& path) {
  OutputTarget t;
  int fd = -1;
  if (path == "-" || path == "/dev/stdout") fd = STDOUT_FILENO;
  else if (path == "/dev/stderr") fd = STDERR_FILENO;
  else if (path.rfind("/dev/fd/", 0) == 0) fd = descriptor_number(path.substr(8));
  else if (path.rfind("/proc/self/fd/", 0) == 0) fd = descriptor_number(path.substr(14));
  if (fd >= 0) {
    t.way = OutputWay::descriptor;
    t.descriptor = fd;
    return t;
  }
  struct stat st {};
  if (!path.empty() && ::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode))
    t.way = OutputWay::in_place;
  return t;
}

bool is_standard_output(const std::string& path) {
  const OutputTarget t = output_target(path);
  return t.way == OutputWay::descriptor && t.descriptor == STDOUT_FILENO;
}

std::string why_not_writable_in_place(const std::string& path) {
  const OutputTarget t = output_target(path);
  if (t.way == OutputWay::descriptor) {
    const int flags = ::fcntl(t.descriptor, F_GETFL);
    const std::string which = t.descriptor == STDOUT_FILENO ? std::string("standard output")
                                                            : "file descriptor " + std::to_string(t.descriptor);
    if (flags == -1) return which + " is not open";
    if ((flags & O_ACCMODE) == O_RDONLY) return which + " is open for reading only";
    return std::string();
  }
  if (t.way != OutputWay::in_place) return std::string();
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && S_ISSOCK(st.st_mode))
    return "is a socket, which cannot be opened as a file (give a file, a FIFO or a device)";
  if (::access(path.c_str(), W_OK) != 0) return std::string("cannot be written to: ") + std::strerror(errno);
  return std::string();
}

std::string temporary_name_for(const std::string& target, long pid) {
  const fs::path t(target);
  return (folder_of(t) / ("." + t.filename().string() + kTag + std::to_string(pid))).string();
}

OutputStage::~OutputStage() { discard(); }

OutputStage::Entry& OutputStage::stage(const std::string& path) {
  if (path.empty()) throw std::runtime_error("an output file name is empty");
  const OutputTarget way = output_target(path);
  if (way.way != OutputWay::replace) {
    // Written in place at commit: a device, a FIFO or a descriptor is never renamed over.
    const std::string why = why_not_writable_in_place(path);
    if (!why.empty()) throw std::runtime_error(path + ": " + why);
    Entry e;
    e.target = path;
    e.in_place = true;
    e.descriptor = way.descriptor;
    std::error_code ec;
    e.resolved = e.descriptor >= 0 ? "/dev/fd/" + std::to_string(e.descriptor) : fs::canonical(path, ec).string();
    if (ec) e.resolved = path;
    for (const Entry& other : entries_)
      if (other.resolved == e.resolved)
        throw std::runtime_error(path + ": given for two outputs of the same run (" + other.target + ")");
    entries_.push_back(e);
    return entries_.back();
  }
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
  if (e.in_place) {
    e.content = content;
    return;
  }
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
  if (e.in_place) {
    // The writer fills a temporary of the temporary folder (the target's folder may be /dev or
    // /proc/self/fd); commit() copies it into the target.
    static std::atomic<int> reserved{0};
    std::error_code ec;
    const fs::path folder = fs::temp_directory_path(ec);
    e.temporary = ((ec ? fs::path("/tmp") : folder) / (".epuck2-in-place." + std::to_string(::getpid()) + "." +
                                                       std::to_string(++reserved)))
                      .string();
    e.slot = register_temporary(e.temporary);
  }
  try {
    create_temporary(e.temporary, e.in_place ? fs::path(e.temporary) : fs::path(e.resolved), std::string(), path);
  } catch (...) {
    unregister_temporary(e.slot);
    entries_.pop_back();
    throw;
  }
  return e.temporary;
}

void OutputStage::write_in_place(const Entry& e) const {
  const std::string shown = shown_target(e.target, e.descriptor);
  const std::string content = e.temporary.empty() ? e.content : read_whole(e.temporary, e.target);
  int fd = e.descriptor;
  if (fd < 0) {
    // No O_CREAT, no O_TRUNC: the special file is written as it is (a FIFO waits for a reader).
    fd = ::open(e.target.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC);
    if (fd < 0) throw std::runtime_error(shown + ": cannot open it for writing: " + std::strerror(errno));
  } else if (fd == STDOUT_FILENO) {
    std::fflush(stdout);  // what the run printed before keeps its place
  }
  if (!write_all(fd, content)) {
    const int err = errno;
    if (e.descriptor < 0) ::close(fd);
    throw std::runtime_error(shown + ": " + std::strerror(err));
  }
  if (e.descriptor < 0 && ::close(fd) != 0) throw std::runtime_error(shown + ": " + std::strerror(errno));
}

void OutputStage::commit() {
  // First the targets written in place: a full device or a closed pipe fails before any file is
  // replaced.
  for (Entry& e : entries_) {
    if (!e.in_place) continue;
    try {
      write_in_place(e);
    } catch (...) {
      discard();
      throw;
    }
  }
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    Entry& e = entries_[i];
    if (e.in_place) {
      if (!e.temporary.empty()) ::unlink(e.temporary.c_str());
      unregister_temporary(e.slot);
      continue;
    }
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
    if (!e.temporary.empty()) ::unlink(e.temporary.c_str());
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
