// Session 13's probes (scripts/mutate.sh, s13_): slips the lead listed in product files no mutant
// had touched, to find where the tests were thin. For each probe that survived, a test whose
// expected values are worked by hand here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "epuck2/logs/json_location.hpp"

namespace test_probed_areas_cpp {
namespace {

std::string at(const std::string& text, const std::string& pointer) {
  const epuck2::logs::SourcePos p = epuck2::logs::locate_json_pointer(text, pointer);
  return std::to_string(p.line) + ":" + std::to_string(p.column);
}

// A file written on Windows: a byte-order mark, then CRLF line ends. The BOM is skipped (the JSON
// starts after it) and each CRLF ends one line; columns count bytes from the line's start (the
// BOM's three on line 1). Worked by hand: line 2 is `  "kind": "x",`, its value at column 11;
// line 4 is ` 2]`, the element at column 2.
TEST(JsonLocationProbe, AByteOrderMarkAndWindowsLineEnds) {
  const std::string text = "\xEF\xBB\xBF{\r\n  \"kind\": \"x\",\r\n  \"a\": [1,\r\n 2]\r\n}\r\n";
  EXPECT_EQ(at(text, ""), "1:4");
  EXPECT_EQ(at(text, "/kind"), "2:11");
  EXPECT_EQ(at(text, "/a"), "3:8");
  EXPECT_EQ(at(text, "/a/1"), "4:2");
  EXPECT_EQ(at(text, "/b"), "0:0");
}

// An old Mac file: lone CRs end lines too. `{` CR ` "k": 1}`: the value at line 2, column 7
// (space 1, quote 2, k 3, quote 4, colon 5, space 6, 1 at 7).
TEST(JsonLocationProbe, LoneCarriageReturnsEndLines) {
  EXPECT_EQ(at("{\r \"k\": 1}", "/k"), "2:7");
  // CR LF is one line end, CR CR two.
  EXPECT_EQ(at("{\r\n\"k\": 1}", "/k"), "2:6");
  EXPECT_EQ(at("{\r\r\"k\": 1}", "/k"), "3:6");
}

namespace fs = std::filesystem;

/// Runs the real binary; standard output to `out`, standard error to `err` (files), the exit code.
int run(const std::string& args, const fs::path& out, const fs::path& err) {
  const std::string cmd = "'" EPUCK2_FIT_EXE "' " + args + " >'" + out.string() + "' 2>'" + err.string() + "'";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}
using epuck2::testing::slurp;
fs::path scratch() {
  char tmpl[] = "/tmp/epuck2-probed-XXXXXX";
  EXPECT_NE(::mkdtemp(tmpl), nullptr);
  return tmpl;
}

// `diagnose --json` in the spellings docs/cli.md publishes: the flag, `--json -` and `--json=-`
// (standard output), `--json=FILE.json` (the report to FILE); `--json=FILE` of another name is
// exit 2 saying what was expected.
TEST(DiagnoseJsonProbe, EverySpellingOfStandardOutput) {
  const fs::path d = scratch();
  const std::string log = std::string(EPUCK2_SOURCE_DIR) + "/data/raw/ground/ground_virtual-epuck2-1.csv";
  for (const std::string spelling : {"--json", "--json -", "--json=-"}) {
    ASSERT_EQ(run("diagnose '" + log + "' " + spelling, d / "out", d / "err"), 0) << spelling << ": " << slurp(d / "err");
    const nlohmann::json j = nlohmann::json::parse(slurp(d / "out"));
    EXPECT_EQ(j["kind"], "ground") << spelling;
  }
  ASSERT_EQ(run("diagnose '" + log + "' --json=" + (d / "r.json").string(), d / "out", d / "err"), 0) << slurp(d / "err");
  EXPECT_EQ(nlohmann::json::parse(slurp(d / "r.json"))["kind"], "ground");
  EXPECT_EQ(run("diagnose '" + log + "' --json=" + (d / "r.txt").string(), d / "out", d / "err"), 2);
  EXPECT_NE(slurp(d / "err").find("must end in .json"), std::string::npos) << slurp(d / "err");
  fs::remove_all(d);
}

// The extended model a diagnosis writes (`diagnose -o`) predicts what the diagnosis fitted: a
// ground log whose readings drift with a temperature in kelvin (around 300 K, far from 0: a term
// slope (T - centre) taken about the wrong centre moves every prediction by slope x the error,
// which the base's offsets absorb in the fit but not in the file). Generated here: offset 60 + gain
// 900 grey + 3 counts/K (T - 300) + N(0, 3), 3 sensors x 11 grey levels x 30 readings. The file,
// run by `simulate --like` without noise, leaves residuals of mean 0 on each sensor (the fit's
// offsets make them so: within 0.35 counts, 3.5 standard errors of a 330-reading mean), and its
// slope is the truth's (within 0.1 counts/K: the slope's standard error is about 0.02).
TEST(ExtendedModelProbe, TheFileOfAKelvinCovariatePredictsWhatTheDiagnosisFitted) {
  const fs::path d = scratch();
  std::uint64_t state = 20261127;
  auto unit = [&]() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (static_cast<double>(state >> 11) + 0.5) / 9007199254740992.0;
  };
  auto normal = [&]() { return std::sqrt(-2.0 * std::log(unit())) * std::cos(2.0 * std::acos(-1.0) * unit()); };
  {
    std::ofstream log(d / "ground_kelvin.csv");
    log << "# robot: r\ngrey,sensor,value,temperature_k\n";
    for (int g = 0; g <= 10; ++g)
      for (int s = 0; s < 3; ++s)
        for (int i = 0; i < 30; ++i) {
          const double t = 290.0 + 20.0 * unit();
          const double v = std::round(60.0 + 900.0 * g / 10.0 + 3.0 * (t - 300.0) + 3.0 * normal());
          char row[96];
          std::snprintf(row, sizeof row, "%.1f,%d,%.0f,%.3f\n", g / 10.0, s, v, t);
          log << row;
        }
  }
  const std::string log = (d / "ground_kelvin.csv").string();
  ASSERT_EQ(run("diagnose '" + log + "' -o '" + (d / "ext.json").string() + "'", d / "out", d / "err"), 0) << slurp(d / "err");
  const nlohmann::json ext = nlohmann::json::parse(slurp(d / "ext.json"));
  ASSERT_TRUE(ext["effects"].contains("covariate:temperature_k")) << ext["effects"].dump();
  EXPECT_NEAR(ext["effects"]["covariate:temperature_k"]["slope"].get<double>(), 3.0, 0.1);
  ASSERT_EQ(run("simulate ground --like '" + log + "' --coefficients '" + (d / "ext.json").string() + "' -o '" + (d / "sim.csv").string() + "'",
                d / "out", d / "err"),
            0)
      << slurp(d / "err");
  // Row by row: the measured reading minus the simulated one, per sensor.
  auto rows = [](const fs::path& p) {
    std::vector<std::vector<double>> out;
    std::ifstream in(p);
    std::string line;
    bool header = false;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      if (!header) {
        header = true;
        EXPECT_EQ(line.rfind("grey,sensor,value", 0), 0u) << line;
        continue;
      }
      std::vector<double> r;
      std::stringstream cells(line);
      std::string c;
      while (std::getline(cells, c, ',')) r.push_back(std::strtod(c.c_str(), nullptr));
      out.push_back(r);
    }
    return out;
  };
  const auto measured = rows(d / "ground_kelvin.csv"), simulated = rows(d / "sim.csv");
  ASSERT_EQ(measured.size(), simulated.size());
  double sum[3] = {0, 0, 0};
  int n[3] = {0, 0, 0};
  for (std::size_t i = 0; i < measured.size(); ++i) {
    const int s = static_cast<int>(measured[i][1]);
    sum[s] += measured[i][2] - simulated[i][2];
    ++n[s];
  }
  for (int s = 0; s < 3; ++s) EXPECT_NEAR(sum[s] / n[s], 0.0, 0.35) << "sensor " << s << ": the file's predictions are off";
  fs::remove_all(d);
}

}  // namespace
}  // namespace test_probed_areas_cpp
