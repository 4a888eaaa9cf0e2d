// epuck2-fit generate KIND --out-dir DIR [--seed N]: the virtual robot records the reference logs
// of one kind (or `all`, into DIR/<kind>/), all or nothing. The spellings published first,
// -o DIR and --out DIR, still work.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <unistd.h>

#include "app_support.hpp"
#include "commands.hpp"
#include "epuck2/logs/output.hpp"
#include "epuck2/virtual_robot/reference_logs.hpp"

namespace epuck2::app {

namespace {
struct GenerateOptions {
  std::string kind;
  std::string out_dir;
  std::string old_out;  ///< -o DIR, --out DIR: the spellings published first
  std::uint64_t seed = virtual_robot::kReferenceSeed;
  bool progress = false;
};

int run_generate(const GenerateOptions& o) {
  namespace fs = std::filesystem;
  std::vector<logs::Kind> kinds;
  if (o.kind == "all") {
    kinds = logs::all_kinds();
  } else if (auto k = logs::parse_kind(o.kind)) {
    kinds.push_back(*k);
  } else {
    std::vector<std::string> names = kind_names();
    names.push_back("all");
    throw UsageError(unknown_name("kind", o.kind, names));
  }
  if (!o.out_dir.empty() && !o.old_out.empty() && o.out_dir != o.old_out)
    throw UsageError("--out-dir " + o.out_dir + " and --out " + o.old_out + ": both name the folder (--out is the old spelling); give one");
  const std::string out_dir = o.out_dir.empty() ? o.old_out : o.out_dir;
  if (out_dir.empty()) throw UsageError("--out-dir DIR is required: the folder to write the logs into");
  // Checked before anything is recorded (issue #24, item 2): the folder, or the nearest of its
  // parents that exists, must be a folder that can be written to.
  {
    const std::string shown = "'" + logs::escape_control(out_dir) + "'";
    std::error_code ec;
    fs::path existing = fs::path(out_dir);
    while (!existing.empty() && !fs::exists(existing, ec)) existing = existing.parent_path();
    if (existing.empty()) existing = ".";
    const std::string existing_shown = "'" + logs::escape_control(existing.string()) + "'";
    if (!fs::is_directory(existing, ec))
      throw UsageError("--out-dir: " + shown + ": " + existing_shown + " is not a folder (nothing was recorded)");
    if (::access(existing.c_str(), W_OK | X_OK) != 0)
      throw UsageError("--out-dir: " + shown + ": the folder " + existing_shown + " cannot be written to (nothing was recorded)");
  }
  // All or nothing: every log of every kind is staged, then renamed into place together.
  logs::OutputStage stage;
  std::vector<std::string> done;
  // Progress on standard error, one line per kind (the virtual robot records a kind's logs in one
  // call): on a terminal rewritten in place, with --progress elsewhere one line each.
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  const bool show = o.progress || tty;
  std::size_t index = 0;
  for (logs::Kind kind : kinds) {
    if (show) {
      std::fprintf(stderr, "%sgenerate: recording %s logs (%zu/%zu)...%s", tty ? "\r" : "", std::string(logs::to_string(kind)).c_str(),
                   ++index, kinds.size(), tty ? "\033[K" : "\n");
      std::fflush(stderr);
    }
    const fs::path dir = o.kind == "all" ? fs::path(out_dir) / std::string(logs::to_string(kind)) : fs::path(out_dir);
    fs::create_directories(dir);
    const auto files = virtual_robot::reference_logs(kind, o.seed);
    for (const auto& f : files) stage.write((dir / f.name).string(), f.content);
    done.push_back("generate: wrote " + std::to_string(files.size()) + " " + std::string(logs::to_string(kind)) + " logs to " +
                   dir.string());
  }
  if (show && tty) std::fprintf(stderr, "\r\033[K");
  stage.commit();
  for (const auto& line : done) std::cerr << line << '\n';
  return 0;
}
}  // namespace

void setup_generate(CLI::App& app, Action& action) {
  auto opts = std::make_shared<GenerateOptions>();
  CLI::App* sub = app.add_subcommand("generate", "The virtual robot records reference logs (seeded, deterministic)");
  std::vector<std::string> kinds = kind_names();
  kinds.push_back("all");
  sub->add_option("KIND", opts->kind, "The kind of logs to record, or all")->required()->check(one_of(kinds, "kind"));
  sub->add_option("--out-dir", opts->out_dir, "Folder to write into, created if needed (for `all`, one sub-folder per kind); required")
      ->type_name("DIR");
  sub->add_option("-o,--out", opts->old_out)->group("");  // the spellings published first
  sub->add_option("--seed", opts->seed, "Random seed")->capture_default_str()->check(whole_number());
  sub->add_flag("--progress", opts->progress,
                "Show progress on standard error (the kind being recorded); on by default when standard error is a terminal");
  sub->callback([opts, &action] { action = [opts] { return run_generate(*opts); }; });
}

}  // namespace epuck2::app
