// Round 16 of the fresh slips (bench/fresh-slips.md): a test for each behaviour its slips changed
// that no test had pinned down. Every expected value comes from the docs or the NIST StRD, or is
// worked by hand in the comment beside it, never from the code under test.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "epuck2/coefficients/model_sets.hpp"
#include "epuck2/fit/fit_curve.hpp"
#include "epuck2/logs/output.hpp"

namespace test_round_sixteen_cpp {

namespace fs = std::filesystem;
using epuck2::testing::CliTest;
using epuck2::testing::slurp;
using nlohmann::json;

class RoundSixteenCli : public CliTest {
 protected:
  std::string q(const std::string& name) const { return "\"" + (dir_ / name).string() + "\""; }
};

// ---- lib/fit --------------------------------------------------------------------------------

struct Constant {
  static constexpr int kParameters = 1;
  static constexpr bool kLinearInParameters = true;
  template <typename T>
  T operator()(const T* p, double) const { return p[0]; }
};

// A bound given alone is kept: a constant fitted to 2, 2, 2 with an upper bound of 1 and no lower
// bound ends on the bound, 1; with a lower bound of 3 and no upper, on 3.
TEST(RoundSixteenFit, AnUpperBoundAloneIsKept) {
  const double inf = std::numeric_limits<double>::infinity();
  epuck2::fit::Parameter upper{"k", 0.0};
  upper.lower = -inf;
  upper.upper = 1.0;
  const auto r = epuck2::fit::fit_curve(Constant{}, {0, 1, 2}, {2, 2, 2}, {upper});
  ASSERT_TRUE(r.usable) << r.message;
  EXPECT_NEAR(r.parameters[0].value, 1.0, 1e-9);
  epuck2::fit::Parameter lower{"k", 5.0};
  lower.lower = 3.0;
  lower.upper = inf;
  const auto s = epuck2::fit::fit_curve(Constant{}, {0, 1, 2}, {2, 2, 2}, {lower});
  ASSERT_TRUE(s.usable) << s.message;
  EXPECT_NEAR(s.parameters[0].value, 3.0, 1e-9);
}

// ---- lib/logs --------------------------------------------------------------------------------

// A NaN is never written; the error names the row as a person counts (the first row is row 1) and
// the column (docs/cli.md: no output holds a NaN).
TEST(RoundSixteenLogs, ANaNRowIsNamedFromOne) {
  epuck2::logs::LogWriter first({"a"});
  try {
    first.row({std::nan("")});
    FAIL() << "a NaN was written";
  } catch (const std::domain_error& e) {
    EXPECT_NE(std::string(e.what()).find("row 1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'a'"), std::string::npos) << e.what();
  }
  epuck2::logs::LogWriter third({"a", "b"});
  third.row({1, 2});
  third.row({3, 4});
  try {
    third.row({5, std::numeric_limits<double>::infinity()});
    FAIL() << "an infinity was written";
  } catch (const std::domain_error& e) {
    EXPECT_NE(std::string(e.what()).find("row 3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'b'"), std::string::npos) << e.what();
  }
}

// ---- lib/coefficients: the file cache ---------------------------------------------------------

// A coefficient file rewritten with the same length but another value is read anew (the cache
// keys on size and modification time): 1.5 then 2.5, the same number of bytes.
TEST(RoundSixteenCoefficients, AFileRewrittenAtTheSameLengthIsReadAnew) {
  const fs::path f = fs::temp_directory_path() / ("epuck2_r16_cache_" + std::to_string(::getpid()) + ".json");
  std::ofstream(f) << R"({"gain_raw": 1.5})";
  const auto a = epuck2::coefficients::shared_json_file(f.string());
  ASSERT_TRUE(a);
  EXPECT_DOUBLE_EQ(a->at("gain_raw").get<double>(), 1.5);
  std::ofstream(f) << R"({"gain_raw": 2.5})";
  fs::last_write_time(f, fs::last_write_time(f) + std::chrono::seconds(2));
  const auto b = epuck2::coefficients::shared_json_file(f.string());
  ASSERT_TRUE(b);
  EXPECT_DOUBLE_EQ(b->at("gain_raw").get<double>(), 2.5);
  fs::remove(f);
}

// ---- calibrations ------------------------------------------------------------------------------

/// A proximity log by hand: 10 distances 5..50 mm, 8 sensors, 6 readings each, from Eq. 1 with
/// a = 200, b = -30, c = 1.1; sensor s's readings scattered by (s + 1) x {-2, 1, 0, 2, -1, 0}:
/// replicate sd (s + 1) sqrt(10/5) = 1.414 (s + 1) counts.
std::string proximity_log_noisier_by_sensor() {
  const int jitter[6] = {-2, 1, 0, 2, -1, 0};
  std::ostringstream o;
  o << "# robot: hand-made\ndistance_m,sensor,value\n";
  for (int mm = 5; mm <= 50; mm += 5) {
    const double d = mm / 1000.0;
    for (int s = 0; s < 8; ++s)
      for (int k = 0; k < 6; ++k)
        o << d << ',' << s << ',' << std::lround(4095.0 * (200 * d * d - 30 * d + 1.1)) + (s + 1) * jitter[k] << '\n';
  }
  return o.str();
}

// Each sensor's reading noise is its own: per_sensor_sd[s] = 1.414 (s + 1) counts, by hand.
TEST_F(RoundSixteenCli, EachSensorsNoiseIsItsOwn) {
  const auto r = run("proximity \"" + write("p.csv", proximity_log_noisier_by_sensor()) + "\" -o " + q("p.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json n = json::parse(slurp(dir_ / "p.json")).at("noise").at("proximity");
  ASSERT_EQ(n.at("per_sensor_sd").size(), 8u) << n.dump();
  for (int s = 0; s < 8; ++s)
    EXPECT_NEAR(n.at("per_sensor_sd")[s].get<double>(), std::sqrt(2.0) * (s + 1), 1e-3) << "sensor " << s << ": " << n.dump();
}

// The drive's firmware-cap test writes both BICs it compared (docs/coefficient-files.md,
// `firmware_cap`): the JSON's bic_capped and bic_uncapped are the text report's "BIC X with the
// cap, Y without", and differ.
TEST_F(RoundSixteenCli, TheFirmwareCapsTwoBICsAreBothWritten) {
  const auto r = run("drive" + epuck2::testing::shipped_args("drive") + " -o " + q("d.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto t = run("drive" + epuck2::testing::shipped_args("drive"));
  const std::size_t at = t.out.find("firmware cap tested: BIC ");
  ASSERT_NE(at, std::string::npos) << t.out;
  std::istringstream line(t.out.substr(at + 25));
  double with = 0, without = 0;
  std::string w1, w2, w3;
  line >> with >> w1 >> w2 >> w3 >> without;  // "X with the cap, Y without"
  ASSERT_EQ(w1 + " " + w2 + " " + w3, "with the cap,") << t.out.substr(at, 120);
  const json cap = json::parse(slurp(dir_ / "d.json")).at("firmware_cap");
  EXPECT_NEAR(cap.at("bic_capped").get<double>(), with, 0.1) << cap.dump();
  EXPECT_NEAR(cap.at("bic_uncapped").get<double>(), without, 0.1) << cap.dump();
  EXPECT_NE(cap.at("bic_capped").get<double>(), cap.at("bic_uncapped").get<double>()) << cap.dump();
}

// ---- the diagnosis ---------------------------------------------------------------------------

/// A ground log by hand: 11 greys, 3 sensors, 5 readings each, reading = 50 + 900 grey + a jitter
/// {-1, 0, 1, 0, -1}; `shift` counts added to every reading.
std::string ground_log(int shift) {
  const int jitter[5] = {-1, 0, 1, 0, -1};
  std::ostringstream o;
  o << "# robot: hand-made\ngrey,sensor,value\n";
  for (int g = 0; g <= 10; ++g)
    for (int s = 0; s < 3; ++s)
      for (int k = 0; k < 5; ++k) o << g / 10.0 << ',' << s << ',' << 50 + 90 * g + jitter[k] + shift << '\n';
  return o.str();
}

// docs/diagnose.md, residual structure: `log` (which file) is scored when there are several, as
// from two on. Two logs, the second 40 counts higher: the structure names `log` among its columns.
TEST_F(RoundSixteenCli, TwoLogsAreEnoughForTheLogCovariate) {
  const std::string a = write("a.csv", ground_log(0));
  const std::string b = write("b.csv", ground_log(40));
  const auto r = run("diagnose \"" + a + "\" \"" + b + "\" -o " + q("d.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = slurp(dir_ / "d.json");
  const json j = json::parse(text);
  const std::string before = j.at("residual_structure_before").dump();
  EXPECT_NE(before.find("\"log\""), std::string::npos) << before;
  const auto one = run("diagnose \"" + a + "\" -o " + q("one.json"));
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_EQ(json::parse(slurp(dir_ / "one.json")).at("residual_structure_before").dump().find("\"log\""), std::string::npos);
}

// ---- apps ------------------------------------------------------------------------------------

// `nist` runs the StRD problems in NIST's own order (lower, average, higher difficulty, as the
// StRD lists them), each problem's runs together.
TEST_F(RoundSixteenCli, NistRunsTheProblemsInNistsOrder) {
  const std::vector<std::string> nist_order{"Misra1a", "Chwirut2", "Chwirut1", "Lanczos3", "Gauss1",  "Gauss2",
                                            "DanWood", "Misra1b",  "Kirby2",   "Hahn1",    "Nelson",  "MGH17",
                                            "Lanczos1", "Lanczos2", "Gauss3",  "Misra1c",  "Misra1d", "Roszman1",
                                            "ENSO",    "MGH09",    "Thurber",  "BoxBOD",   "Rat42",   "MGH10",
                                            "Eckerle4", "Rat43",   "Bennett5"};
  const auto r = run("nist \"" + (fs::path(EPUCK2_SOURCE_DIR) / "tests" / "data" / "nist").string() + "\" --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::vector<std::string> seen;
  const json report = json::parse(r.out);
  for (const json& one : report.at("runs")) {
    const std::string p = one.at("problem");
    if (seen.empty() || seen.back() != p) seen.push_back(p);
  }
  ASSERT_GE(seen.size(), 20u);
  std::size_t last = 0;
  for (std::size_t i = 0; i < seen.size(); ++i) {
    const auto at = std::find(nist_order.begin(), nist_order.end(), seen[i]);
    ASSERT_NE(at, nist_order.end()) << seen[i];
    const auto rank = static_cast<std::size_t>(at - nist_order.begin());
    if (i > 0) EXPECT_GT(rank, last) << seen[i] << " after " << seen[i - 1];
    last = rank;
  }
  EXPECT_EQ(seen.front(), "Misra1a");
}

// A misspelt name two edits from the word it meant, when the word is longer than four letters:
// "lig" is 2 insertions from "light" (2 x 2 = 4 < 5 letters), so the error says did you mean it.
TEST_F(RoundSixteenCli, AShortMisspellingStillGetsItsDidYouMean) {
  const auto r = run("diagnose --kind lig x.csv");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("did you mean 'light'?"), std::string::npos) << r.err;
  const auto g = run("generate grnd --out-dir " + q("g"));
  EXPECT_EQ(g.exit_code, 2) << g.err;
  EXPECT_NE(g.err.find("did you mean 'ground'?"), std::string::npos) << g.err;
}

// docs/cli.md: `-o -` with standard output closed is exit 2 with "standard output is not open"
// (not a descriptor number).
TEST_F(RoundSixteenCli, AClosedStandardOutputIsCalledSo) {
  const std::string log = epuck2::testing::shipped_logs("ground").front().string();
  const std::string cmd = "\"" EPUCK2_FIT_EXE "\" ground \"" + log + "\" -o - >&- 2>" + q("err.txt");
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
  const std::string err = slurp(dir_ / "err.txt");
  EXPECT_NE(err.find("standard output is not open"), std::string::npos) << err;
  EXPECT_EQ(err.find("file descriptor 1"), std::string::npos) << err;
}

}  // namespace test_round_sixteen_cpp
