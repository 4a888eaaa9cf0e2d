// Shared by the subcommands: JSON output (stdout or atomically to a file), the repository's
// data folder.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace epuck2::app {

/// Writes `j` (indented, trailing newline) to `path` atomically; "-" means standard output.
void write_json(const nlohmann::json& j, const std::string& path);
/// Reads a JSON file; errors name the file (and line/column for a parse error).
nlohmann::json read_json(const std::string& path);

}  // namespace epuck2::app
