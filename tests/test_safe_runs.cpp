// Crashes and unsafe writes found by fuzzing, at the library level: summarize with no estimable
// column, a battery step of no length, simulation tick and length, and the output stage (all or
// nothing, signals, stale temporaries, modes, symlinks).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "app_support.hpp"
#include "commands.hpp"
#include "epuck2/fit/problem.hpp"
#include "epuck2/logs/output.hpp"
#include "epuck2/models/battery.hpp"
#include "epuck2/models/battery_simulation.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"

namespace fs = std::filesystem;
namespace mb = epuck2::models::battery;
namespace lg = epuck2::logs;

namespace {

// r_i = y_i - a: the residuals do not depend on b at all.
struct IgnoresSecondParameter {
  std::vector<double> y;
  bool operator()(double const* const* p, double* r, double** jac) const {
    for (std::size_t i = 0; i < y.size(); ++i) r[i] = y[i] - p[0][0];
    if (jac) {
      if (jac[0]) for (std::size_t i = 0; i < y.size(); ++i) jac[0][i] = -1.0;
      if (jac[1]) for (std::size_t i = 0; i < y.size(); ++i) jac[1][i] = 0.0;
    }
    return true;
  }
};

// The residuals of IgnoresSecondParameter as the engine's residual block (over a and b); with
// `first_free_too` false, a has no effect either.
epuck2::fit::ResidualBlock zero_column_block(std::vector<double> y, bool first_free_too) {
  epuck2::fit::ResidualBlock block;
  block.residuals = static_cast<int>(y.size());
  block.sizes = {1, 1};
  block.evaluate = [f = IgnoresSecondParameter{std::move(y)}, first_free_too](double const* const* p, double* r, double** jac) {
    if (!f(p, r, jac)) return false;
    if (!first_free_too && jac && jac[0]) for (std::size_t i = 0; i < f.y.size(); ++i) jac[0][i] = 0.0;
    if (!first_free_too) for (std::size_t i = 0; i < f.y.size(); ++i) r[i] = f.y[i];
    return true;
  };
  return block;
}

epuck2::fit::FitResult fit_zero_column(bool a_matters) {
  double a = 1.0, b = 2.0;
  epuck2::fit::Problem problem;
  problem.add(zero_column_block({4.0, 3.5, 3.8, 3.9}, a_matters), {&a, &b});
  epuck2::fit::FitOptions options;
  const auto summary = problem.solve(options);
  return problem.summarize(epuck2::fit::ParameterLayout{{&a, &b}, {1, 1}, {"a", "b"}}, {4.0, 3.5, 3.8, 3.9}, summary, options);
}

}  // namespace

// fuzz report 1: every free column zero used to run a QR on a matrix with no columns (SIGSEGV).
TEST(SafeSummarize, NoEstimableColumnGivesNaNStandardErrorsWithAReason) {
  const auto r = fit_zero_column(false);
  ASSERT_EQ(r.parameters.size(), 2u);
  for (const auto& p : r.parameters) {
    EXPECT_TRUE(std::isnan(p.std_error)) << p.name;
    EXPECT_NE(p.std_error_why.find("not identifiable"), std::string::npos) << p.name << ": " << p.std_error_why;
  }
}

TEST(SafeSummarize, AZeroColumnBesideADeterminedOneIsReportedNotIdentifiable) {
  const auto r = fit_zero_column(true);
  // a is the mean of the four values, its standard error the sample sd / sqrt(4).
  const double mean = (4.0 + 3.5 + 3.8 + 3.9) / 4;
  double ss = 0;
  for (double v : {4.0, 3.5, 3.8, 3.9}) ss += (v - mean) * (v - mean);
  EXPECT_NEAR(r.value("a"), mean, 1e-9);
  EXPECT_NEAR(r.std_error("a"), std::sqrt(ss / 3 / 4), 1e-9);
  EXPECT_TRUE(r.parameters[0].std_error_why.empty());
  EXPECT_TRUE(std::isnan(r.std_error("b")));
  EXPECT_NE(r.parameters[1].std_error_why.find("b"), std::string::npos);
}

// fuzz report 2: a repeated time stamp is a step of dt = 0; its speed was 0/0 and
// static_cast<int>(floor(NaN)) indexed a speed table.
TEST(SafeBatteryStep, AStepOfNoLengthKeepsTheChargeInEveryModelAndBehaviour) {
  const mb::Tables& t = mb::plugin_tables();
  EXPECT_EQ(mb::plugin_speed_cm_s(0.0, 0.0), 0.0);
  EXPECT_EQ(mb::exact_speed_cm_s(0.0, 0.0), 0.0);
  for (mb::Model m : mb::kAllModels)
    for (mb::Behaviour b : {mb::Behaviour::argos_compatible, mb::Behaviour::corrected})
      for (double charge : {1.0, 0.7, 0.05}) {
        EXPECT_EQ(mb::step(m, b, t, charge, 0.0, 0.0), charge) << mb::to_string(m) << " " << static_cast<int>(b);
        mb::corrected::CubicHints hints;
        EXPECT_EQ(mb::step(m, b, t, charge, 0.0, 0.0, hints), charge) << mb::to_string(m);
      }
}

// fuzz report 6: the tick count was cast from a double out of size_t's range (dt = 1e-300, inf),
// and memory was reserved for the profile's end rather than the battery's life.
TEST(SafeSimulation, RejectsATickThatIsNotAFinitePositiveNumber) {
  const std::vector<mb::ProfilePoint> profile{{0.0, 5.0}, {100.0, 5.0}};
  for (double dt : {0.0, -0.1, std::numeric_limits<double>::infinity(), std::nan(""), 1e-300})
    EXPECT_THROW(mb::simulate_discharge(mb::Model::cubic, mb::Behaviour::corrected, mb::plugin_tables(), profile, dt),
                 std::invalid_argument)
        << dt;
}

TEST(SafeSimulation, AProfileEndingFarBeyondTheBatterysLifeStopsAtEmptyWithoutReservingForTheEnd) {
  const std::vector<mb::ProfilePoint> profile{{0.0, 5.0}, {1e9, 5.0}};  // 1e10 ticks: 160 GB if reserved
  const auto s = mb::simulate_discharge(mb::Model::linear, mb::Behaviour::corrected, mb::plugin_tables(), profile, 0.1);
  ASSERT_GT(s.size(), 2u);
  EXPECT_EQ(s.back().charge, 0.0);
  // The plug-in's tables empty the battery within a day at any speed.
  EXPECT_LT(s.back().time_s, 86400.0);
  EXPECT_LT(s.capacity(), 2 * s.size() + mb::kReservedSamples);
}

// ---- the output stage (fuzz report 3 and 4) ----

class Stage : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("epuck2_stage_" + std::to_string(::getpid()) + "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  static std::string read(const std::string& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  static void put(const std::string& p, const std::string& text) { std::ofstream(p) << text; }
  std::vector<std::string> hidden() const {
    std::vector<std::string> h;
    for (const auto& e : fs::directory_iterator(dir_))
      if (e.path().filename().string()[0] == '.') h.push_back(e.path().filename().string());
    return h;
  }
  fs::path dir_;
};

TEST_F(Stage, NothingIsReplacedUntilCommitAndEverythingAfter) {
  put(path("a.json"), "old a");
  put(path("b.png"), "old b");
  lg::OutputStage stage;
  stage.write(path("a.json"), "new a");
  stage.write(path("b.png"), "new b");
  EXPECT_EQ(read(path("a.json")), "old a");
  EXPECT_EQ(read(path("b.png")), "old b");
  EXPECT_EQ(hidden().size(), 2u);
  stage.commit();
  EXPECT_EQ(read(path("a.json")), "new a");
  EXPECT_EQ(read(path("b.png")), "new b");
  EXPECT_TRUE(hidden().empty());
}

TEST_F(Stage, AFailureLeavesEveryTargetAsItWasAndNoTemporary) {
  put(path("a.json"), "old a");
  {
    lg::OutputStage stage;
    stage.write(path("a.json"), "new a");
    EXPECT_THROW(stage.write((dir_ / "missing" / "x.png").string(), "png"), std::runtime_error);
  }  // not committed: the destructor removes the staged temporary
  EXPECT_EQ(read(path("a.json")), "old a");
  EXPECT_TRUE(hidden().empty());
}

TEST_F(Stage, TemporariesAreNamedForTheTargetAndTheProcess) {
  lg::OutputStage stage;
  const std::string tmp = stage.reserve(path("fig.png"));
  EXPECT_EQ(fs::path(tmp).filename().string(), ".fig.png.epuck2-tmp." + std::to_string(::getpid()));
  EXPECT_EQ(tmp, lg::temporary_name_for(path("fig.png"), ::getpid()));
}

TEST_F(Stage, AReplacedFileKeepsItsMode) {
  put(path("secret.json"), "old");
  ASSERT_EQ(::chmod(path("secret.json").c_str(), 0600), 0);
  lg::write_file_atomically(path("secret.json"), "new");
  struct stat st {};
  ASSERT_EQ(::stat(path("secret.json").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 07777, 0600u);
  EXPECT_EQ(read(path("secret.json")), "new");
}

TEST_F(Stage, ASymlinkedTargetIsFollowedAndTheLinkStays) {
  fs::create_directories(dir_ / "real");
  put((dir_ / "real" / "out.json").string(), "old");
  fs::create_symlink(fs::path("real") / "out.json", dir_ / "link.json");  // relative link
  lg::write_file_atomically(path("link.json"), "new");
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.json"));
  EXPECT_EQ(read((dir_ / "real" / "out.json").string()), "new");
  EXPECT_TRUE(hidden().empty());
  for (const auto& e : fs::directory_iterator(dir_ / "real")) EXPECT_EQ(e.path().filename(), "out.json");
}

TEST_F(Stage, AStaleTemporaryOfADeadProcessIsSweptOnTheNextWrite) {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ASSERT_EQ(::waitpid(child, nullptr, 0), child);  // its PID now names no process
  const std::string stale = lg::temporary_name_for(path("out.json"), child);
  put(stale, "half written");
  const std::string alive = lg::temporary_name_for(path("out.json"), ::getppid());  // a running process's
  put(alive, "being written");
  lg::write_file_atomically(path("out.json"), "new");
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(alive));
  EXPECT_EQ(read(path("out.json")), "new");
}

TEST_F(Stage, TheSameFileForTwoOutputsIsRefused) {
  lg::OutputStage stage;
  stage.write(path("x.json"), "1");
  EXPECT_THROW(stage.write(path("x.json"), "2"), std::runtime_error);
}

TEST_F(Stage, SigtermAndSigintRemoveTheTemporariesThenEndTheProcessBySignal) {
  for (int sig : {SIGTERM, SIGINT}) {
    const std::string target = path("sig" + std::to_string(sig) + ".json");
    put(target, "old");
    const pid_t child = ::fork();
    if (child == 0) {
      lg::OutputStage stage;
      stage.write(target, "new");
      stage.reserve(path("fig" + std::to_string(sig) + ".png"));
      ::raise(sig);
      ::_exit(3);  // not reached
    }
    ASSERT_GT(child, 0);
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << status;
    EXPECT_EQ(read(target), "old");
    EXPECT_TRUE(hidden().empty()) << hidden().front();
  }
}

// ---- the apps' JSON writer and option checks (apps/app_support.cpp, through the library the CLI links) ----

// fuzz report 7: a NaN left in a result used to be written as a bare null (nlohmann's dump).
TEST(SafeJson, ANaNOrInfinityAnywhereIsRefusedNamingWhereItIs) {
  nlohmann::json j;
  j["kind"] = "camera";
  j["std_errors"]["fov_deg"] = std::nan("");
  try {
    (void)epuck2::app::json_text(j);
    FAIL() << "a NaN was accepted";
  } catch (const epuck2::app::NoUsableFit& e) {
    EXPECT_NE(std::string(e.what()).find("std_errors.fov_deg"), std::string::npos) << e.what();
  }
  nlohmann::json a;
  a["speeds"] = nlohmann::json::array({nlohmann::json{{"cubic", {1.0, std::numeric_limits<double>::infinity()}}}});
  EXPECT_THROW((void)epuck2::app::json_text(a), epuck2::app::NoUsableFit);
  nlohmann::json ok;
  ok["std_errors"]["fov_deg"] = nullptr;
  ok["std_error_why"]["fov_deg"] = "not identifiable";
  EXPECT_EQ(epuck2::app::json_text(ok), ok.dump(2) + "\n");
}

TEST(SafeOptions, FiniteRangeRefusesNaNInfinityAndOutOfRangeNaming) {
  const CLI::Validator v = epuck2::app::finite_range(1e-3, 10.0);
  for (std::string bad : {"nan", "inf", "-inf", "0", "1e-300", "11", "abc", ""}) {
    std::string in = bad;
    EXPECT_FALSE(v(in).empty()) << bad;
  }
  for (std::string good : {"0.001", "0.1", "10"}) {
    std::string in = good;
    EXPECT_TRUE(v(in).empty()) << good;
  }
  const CLI::Validator w = epuck2::app::whole_number();
  for (std::string bad : {"-1", "1.5", "abc", "", "18446744073709551616"}) {
    std::string in = bad;
    EXPECT_FALSE(w(in).empty()) << bad;
  }
  std::string max = "18446744073709551615";
  EXPECT_TRUE(w(max).empty());
}
