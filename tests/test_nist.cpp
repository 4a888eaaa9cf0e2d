// The fitting engine against the NIST StRD nonlinear regression problems: every problem from both
// starting points, counted in digits (log relative error) against the certified values, as Ceres'
// examples/nist.cc and McCullough (1998) do.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "epuck2/nist/nist.hpp"
#include "epuck2/fit/fit_curve.hpp"
#include "epuck2/logs/log.hpp"

// This file's `using namespace` stays in its own named namespace, so it opens nothing to the
// files compiled after it in the same unity unit (tests/CMakeLists.txt).
namespace test_nist_cpp {
namespace {

using namespace epuck2::fit;
namespace nist = epuck2::nist;

const std::string kNistDir = std::string(EPUCK2_SOURCE_DIR) + "/tests/data/nist";

// Runs that are allowed to miss the target, each with its reason. None today: every one of the
// 54 runs meets it. An entry here must still fail (the test below checks), so a stale exception
// cannot hide.
const std::map<std::string, std::string> kExceptions = {};

struct NistCase {
  std::string problem;
  int start;
};

std::vector<NistCase> all_runs() {
  std::vector<NistCase> runs;
  for (const auto& name : nist::problem_names())
    for (int start : {1, 2}) runs.push_back({name, start});
  return runs;
}

std::string run_name(const NistCase& r) { return r.problem + "_start" + std::to_string(r.start); }

class NistRun : public ::testing::TestWithParam<NistCase> {};

TEST_P(NistRun, MeetsTarget) {
  const NistCase& run = GetParam();
  const nist::Problem problem = nist::read(kNistDir + "/" + run.problem + ".dat");
  const nist::Target target;  // parameter LRE >= 6, standard-error LRE >= 4
  const nist::RunReport r = nist::run(problem, run.start, nist::default_options(), target);
  std::ostringstream detail;
  for (const auto& p : r.parameters)
    detail << p.name << ": " << p.value << " (LRE " << p.lre << "), se " << p.std_error << " (LRE " << p.std_error_lre
           << ")\n";
  const auto exception = kExceptions.find(run_name(run));
  if (exception != kExceptions.end()) {
    EXPECT_FALSE(r.at_target) << "listed as an exception (" << exception->second << ") but meets the target now";
    return;
  }
  ASSERT_TRUE(r.usable) << r.message;
  EXPECT_GE(r.min_lre, target.parameter_lre) << detail.str();
  EXPECT_GE(r.min_std_error_lre, target.std_error_lre) << detail.str();
  EXPECT_TRUE(r.at_target);
  EXPECT_EQ(r.parameters.size(), problem.parameters.size());
}

INSTANTIATE_TEST_SUITE_P(StRD, NistRun, ::testing::ValuesIn(all_runs()),
                         [](const ::testing::TestParamInfo<NistCase>& info) { return run_name(info.param); });

TEST(NistFiles, AllProblemsPresentAndParsed) {
  ASSERT_EQ(nist::problem_names().size(), 27u);
  for (const auto& name : nist::problem_names()) {
    const nist::Problem p = nist::read(kNistDir + "/" + name + ".dat");
    EXPECT_EQ(p.y.size(), p.certified_observations) << name;
    EXPECT_FALSE(p.parameters.empty()) << name;
    EXPECT_GT(p.certified_rss, 0.0) << name;
  }
  // Spot checks against the text of the files.
  const nist::Problem misra = nist::read(kNistDir + "/Misra1a.dat");
  ASSERT_EQ(misra.parameters.size(), 2u);
  EXPECT_EQ(misra.parameters[0].start1, 500.0);
  EXPECT_EQ(misra.parameters[1].start2, 0.0005);
  EXPECT_EQ(misra.parameters[0].certified, 2.3894212918E+02);
  EXPECT_EQ(misra.parameters[1].certified_sd, 7.2668688436E-06);
  EXPECT_EQ(misra.certified_rss, 1.2455138894E-01);
  EXPECT_EQ(misra.y.front(), 10.07);
  EXPECT_EQ(misra.x[0].back(), 760.0);
  const nist::Problem nelson = nist::read(kNistDir + "/Nelson.dat");
  ASSERT_EQ(nelson.x.size(), 2u);
  EXPECT_EQ(nelson.y.size(), 128u);
}

TEST(LogRelativeError, CountsDigits) {
  EXPECT_NEAR(nist::log_relative_error(1.0001, 1.0), 4.0, 1e-9);
  EXPECT_NEAR(nist::log_relative_error(-2.0002, -2.0), 4.0, 1e-9);
  EXPECT_NEAR(nist::log_relative_error(123.4567, 123.4568), -std::log10(1e-4 / 123.4568), 1e-9);
  // Capped at the certified digits; an exact match gives the cap.
  EXPECT_EQ(nist::log_relative_error(5.0, 5.0), nist::kCertifiedDigits);
  EXPECT_EQ(nist::log_relative_error(5.0 + 1e-15, 5.0), nist::kCertifiedDigits);
  EXPECT_EQ(nist::log_relative_error(5.0, 5.0, 3.0), 3.0);
  // No digit in common: 0, never negative; NaN counts as none.
  EXPECT_EQ(nist::log_relative_error(300.0, 1.0), 0.0);
  EXPECT_EQ(nist::log_relative_error(std::nan(""), 1.0), 0.0);
  // A certified zero: the absolute error.
  EXPECT_NEAR(nist::log_relative_error(1e-7, 0.0), 7.0, 1e-9);
}

// A well-formed file to corrupt: the Misra1a text, written under its own name in a fresh folder.
class MalformedDat : public ::testing::Test {
 protected:
  void SetUp() override {
    std::ifstream in(kNistDir + "/Misra1a.dat", std::ios::binary);
    for (std::string line; std::getline(in, line);) lines_.push_back(line);
    ASSERT_EQ(lines_.size(), 74u);
  }
  std::string text() const {
    std::string t;
    for (const auto& l : lines_) t += l + "\n";
    return t;
  }
  std::vector<std::string> lines_;
};

void expect_input_error(const std::string& text, const std::string& path, int line, int column, const std::string& needle) {
  try {
    nist::parse(text, path);
    ADD_FAILURE() << "no error for " << needle;
  } catch (const epuck2::logs::InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.column(), column) << e.what();
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST_F(MalformedDat, GoodTextParses) { EXPECT_NO_THROW(nist::parse(text(), "dir/Misra1a.dat")); }

TEST_F(MalformedDat, BadNumberInData) {
  lines_[64] = "      14.73E0     1x4.9E0\r";  // line 65
  expect_input_error(text(), "dir/Misra1a.dat", 65, 19, "1x4.9E0");
}

TEST_F(MalformedDat, MissingColumnInData) {
  lines_[69] = "      40.02E0\r";  // line 70
  expect_input_error(text(), "dir/Misra1a.dat", 70, 14, "2 numbers");
}

TEST_F(MalformedDat, BadCertifiedValue) {
  lines_[41] = "  b2 =     0.0001      0.0005      5.5015643181E-0Q  7.2668688436E-06\r";  // line 42
  expect_input_error(text(), "dir/Misra1a.dat", 42, 36, "b2 certified value");
}

TEST_F(MalformedDat, MissingParameterLine) {
  lines_[41] = "\r";
  expect_input_error(text(), "dir/Misra1a.dat", 74, 1, "2 parameters");
}

TEST_F(MalformedDat, RowCountDisagrees) {
  lines_.pop_back();
  expect_input_error(text(), "dir/Misra1a.dat", 73, 1, "14 observations");
}

TEST_F(MalformedDat, UnknownProblemName) { expect_input_error(text(), "dir/Misra9z.dat", 1, 1, "unknown StRD problem"); }

// The options other callers get by default keep the single Levenberg-Marquardt solve: from
// BoxBOD's first start it stops on the saturated plateau, which the NIST options escape.
TEST(FitOptionsDefaults, SingleSolveUnchanged) {
  const nist::Problem p = nist::read(kNistDir + "/BoxBOD.dat");
  const nist::RunReport plain = nist::run(p, 1, FitOptions{});
  EXPECT_LT(plain.min_lre, 1.0);
  const nist::RunReport searched = nist::run(p, 1);
  EXPECT_TRUE(searched.at_target);
}

// The other strategies are spent only where the first one's solution fails its own checks. From
// MGH09's first start the first strategy (Levenberg-Marquardt, restarts) converges to the
// certified minimum, so the NIST options give the very fit that strategy alone gives, with the
// same iterations (none spent on the others). From BoxBOD's first start it stops on the
// saturated plateau (a parameter the residuals no longer depend on): the others run, and one
// reaches NIST's certified values.
TEST(FitOptionsAlternatives, OnlyWhenTheFirstSolutionFailsItsChecks) {
  FitOptions first_only = nist::default_options();
  first_only.try_alternatives = false;
  const nist::Problem mgh09 = nist::read(kNistDir + "/MGH09.dat");
  const FitResult searched = nist::fit(mgh09, 1);
  const FitResult first = nist::fit(mgh09, 1, first_only);
  ASSERT_TRUE(searched.usable && first.usable);
  EXPECT_EQ(searched.iterations, first.iterations);
  for (std::size_t j = 0; j < mgh09.parameters.size(); ++j) {
    EXPECT_EQ(searched.parameters[j].value, first.parameters[j].value) << mgh09.parameters[j].name;
    EXPECT_GE(nist::log_relative_error(searched.parameters[j].value, mgh09.parameters[j].certified), 6.0);
  }
  const nist::Problem boxbod = nist::read(kNistDir + "/BoxBOD.dat");
  const FitResult escalated = nist::fit(boxbod, 1);
  const FitResult stuck = nist::fit(boxbod, 1, first_only);
  EXPECT_GT(escalated.iterations, stuck.iterations);
  EXPECT_LT(nist::log_relative_error(stuck.parameters[1].value, boxbod.parameters[1].certified), 1.0);
  for (std::size_t j = 0; j < boxbod.parameters.size(); ++j)
    EXPECT_GE(nist::log_relative_error(escalated.parameters[j].value, boxbod.parameters[j].certified), 6.0);
}

// One residual block for all rows (the default) is the same least-squares problem as one block
// per row: the same minimum, the same standard errors (to the digits the 1e-15 tolerances leave).
TEST(FitOptionsSingleBlock, SameFitAsOneBlockPerRow) {
  constexpr double kDigits = 9.0;
  const nist::Problem p = nist::read(kNistDir + "/Misra1a.dat");
  const std::vector<std::string> names{"b1", "b2"};
  FitOptions block;
  block.single_residual_block = true;
  FitOptions per_row;
  per_row.single_residual_block = false;
  for (int start : {1, 2}) {
    const std::vector<double> b0{start == 1 ? p.parameters[0].start1 : p.parameters[0].start2,
                                 start == 1 ? p.parameters[1].start1 : p.parameters[1].start2};
    const FitResult a = fit_curve(nist::models::Misra1a{}, p.x[0], p.y, free_parameters(names, b0), per_row);
    const FitResult b = fit_curve(nist::models::Misra1a{}, p.x[0], p.y, free_parameters(names, b0), block);
    ASSERT_TRUE(a.usable && b.usable);
    for (std::size_t j = 0; j < 2; ++j) {
      EXPECT_GE(nist::log_relative_error(b.parameters[j].value, a.parameters[j].value), kDigits);
      EXPECT_GE(nist::log_relative_error(b.parameters[j].std_error, a.parameters[j].std_error), kDigits);
      EXPECT_GE(nist::log_relative_error(b.parameters[j].value, p.parameters[j].certified), 6.0);
    }
    EXPECT_GE(nist::log_relative_error(b.rss, a.rss), kDigits);
  }
}

std::string run_command(const std::string& cmd, int* status) {
  std::string out;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return out;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), static_cast<int>(buf.size()), pipe)) out += buf.data();
  *status = pclose(pipe);
  return out;
}

TEST(NistCli, ReportsAllRuns) {
  int status = -1;
  const std::string out = run_command(std::string(EPUCK2_FIT_EXE) + " nist " + kNistDir + " 2>/dev/null", &status);
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_NE(out.find("54/54 runs at target"), std::string::npos) << out;
  EXPECT_NE(out.find("Bennett5"), std::string::npos);
}

TEST(NistCli, MalformedFileExitsTwoWithPosition) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "epuck2_test_nist_malformed";
  fs::create_directories(dir);
  {
    std::ifstream in(kNistDir + "/Misra1a.dat", std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    std::string t = ss.str();
    const std::string good = "      10.07E0      77.6E0";
    t.replace(t.find(good), good.size(), "      10.07E0      77.6E0   9");
    std::ofstream(dir / "Misra1a.dat", std::ios::binary) << t;
  }
  int status = -1;
  const std::string out = run_command(std::string(EPUCK2_FIT_EXE) + " nist " + dir.string() + " 2>&1", &status);
  EXPECT_EQ(WEXITSTATUS(status), 2) << out;
  EXPECT_NE(out.find("Misra1a.dat:61:29"), std::string::npos) << out;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace test_nist_cpp
