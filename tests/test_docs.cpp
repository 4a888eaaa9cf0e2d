// The repository's own documentation stays in step with the code: every column the reader requires
// is documented in docs/logs.md and listed by `epuck2-fit KIND --help`, every option the CLI has is
// in docs/cli.md, docs/plugin-models.md's plug-in code is examples/plugin_models.cpp (which CTest builds, runs
// and checks), and no tracked product file points at notes outside the repository (a user's clone
// has only the repository).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "cli_harness.hpp"
#include "epuck2/logs/log.hpp"

namespace {

namespace fs = std::filesystem;
using epuck2::testing::CliTest;
using epuck2::testing::slurp;

const fs::path kSource = EPUCK2_SOURCE_DIR;

std::string doc(const std::string& name) { return slurp(kSource / "docs" / name); }

/// The files git tracks (paths relative to the source folder); empty when git is not available
/// or the source is not a git checkout.
std::vector<std::string> tracked_files() {
  std::vector<std::string> out;
  const std::string cmd = "git -C \"" + kSource.string() + "\" ls-files 2>/dev/null";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return out;
  std::string line;
  int c;
  while ((c = std::fgetc(pipe)) != EOF) {
    if (c == '\n') {
      if (!line.empty()) out.push_back(line);
      line.clear();
    } else {
      line += static_cast<char>(c);
    }
  }
  const int status = ::pclose(pipe);
  if (status != 0) out.clear();
  return out;
}

/// Without git: every file under the source folder but .git and build folders.
std::vector<std::string> files_on_disk() {
  std::vector<std::string> out;
  for (auto it = fs::recursive_directory_iterator(kSource); it != fs::recursive_directory_iterator(); ++it) {
    const std::string name = it->path().filename().string();
    if (it->is_directory() && (name == ".git" || name.rfind("build", 0) == 0 || fs::exists(it->path() / "CMakeCache.txt"))) {
      it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file()) out.push_back(fs::relative(it->path(), kSource).string());
  }
  return out;
}

class Docs : public CliTest {};

TEST_F(Docs, EveryRequiredColumnIsInLogsMdAndInTheKindsHelp) {
  const std::string logs_md = doc("logs.md");
  ASSERT_FALSE(logs_md.empty()) << "docs/logs.md is missing";
  for (epuck2::logs::Kind kind : epuck2::logs::all_kinds()) {
    const std::string k(epuck2::logs::to_string(kind));
    EXPECT_NE(logs_md.find("## " + k), std::string::npos) << "docs/logs.md has no section for " << k;
    const auto help = run(k + " --help");
    EXPECT_EQ(help.exit_code, 0) << k << " --help: " << help.err;
    EXPECT_NE(help.out.find("docs/logs.md"), std::string::npos) << k << " --help does not point to docs/logs.md";
    for (const std::string& column : epuck2::logs::required_columns(kind)) {
      EXPECT_NE(logs_md.find("`" + column + "`"), std::string::npos) << "docs/logs.md does not document " << k << " column " << column;
      EXPECT_NE(help.out.find(column), std::string::npos) << k << " --help does not list its required column " << column;
    }
  }
  EXPECT_NE(logs_md.find("`obstacle_distance_m`"), std::string::npos);
  EXPECT_NE(logs_md.find("`robot`"), std::string::npos);
}

TEST_F(Docs, DiagnoseAndSimulateHelpListTheirColumns) {
  const auto diagnose = run("diagnose --help");
  EXPECT_EQ(diagnose.exit_code, 0);
  for (epuck2::logs::Kind kind : epuck2::logs::all_kinds())
    for (const std::string& column : epuck2::logs::required_columns(kind))
      EXPECT_NE(diagnose.out.find(column), std::string::npos) << "diagnose --help does not list " << column;
  EXPECT_NE(diagnose.out.find("docs/diagnose.md"), std::string::npos);
  const auto simulate = run("simulate battery --help");
  EXPECT_EQ(simulate.exit_code, 0);
  EXPECT_NE(simulate.out.find("time_s"), std::string::npos);
  EXPECT_NE(simulate.out.find("speed_cm_s"), std::string::npos);
  EXPECT_NE(simulate.out.find("docs/logs.md"), std::string::npos);
}

TEST_F(Docs, EveryOptionOfEverySubcommandIsInCliMd) {
  const std::string cli_md = doc("cli.md");
  ASSERT_FALSE(cli_md.empty()) << "docs/cli.md is missing";
  const std::vector<std::string> subcommands{"battery", "table5",  "codegen", "simulate battery", "generate", "proximity",
                                             "light",   "ground",  "camera",  "drive",            "nist",     "diagnose"};
  const std::regex option("(^|[\\s,])(--[a-z][a-z0-9-]*)");
  for (const std::string& sub : subcommands) {
    const auto help = run(sub + " --help");
    ASSERT_EQ(help.exit_code, 0) << sub << " --help: " << help.err;
    EXPECT_NE(cli_md.find("epuck2-fit " + sub), std::string::npos) << "docs/cli.md does not show `epuck2-fit " << sub << "`";
    // Options are listed before the footer (which may mention other subcommands' options).
    const std::string options = help.out.substr(0, help.out.find("Log format"));
    std::set<std::string> seen;
    for (std::sregex_iterator it(options.begin(), options.end(), option), end; it != end; ++it) seen.insert((*it)[2]);
    for (const std::string& o : seen) EXPECT_NE(cli_md.find(o), std::string::npos) << "docs/cli.md does not document " << sub << " " << o;
  }
}

TEST(DocsFiles, TheReadmesPluginCodeIsTheExampleThatIsBuiltAndChecked) {
  // The README's plug-in section moved to docs/plugin-models.md (the README links to it).
  const std::string readme = slurp(kSource / "docs" / "plugin-models.md");
  const std::string heading = "# Using the models from an ARGoS plug-in";
  const std::size_t section = readme.find(heading);
  ASSERT_NE(section, std::string::npos) << "docs/plugin-models.md has no section '" << heading << "'";
  const std::size_t section_end = readme.find("\n## ", section + heading.size());
  const std::string fence = "```cpp\n";
  const std::size_t open = readme.find(fence, section);
  ASSERT_TRUE(open != std::string::npos && open < section_end) << "the section quotes no C++";
  const std::size_t close = readme.find("\n```", open + fence.size());
  ASSERT_NE(close, std::string::npos);
  const std::string quoted = readme.substr(open + fence.size(), close + 1 - (open + fence.size()));

  const std::string example = slurp(kSource / "examples" / "plugin_models.cpp");
  const std::string mark = "// [readme]\n";
  const std::size_t from = example.find(mark);
  ASSERT_NE(from, std::string::npos) << "examples/plugin_models.cpp has no '// [readme]' mark";
  const std::size_t to = example.find(mark, from + mark.size());
  ASSERT_NE(to, std::string::npos) << "examples/plugin_models.cpp has one '// [readme]' mark, not two";
  EXPECT_EQ(quoted, example.substr(from + mark.size(), to - (from + mark.size())))
      << "the README's plug-in code differs from examples/plugin_models.cpp between its [readme] marks: copy it over";
  // Every kind's model is shown.
  for (const char* use : {"proximity_model()", "light_model()", "ground_model()", "camera_model()", "drive_model()",
                          "battery_tables()", "DriveSimulation", "mean_raw", "mean_px", "reading("})
    EXPECT_NE(quoted.find(use), std::string::npos) << "the README's plug-in code does not use " << use;
}

TEST(DocsFiles, NoTrackedProductFileMentionsNotesOutsideTheRepository) {
  // Built at run time so that this file does not contain what it looks for.
  const std::string shared = "shared";
  const std::vector<std::string> needles{"../" + shared, shared + "/spec/", shared + "/reference/", shared + "/seed/"};
  std::vector<std::string> files = tracked_files();
  if (files.empty()) files = files_on_disk();
  ASSERT_FALSE(files.empty());
  for (const std::string& f : files) {
    const fs::path p = kSource / f;
    if (!fs::is_regular_file(p)) continue;
    // CI's entry point is the team's, not the product's: it may install ARGoS from the notes
    // beside the clone before running the README's test command.
    if (f == ".ci/run") continue;
    const std::string text = slurp(p);
    for (const std::string& needle : needles) {
      std::size_t at = text.find(needle);
      if (at == std::string::npos) continue;
      const std::size_t line = 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
      ADD_FAILURE() << f << ":" << line << ": mentions '" << needle << "', which a user's clone does not have; cite docs/ instead";
    }
  }
  for (const char* name : {"logs.md", "cli.md", "diagnose.md", "coefficient-files.md"})
    EXPECT_TRUE(fs::is_regular_file(kSource / "docs" / name)) << "docs/" << name << " is missing";
}

}  // namespace
