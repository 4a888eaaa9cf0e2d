// Shared by the subcommands: JSON output (stdout, or staged with the run's other outputs), the
// repository's data folder.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "epuck2/logs/output.hpp"

namespace epuck2::app {

/// `j` as written (indented, trailing newline). A NaN or infinity left in it is a bug of the
/// subcommand (a value the data do not determine must be written as null with its reason):
/// throws NoUsableFit (exit 1) naming where it is, e.g. `std_errors.fov_deg`.
std::string json_text(const nlohmann::json& j);
/// Stages `j` for `path` in `stage` (in place once the run commits).
void write_json(logs::OutputStage& stage, const nlohmann::json& j, const std::string& path);
/// Writes `j` to `path` on its own, atomically; "-" means standard output.
void write_json(const nlohmann::json& j, const std::string& path);
/// A CLI11 check for a numeric option: a finite number in [lo, hi]. (CLI::Range alone lets NaN
/// through, since every comparison with NaN is false.) The error names the option and the range.
CLI::Validator finite_range(double lo, double hi);

/// A CLI11 check for an unsigned whole number (a seed, a count): digits only, so that "-1" is
/// refused instead of wrapping round to 2^64 - 1.
CLI::Validator whole_number();

/// Reads a JSON file; errors name the file (and line/column for a parse error).
nlohmann::json read_json(const std::string& path);

}  // namespace epuck2::app
