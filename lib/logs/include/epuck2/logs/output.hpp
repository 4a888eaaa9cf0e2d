// Writing results: whole or not at all (temporary file in the same folder, then rename), and
// logs in the CSV format of docs/logs.md (what the virtual robot and the simulator write).
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace epuck2::logs {

/// Every output file of one run, all or nothing. Each file is first written whole to a temporary
/// file in its target's folder, named `.NAME.epuck2-tmp.PID`; commit() renames them all onto
/// their targets once the run has succeeded. A stage destroyed without commit() (an exception, an
/// early return) removes its temporaries, and so does SIGINT or SIGTERM (a handler unlinks the
/// registered temporaries, then the signal is raised again with its default action). A temporary
/// left by a process that no longer runs (SIGKILL, power loss) is swept on the next write to the
/// same target.
///
/// Targets: a symlink is followed (the link stays, the file it points to is replaced); a replaced
/// file keeps its permission bits; a new file gets 0666 minus the umask. A target that is not a
/// regular file is never renamed over (output_target()): an existing device, FIFO or other special
/// file, and an open file descriptor (`-`, /dev/stdout, /dev/fd/N), are written in place at
/// commit(), before any rename, and every write is checked (a full device, a closed pipe: commit()
/// throws and replaces nothing).
class OutputStage {
 public:
  OutputStage() = default;
  ~OutputStage();
  OutputStage(const OutputStage&) = delete;
  OutputStage& operator=(const OutputStage&) = delete;

  /// Writes `content` to the temporary file of `path` now (a missing folder or a full disk fails
  /// here, before anything is replaced). Throws std::runtime_error naming `path`.
  void write(const std::string& path, const std::string& content);
  /// Reserves (creates empty) the temporary file of `path` for a writer of its own (gnuplot) and
  /// returns its name; the writer fills it before commit(). Throws std::runtime_error.
  std::string reserve(const std::string& path);
  /// Writes the targets written in place (checked, in the order staged), then renames every other
  /// staged file onto its target, in the order staged. Throws std::runtime_error (and removes the
  /// temporaries not yet renamed) when a write or a rename fails; a failed write in place replaces
  /// nothing.
  void commit();
  /// Removes every staged temporary; the targets are left as they were.
  void discard();
  /// The files staged so far (their targets, as given).
  std::vector<std::string> targets() const;

 private:
  struct Entry {
    std::string target;     ///< as given (for messages)
    std::string resolved;   ///< the file that is replaced (symlinks followed)
    std::string temporary;
    int slot = -1;          ///< in the signal handler's table
    bool in_place = false;  ///< written in place at commit() (output_target()), never renamed over
    int descriptor = -1;    ///< in place: the open descriptor written (-1: the target is opened)
    std::string content;    ///< in place, from write(): the bytes (reserve(): the temporary holds them)
  };
  void write_in_place(const Entry& e) const;
  Entry& stage(const std::string& path);
  std::vector<Entry> entries_;
};

/// How an output path is written. `replace`: a regular file or a new one (a temporary beside it,
/// then a rename). `in_place`: an existing file that is not a regular file or a folder (a device
/// such as /dev/null, a FIFO, a socket): opened at commit (a FIFO waits for its reader) and
/// written, never replaced. `descriptor`: an open file descriptor of this process, written as it
/// is (its offset and append mode kept): `-` and /dev/stdout are 1, /dev/stderr 2, /dev/fd/N and
/// /proc/self/fd/N are N.
enum class OutputWay { replace, in_place, descriptor };
struct OutputTarget {
  OutputWay way = OutputWay::replace;
  int descriptor = -1;  ///< OutputWay::descriptor: its number
};
OutputTarget output_target(const std::string& path);
/// True when `path` names standard output (`-`, /dev/stdout, /dev/fd/1, /proc/self/fd/1).
bool is_standard_output(const std::string& path);
/// For a target written in place (output_target()): why it cannot be written, checked without
/// writing or opening ("" when it can): a descriptor that is not open or is open for reading only,
/// a socket, a special file without write permission. "" for a target that is replaced.
std::string why_not_writable_in_place(const std::string& path);

/// The temporary file name a stage uses for `target` in this process: `.NAME.epuck2-tmp.PID` in
/// the target's folder.
std::string temporary_name_for(const std::string& target, long pid);

/// Writes `content` to `path` through a temporary file in the same folder and an atomic rename:
/// an existing file is either replaced whole or left untouched (a one-file OutputStage).
/// Throws std::runtime_error.
void write_file_atomically(const std::string& path, const std::string& content);

/// Shortest text that reads back to the same double (up to 17 significant digits).
std::string format_number(double value);
/// Fixed number of significant digits ("%.*g").
std::string format_number(double value, int significant_digits);

/// A log in docs/logs.md format, built in memory.
class LogWriter {
 public:
  explicit LogWriter(std::vector<std::string> columns) : columns_(std::move(columns)) {}
  void comment(const std::string& text) { comments_.push_back(text); }
  void metadata(const std::string& key, const std::string& value) { metadata_.emplace_back(key, value); }
  /// One row; values are printed with format_number unless `digits` > 0. A NaN or infinite value
  /// is never written: throws std::domain_error naming the row and column (the caller's bug, or a
  /// condition the caller should have refused with its location).
  void row(const std::vector<double>& values, int digits = 0);
  std::string str() const;
  std::size_t rows() const { return rows_.size(); }

 private:
  std::vector<std::string> columns_;
  std::vector<std::string> comments_;
  std::vector<std::pair<std::string, std::string>> metadata_;
  std::vector<std::string> rows_;
};

}  // namespace epuck2::logs
