// Runs the real epuck2-fit binary (EPUCK2_FIT_EXE) in a per-test temporary folder and captures
// its exit code, standard output and standard error. Shared by the CLI test suites.
#pragma once

#include <algorithm>
#include <vector>

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "epuck2/logs/log.hpp"

namespace epuck2::testing {

namespace fs = std::filesystem;

/// The shipped logs of `kind` (data/raw/KIND/*.csv whose name starts with `prefix`), in name order.
inline std::vector<fs::path> shipped_logs(const std::string& kind, const std::string& prefix = "") {
  std::vector<fs::path> paths;
  for (const auto& e : fs::directory_iterator(fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / kind))
    if (e.path().extension() == ".csv" && e.path().filename().string().rfind(prefix, 0) == 0) paths.push_back(e.path());
  std::sort(paths.begin(), paths.end());
  return paths;
}

/// shipped_logs as command-line arguments, each quoted, each after a space.
inline std::string shipped_args(const std::string& kind, const std::string& prefix = "") {
  std::string args;
  for (const auto& p : shipped_logs(kind, prefix)) args += " \"" + p.string() + "\"";
  return args;
}

struct CliRun {
  int exit_code = -1;
  std::string out, err;
};

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// The shipped coefficient file data/fitted/KIND.json.
inline nlohmann::json shipped_fitted(const std::string& kind) {
  return nlohmann::json::parse(slurp(fs::path(EPUCK2_SOURCE_DIR) / "data" / "fitted" / (kind + ".json")));
}

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("epuck2_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// Runs `epuck2-fit ARGS` (in `cwd` when given).
  CliRun run(const std::string& args, const std::string& cwd = "") {
    const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    const std::string cmd = (cwd.empty() ? std::string() : "cd \"" + cwd + "\" && ") + "\"" + EPUCK2_FIT_EXE + "\" " + args + " >\"" + out.string() + "\" 2>\"" + err.string() + "\"";
    const int status = std::system(cmd.c_str());
    CliRun r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
  }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  /// The shipped logs of a kind (those whose name starts with `prefix`), in name order, as
  /// command-line arguments.
  static std::string shipped(const std::string& kind, const std::string& prefix = "") { return shipped_args(kind, prefix); }
  fs::path dir_;
};

/// A scratch folder for one test file's plain TEST()s (made on first use by mkdtemp under /tmp,
/// named from `tag`), the files they write there, and `simulate --like` through the real binary.
class Scratch {
 public:
  explicit Scratch(std::string tag) : tag_(std::move(tag)) {}
  const std::string& dir() const {
    if (dir_.empty()) {
      std::string tmpl = "/tmp/" + tag_ + "_XXXXXX";
      const char* d = mkdtemp(tmpl.data());
      dir_ = d ? d : "/tmp";
    }
    return dir_;
  }
  std::string write(const std::string& name, const std::string& text) const {
    const std::string path = dir() + "/" + name;
    std::ofstream(path) << text;
    return path;
  }
  /// Runs `epuck2-fit simulate KIND --like LOG [--coefficients FILE] -o OUT` and reads OUT back.
  logs::Log simulate_like(const std::string& kind, const std::string& log, const std::string& coefficients) const {
    const std::string out = dir() + "/" + kind + "_sim.csv";
    const std::string cmd = std::string(EPUCK2_FIT_EXE) + " simulate " + kind + " --like " + log +
                            (coefficients.empty() ? std::string() : " --coefficients " + coefficients) + " -o " + out + " 2>/dev/null";
    const int rc = std::system(cmd.c_str());
    EXPECT_EQ(rc, 0) << cmd;
    return logs::read_log(out);
  }

 private:
  std::string tag_;
  mutable std::string dir_;
};

}  // namespace epuck2::testing
