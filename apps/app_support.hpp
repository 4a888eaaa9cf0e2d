// Shared by the subcommands: JSON output (stdout or atomically to a file), JSON input with
// file:line:column errors, and reading logs with --skip-bad-rows.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/coefficients/model_sets.hpp"
#include "epuck2/logs/log.hpp"

#include "epuck2/logs/output.hpp"

namespace epuck2::app {

/// `j` as written (indented, trailing newline). A NaN or infinity left in it is a bug of the
/// subcommand (a value the data do not determine must be written as null with its reason):
/// throws NoUsableFit (exit 1) naming where it is, e.g. `std_errors.fov_deg`.
std::string json_text(const nlohmann::json& j);
/// Stages `j` for `path` in `stage` (in place once the run commits).
void write_json(logs::OutputStage& stage, const nlohmann::json& j, const std::string& path);
/// Writes `j` to `path` on its own, atomically (`-`, a device or a FIFO: in place, checked;
/// logs::output_target()).
void write_json(const nlohmann::json& j, const std::string& path);
/// A result that is text (the CSVs of `simulate`): to standard output when `path` is empty, else
/// to `path` atomically (a temporary file in its folder, then a rename).
void write_output(const std::string& text, const std::string& path);
/// Makes standard output checkable: from here on `stdout` (printf, fwrite) and std::cout write
/// through one stdio stream whose every write to file descriptor 1 is checked, and the first
/// failure's reason (errno) is kept. Called once, first thing in main().
void capture_standard_output();
/// Flushes standard output (std::cout and stdio) and returns "" when everything written since
/// capture_standard_output() reached file descriptor 1, else "standard output: REASON" (e.g.
/// "standard output: No space left on device"). main() turns a failure into exit 2.
std::string standard_output_error();

/// A CLI11 check for a numeric option: a finite number in [lo, hi]. (CLI::Range alone lets NaN
/// through, since every comparison with NaN is false.) The error names the option and the range.
CLI::Validator finite_range(double lo, double hi);

/// A CLI11 check for an unsigned whole number (a seed, a count): digits only, so that "-1" is
/// refused instead of wrapping round to 2^64 - 1.
CLI::Validator whole_number();

/// Reads a JSON file; every error names the file, and the line and column where the text shows
/// them (a syntax error, a number too large for a double such as 1e999).
nlohmann::json read_json(const std::string& path);

/// The one of `choices` closest to `word` (edit distance, ignoring case) when it is close enough
/// to be a slip of the keyboard (at most 2 edits, and fewer than half the word's letters), else "".
std::string closest(const std::string& word, const std::vector<std::string>& choices);

/// "a, b, c": the names joined.
std::string join(const std::vector<std::string>& names, const std::string& separator = ", ");

/// "unknown KIND 'word'; did you mean 'x'? KINDs: a, b, c" (without "did you mean" when nothing is
/// close): the message for a name that is not one of `choices`.
std::string unknown_name(const std::string& what, const std::string& word, const std::vector<std::string>& choices,
                         const std::string& list_title = "");

/// A CLI11 check that the value is one of `choices` (exit 2 otherwise, naming the closest and
/// listing them all); --help shows them as {a,b,c}.
CLI::Validator one_of(const std::vector<std::string>& choices, const std::string& what = "value");

/// The log kinds (battery, proximity, light, ground, camera, drive).
std::vector<std::string> kind_names();

/// `source` of --coefficients when it is not `fitted` or `plugin`: a file. A name that is no file
/// but close to one of the two words (plugn) is a usage error that says so.
const std::string& coefficient_file(const std::string& source);

/// The model of the kind `kind` that --coefficients `source` names: `fitted` the model compiled
/// in from data/fitted (the battery's tables, where this build has them), a FILE its model
/// (coefficients::model_from_json; a reader's error that is not at a file position is a usage
/// error); empty and `plugin` none (the plug-in's published model). `file`, when given, receives
/// the FILE's JSON.
/// `robot`, when given, names the file's robot set read over its pooled one
/// (coefficients_robot's choice).
std::optional<coefficients::AnyModel> coefficients_model(const std::string& kind, const std::string& source,
                                                         nlohmann::json* file = nullptr, const std::string& robot = "");
/// Which robot set of --coefficients `source` runs on logs of the robots `log_robots`, --robot
/// `robot` ("" when not given): coefficients::choose_robot_for_logs on the FILE (docs/cli.md);
/// none for `plugin`, `fitted` or no file. A --robot the file has no set for, or --robot without a
/// FILE, is a usage error (exit 2) listing the file's robots.
coefficients::LogRobotChoice coefficients_robot(const std::string& source, const std::string& robot,
                                                const std::vector<std::string>& log_robots);
/// Adds --robot ID to `simulate KIND --like` and `diagnose` (the same help text on both).
void add_coefficients_robot(CLI::App* sub, std::string& robot);

/// A CLI11 check for a figure file: its extension names the format (.png, .svg or .pdf), else
/// exit 2 saying which are accepted.
CLI::Validator figure_file();

/// A CLI11 check for a file the run will write (-o, --plot, ...), made when the options are read,
/// before any work: the folder it goes into exists, is a folder and is writable, and the path is
/// not itself a folder (unless `folder_allowed`: diagnose's old `--plot DIR`). Otherwise exit 2 at
/// once, naming the path and what is wrong. A symlink is followed. A target written in place
/// (`-` and /dev/stdout: standard output; /dev/fd/N; an existing device or FIFO): the descriptor
/// open for writing, the special file writable and no socket (logs::why_not_writable_in_place).
CLI::Validator output_file(bool folder_allowed = false);
/// Each warning the run's figures left (a page too short for their panels: plot::check_panel_height),
/// on standard error as "COMMAND: warning: FIGURE: ...".
void print_figure_warnings(const std::string& command);

/// Why `path` cannot be written as an output ("" when it can): output_file()'s check.
std::string why_not_writable(const std::string& path, bool folder_allowed = false);

/// Adds --figure-size WxH{cm,mm,in} and --font-size PT (the same on every subcommand that draws):
/// the printed size and text of every figure the run draws (plot::set_page). A bad value is
/// exit 2 saying what was expected.
void add_figure_options(CLI::App* sub);

/// Adds --skip-bad-rows (the same help text on every subcommand that reads logs).
void add_skip_bad_rows(CLI::App* sub, bool& flag);
/// Reads the logs (logs::read_logs), then reports on standard error every row left out under
/// --skip-bad-rows: the count, then the first 10 as file:line:column: why. Throws logs::InputError
/// for units that cannot be the columns' (calibrate::check_plausible_units: cm written as m).
/// Two logs of the same rows (identical_logs: a copy under another name) are a warning, added
/// to `warnings` when given (the command's JSON holds it), else printed on standard error.
std::vector<logs::Log> read_logs_reporting(const std::string& command, const std::vector<std::string>& paths,
                                           std::optional<logs::Kind> kind, bool skip_bad_rows,
                                           std::vector<std::string>* warnings = nullptr);
/// The logs with each one whose `robot` column names several robots split into one log per robot
/// (logs::split_by_robot_column), so that a fit counts each robot's rows as that robot's (its own
/// set, the robots' comparison, replicates within one robot); each such file is said on standard
/// error ("COMMAND: the robot column of F names 2 robots (a, b): ...").
std::vector<logs::Log> split_robot_columns(const std::string& command, std::vector<logs::Log> logs);
/// The logs of `robot` (all when empty); exit 2 listing the robots when none is that one (--robot
/// of the fitting commands).
std::vector<logs::Log> select_robot(std::vector<logs::Log> all, const std::string& robot);
/// The warning for a log whose `robot` column names several robots, read as one log (diagnose):
/// "" when it names one at most.
std::string robot_column_warning(const logs::Log& log);

/// One warning per log whose data rows (every column, row by row) and robot are another's given
/// before it: "B holds the same data rows as A (N rows, robot R): ...". The same file twice is
/// refused earlier (logs::read_logs).
std::vector<std::string> identical_logs(const std::vector<logs::Log>& logs);
/// Reports on standard error the rows left out of these logs (nothing when none was).
void report_skipped(const std::string& command, const std::vector<logs::Log>& logs);

}  // namespace epuck2::app
