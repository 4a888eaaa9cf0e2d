// Nothing lost in silence (issue #22): every command checks that what it printed reached standard
// output, no writer puts a NaN or an infinity into a log, the log reader refuses conditions the
// models cannot simulate (with their location), and `--effects` takes exactly one list. Through the
// real binary, since the defects were in the command line.
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/types.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/logs/output.hpp"

namespace {

using epuck2::testing::CliRun;
using epuck2::testing::CliTest;
using epuck2::testing::slurp;
namespace fs = std::filesystem;

std::string q_checked(const std::string& s) { return "\"" + s + "\""; }
std::string src(const std::string& rel) { return q_checked(std::string(EPUCK2_SOURCE_DIR) + "/" + rel); }

class CheckedOutputs : public CliTest {
 protected:
  /// Runs `epuck2-fit ARGS > STDOUT_TARGET` (e.g. /dev/full), standard error captured.
  CliRun run_to(const std::string& args, const std::string& stdout_target) {
    const fs::path err = dir_ / "stderr.txt";
    const std::string cmd = "\"" + std::string(EPUCK2_FIT_EXE) + "\" " + args + " >" + stdout_target + " 2>" + q_checked(err.string());
    const int status = std::system(cmd.c_str());
    CliRun r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.err = slurp(err);
    return r;
  }
  static bool has_dev_full() { return fs::exists("/dev/full"); }
  /// The first `lines` lines of a shipped file (a short log: every run stays quick).
  static std::string head_of(const std::string& rel, int lines) {
    std::istringstream in(slurp(fs::path(EPUCK2_SOURCE_DIR) / rel));
    std::string line, out;
    for (int i = 0; i < lines && std::getline(in, line); ++i) out += line + "\n";
    return out;
  }
};

// ----- 1. standard output is checked -------------------------------------------------------------

// Each of these prints its result on standard output; to a file it succeeds (exit 0, something
// written), to /dev/full (every write fails with ENOSPC) it must say so and exit 2. The list
// holds small outputs (lost at the final flush) and large ones (lost mid-run, more than stdio's
// buffer: the help, the simulated profile, the JSON report).
TEST_F(CheckedOutputs, EveryCommandThatPrintsFailsOnAFullStandardOutput) {
  if (!has_dev_full()) GTEST_SKIP() << "no /dev/full";
  const std::string profile = write("profile.csv", "time_s,speed_cm_s\n0,7\n3600,3\n");
  const std::string ground_head = write("ground.csv", head_of("data/raw/ground/ground_virtual-epuck2-1.csv", 200));
  const std::vector<std::string> commands = {
      "--help",
      "--version",
      "help diagnose",
      "proximity" + shipped("proximity") + " --json",
      "light" + shipped("light", "light_intensity_0.50.csv"),
      "camera" + shipped("camera", "camera_virtual-epuck2-1"),
      "battery" + shipped("battery", "robot-a_speed-07") + " --json",
      "simulate battery --model cubic --profile " + q_checked(profile),
      "simulate light --like " + src("data/raw/light/light_intensity_0.50.csv"),
      "table5" + shipped("battery", "robot-a_"),
      "diagnose --json " + q_checked(ground_head),
  };
  for (const std::string& c : commands) {
    SCOPED_TRACE(c);
    const CliRun ok = run(c);
    ASSERT_EQ(ok.exit_code, 0) << ok.err;
    ASSERT_FALSE(ok.out.empty());
    const CliRun full = run_to(c, "/dev/full");
    EXPECT_EQ(full.exit_code, 2) << full.err;
    EXPECT_NE(full.err.find("error: standard output: No space left on device"), std::string::npos) << full.err;
  }
}

// The output that did get through is whole: to a pipe that reads everything, the bytes equal the
// file's (the checked stream changes nothing on success), and printf's and std::cout's text keep
// their order (the battery report uses both).
TEST_F(CheckedOutputs, TheCheckedStreamWritesTheSameBytesInOrder) {
  const std::string args = "battery" + shipped("battery", "robot-a_speed-07");
  const CliRun file = run(args);
  ASSERT_EQ(file.exit_code, 0) << file.err;
  const fs::path piped = dir_ / "piped.txt";
  const int status = std::system(("\"" + std::string(EPUCK2_FIT_EXE) + "\" " + args + " 2>/dev/null | cat > " + q_checked(piped.string())).c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_EQ(slurp(piped), file.out);
  EXPECT_EQ(file.out.rfind("Battery discharge fits", 0), 0u) << file.out.substr(0, 200);
}

// An error that exits 2 anyway still says it, once, and the first error stays the reason.
TEST_F(CheckedOutputs, ABadInputIsReportedBeforeTheLostOutput) {
  if (!has_dev_full()) GTEST_SKIP() << "no /dev/full";
  const std::string bad = write("bad.csv", "distance_m,sensor,value\n0.01,0,abc\n");
  const CliRun r = run_to("proximity " + q_checked(bad), "/dev/full");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad.csv:2:"), std::string::npos) << r.err;
}

// ----- 3. no NaN in any output --------------------------------------------------------------------

// Conditions that made `simulate --like` write -nan with exit 0: refused when the log is read,
// with the file, the line and the column of the cell, and no output file.
TEST_F(CheckedOutputs, SimulateLikeRefusesConditionsTheModelCannotTake) {
  struct Case {
    const char* kind;
    std::string log;
    std::string where;  // file:line:column of the bad cell
    std::string column;
  };
  const std::vector<Case> cases = {
      {"camera", "forward_m,lateral_m,vertical_m,px,py\n0.2,0.01,0,70,60\n0.2,1e300,0,70,60\n", ":3:5:", "lateral_m"},
      {"camera", "forward_m,lateral_m,vertical_m,px,py\n0.2,0.01,-1e300,70,60\n", ":2:10:", "vertical_m"},
      {"camera", "forward_m,lateral_m,vertical_m,px,py\n0.2,0.01,1000.5,70,60\n", ":2:10:", "vertical_m"},
      {"light", "distance_m,intensity,sensor,value\n0.1,1,0,3000\n1e-320,1,3,3000\n", ":3:1:", "distance_m"},
      {"light", "distance_m,intensity,sensor,value\n0,1,0,3000\n", ":2:1:", "distance_m"},
      {"light", "distance_m,intensity,sensor,value\n0.0009,1,0,3000\n", ":2:1:", "distance_m"},
  };
  int i = 0;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.log);
    const std::string name = "cond" + std::to_string(i++) + ".csv";
    const std::string log = write(name, c.log);
    const fs::path out = dir_ / ("sim_" + name);
    const CliRun r = run(std::string("simulate ") + c.kind + " --like " + q_checked(log) + " -o " + q_checked(out.string()));
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find(name + c.where), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("column '" + c.column + "'"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
}

// The edges of the new ranges are accepted (0.001 m from a light, an LED 1000 m to the side) and
// simulate to finite readings. (A light farther than 5 m is refused as a unit mistake by the
// plausibility check, docs/fitting.md: the far point is 4.5 m, beyond the 0.5 m range.)
TEST_F(CheckedOutputs, TheEdgesOfTheRangesAreAcceptedAndSimulateFinite) {
  const std::string light = write("light.csv", "distance_m,intensity,sensor,value\n0.001,1,0,3000\n4.5,1e6,7,3000\n");
  CliRun r = run("simulate light --like " + q_checked(light));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // 0.001 m from an intensity-1 source saturates the sensor: the plug-in's model reads 0 there;
  // 4.5 m is beyond its 0.5 m range: dark, 4095.
  EXPECT_NE(r.out.find("\n0.001,1,0,0\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\n4.5,1e+06,7,4095\n"), std::string::npos) << r.out;
  // The LED 1000 m to the side and 1000 m up is read (in range), and falls far off the image: not
  // seen, so left out (the LED on the axis stays).
  const std::string camera = write("camera.csv", "forward_m,lateral_m,vertical_m,px,py\n0.2,-1000,1000,70,60\n0.2,0,0,70,60\n");
  r = run("simulate camera --like " + q_checked(camera));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("inf"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("-1000"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\n0.2,0,0,80,60\n"), std::string::npos) << r.out;
}

// A drive log's obstacle at 1e300 m was taken; it is refused at the metadata line like a
// negative one, and 0 (documented in docs/logs.md) is accepted.
TEST_F(CheckedOutputs, ObstacleDistanceHasThePhysicalRangeOfADistance) {
  const std::string rows = "time_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n0,0,0,0,0,20\n0.1,5,5,0,0,20\n";
  const std::string far = write("far.csv", "# obstacle_distance_m: 1e300\n" + rows);
  CliRun r = run("simulate drive --like " + q_checked(far));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("far.csv:1:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("<= 1000 m"), std::string::npos) << r.err;
  const std::string zero = write("zero.csv", "# obstacle_distance_m: 0\n" + rows);
  r = run("simulate drive --like " + q_checked(zero));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // At the obstacle the ToF reads its lower rail, 20 mm.
  EXPECT_NE(r.out.find("\n0,0,0,0,0,20\n"), std::string::npos) << r.out;
}

// A model whose arithmetic overflows on in-range conditions (a field of view of 4.9e-324 degrees,
// the smallest double: in radians it is 0, the focal length 80 / tan(0) infinite, and an LED on the
// axis gives inf * 0 = NaN): nothing is written, exit 2,
// and the error names a file (the log's row, or the coefficient file when its reader refuses it).
TEST_F(CheckedOutputs, SimulateLikeNeverWritesANonFiniteReading) {
  std::string model = slurp(fs::path(EPUCK2_SOURCE_DIR) / "data/fitted/camera.json");
  const std::string key = "\"fov_deg\": ";
  const std::size_t at = model.find(key, model.find("\"parameters\""));
  ASSERT_NE(at, std::string::npos);
  const std::size_t end = model.find_first_of(",\n}", at + key.size());
  model = model.substr(0, at + key.size()) + "4.9e-324" + model.substr(end);
  const std::string coefficients = write("camera_tiny_fov.json", model);
  const std::string log = write("axis.csv", "forward_m,lateral_m,vertical_m,px,py\n0.2,0,0,80,60\n");
  const fs::path out = dir_ / "sim.csv";
  const CliRun r = run("simulate camera --like " + q_checked(log) + " --coefficients " + q_checked(coefficients) + " -o " + q_checked(out.string()));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(r.err.find("axis.csv:2") != std::string::npos || r.err.find("camera_tiny_fov.json") != std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

// The writer itself refuses a non-finite value, naming the row and the column (every log the
// project writes goes through it: simulate, generate, the virtual robot).
TEST(LogWriterChecks, ANonFiniteValueIsNeverWritten) {
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity()}) {
    epuck2::logs::LogWriter w({"time_s", "charge"});
    w.row({0.0, 1.0});
    try {
      w.row({1.0, bad});
      FAIL() << "accepted " << bad;
    } catch (const std::domain_error& e) {
      EXPECT_NE(std::string(e.what()).find("row 2, column 'charge'"), std::string::npos) << e.what();
    }
    EXPECT_EQ(w.rows(), 1u);  // the bad row was not kept
  }
  epuck2::logs::LogWriter ok({"x"});
  ok.row({std::numeric_limits<double>::max()});
  ok.row({-std::numeric_limits<double>::denorm_min()});
  EXPECT_EQ(ok.str(), "x\n1.7976931348623157e+308\n-4.94066e-324\n");
}

// ----- 4. --effects takes one list ----------------------------------------------------------------

// `--effects ,` swallowed the following `-o FILE` as effect names; an empty list or an empty name
// is now a usage error naming the option, and -o is still -o.
TEST_F(CheckedOutputs, EffectsTakesExactlyOneList) {
  const std::string log = q_checked(write("ground.csv", head_of("data/raw/ground/ground_virtual-epuck2-1.csv", 200)));
  const fs::path out = dir_ / "d.json";
  for (const std::string list : {",", "\"\"", "black_offset,", ",black_offset", "black_offset,,white_level"}) {
    SCOPED_TRACE(list);
    const CliRun r = run("diagnose --effects " + list + " -o " + q_checked(out.string()) + " " + log);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("--effects"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("-o"), std::string::npos) << "-o was taken as an effect: " << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
  // One list is one value: the next word is a log, not another effect.
  const CliRun two = run("diagnose --effects black_offset " + log + " -o " + q_checked(out.string()));
  EXPECT_EQ(two.exit_code, 0) << two.err;
  EXPECT_TRUE(fs::exists(out));
}

// ----- -o onto what is not a regular file (issue #22 row 1b), -o - (row 1c) ----------------------

/// Runs a shell command line; its exit status (-1 when it did not exit).
int checked_outputs_sh(const std::string& cmd) {
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}
std::string checked_outputs_exe() { return q_checked(EPUCK2_FIT_EXE); }

// A FIFO with a reader gets the whole result and stays a FIFO. (The writer used to rename its
// temporary over it: exit 0, the FIFO replaced by a regular file, the reader left with nothing;
// `timeout` ends that reader.) The bytes are those the same run prints on standard output.
TEST_F(CheckedOutputs, AFifoGivenToOIsWrittenInPlace) {
  const std::string log = src("data/raw/ground/ground_virtual-epuck2-1.csv");
  const CliRun printed = run("simulate ground --like " + log);
  ASSERT_EQ(printed.exit_code, 0) << printed.err;
  ASSERT_GT(printed.out.size(), 1000u);
  const fs::path fifo = dir_ / "sim.fifo", got = dir_ / "got.csv", err = dir_ / "err.txt";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const int rc = checked_outputs_sh("timeout 20 cat " + q_checked(fifo.string()) + " > " + q_checked(got.string()) + " & reader=$!; " +
                                    checked_outputs_exe() + " simulate ground --like " + log + " -o " + q_checked(fifo.string()) +
                                    " 2> " + q_checked(err.string()) + "; rc=$?; wait $reader; exit $rc");
  EXPECT_EQ(rc, 0) << slurp(err);
  struct stat st {};
  ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode)) << "the FIFO was replaced";
  EXPECT_EQ(slurp(got), printed.out);
}

// A device node made in the test's folder (so that no real device is at risk): /dev/full's
// (1, 7) takes nothing, and the run says so with exit 2; /dev/null's (1, 3) takes everything,
// exit 0. Both stay devices. Making a node needs root (CAP_MKNOD): skipped otherwise.
TEST_F(CheckedOutputs, ADeviceGivenToOIsWrittenInPlaceAndChecked) {
  const fs::path full = dir_ / "full", null = dir_ / "null";
  if (::mknod(full.c_str(), S_IFCHR | 0666, makedev(1, 7)) != 0 || ::mknod(null.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0)
    GTEST_SKIP() << "cannot make device nodes here (mknod needs root): " << std::strerror(errno);
  const std::string model = src("data/fitted/ground.json");
  CliRun r = run("codegen " + model + " -o " + q_checked(full.string()));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("full: No space left on device"), std::string::npos) << r.err;
  r = run("codegen " + model + " -o " + q_checked(null.string()));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const std::string log = src("data/raw/ground/ground_virtual-epuck2-1.csv");
  r = run("simulate ground --like " + log + " -o " + q_checked(full.string()));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  for (const fs::path& node : {full, null}) {
    struct stat st {};
    ASSERT_EQ(::lstat(node.c_str(), &st), 0);
    EXPECT_TRUE(S_ISCHR(st.st_mode)) << node << " is no longer a device";
  }
  // Nothing left beside them (no temporary in the folder).
  for (const auto& e : fs::directory_iterator(dir_))
    EXPECT_EQ(e.path().filename().string().find(".epuck2-tmp."), std::string::npos) << e.path();
}

// `-o -` is standard output, alone: the file there and no report beside it, and no file named
// `-` in the working folder. `-o /dev/stdout` into a pipe is the same; a full standard output is
// exit 2 with the reason.
TEST_F(CheckedOutputs, ODashIsStandardOutputAlone) {
  const std::string model = src("data/fitted/ground.json");
  CliRun r = run("codegen " + model + " -o -", dir_.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("ground_model()"), std::string::npos) << r.out.substr(0, 300);
  EXPECT_FALSE(fs::exists(dir_ / "-"));
  // The sensor fit with --json and -o -: one JSON document (the same text, not twice).
  r = run("ground" + shipped("ground") + " --json -o -", dir_.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  nlohmann::json j;
  ASSERT_NO_THROW(j = nlohmann::json::parse(r.out)) << r.out.substr(0, 300);
  EXPECT_EQ(j.at("kind"), "ground");
  // diagnose -o -: the JSON report, without the human one after it.
  const std::string head = write("ground.csv", head_of("data/raw/ground/ground_virtual-epuck2-1.csv", 200));
  r = run("diagnose -o - " + q_checked(head), dir_.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_NO_THROW(j = nlohmann::json::parse(r.out)) << r.out.substr(0, 300);
  EXPECT_EQ(j.at("kind"), "ground");
  EXPECT_FALSE(fs::exists(dir_ / "-"));
  // -o /dev/stdout into a pipe.
  const fs::path piped = dir_ / "piped.hpp";
  ASSERT_EQ(checked_outputs_sh(checked_outputs_exe() + " codegen " + model + " -o /dev/stdout 2>/dev/null | cat > " + q_checked(piped.string())), 0);
  EXPECT_NE(slurp(piped).find("ground_model()"), std::string::npos);
  if (has_dev_full()) {
    r = run_to("codegen " + model + " -o -", "/dev/full");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("standard output: No space left on device"), std::string::npos) << r.err;
  }
}

// ----- simulate camera --like: an LED off the image is not seen (issue #22 row 3b) ----------------

// The plug-in's camera by hand: aperture 18.5 deg on the image diagonal (160 x 120, diagonal 200),
// so f = 80 / (0.8 tan 18.5 deg) = 298.87 px and px = 80 - f lateral/forward, py = 60 - f
// vertical/forward. At forward 0.5 m: lateral 0 gives (80, 60); lateral 0.1 gives
// 80 - 0.2 f = 20.23; lateral -0.15 gives 80 + 0.3 f = 169.66, off the image: ARGoS reports no
// blob, and the row is left out.
TEST_F(CheckedOutputs, SimulateCameraLeavesOutAnLedOffTheImage) {
  const double f = 80.0 / (0.8 * std::tan(18.5 * std::acos(-1.0) / 180.0));
  const std::string log = write("cam.csv", "forward_m,lateral_m,vertical_m,px,py\n0.5,0,0,80,60\n0.5,-0.15,0,150,60\n0.5,0.1,0,20,60\n");
  const fs::path out = dir_ / "sim.csv";
  const CliRun r = run("simulate camera --like " + q_checked(log) + " -o " + q_checked(out.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("1 of 3 rows left out"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("cam.csv:3"), std::string::npos) << r.err;
  const epuck2::logs::Log sim = epuck2::logs::read_log(out.string());  // the reader takes it
  ASSERT_EQ(sim.rows(), 2u);
  EXPECT_NEAR(sim.col("px")[0], 80.0, 1e-9);
  EXPECT_NEAR(sim.col("py")[0], 60.0, 1e-9);
  EXPECT_EQ(sim.col("lateral_m")[1], 0.1);
  EXPECT_NEAR(sim.col("px")[1], 80.0 - 0.2 * f, 1e-6);
  EXPECT_NEAR(80.0 + 0.3 * f, 169.66, 0.01);  // the row left out was indeed off the image
}

// The image's edge under a distortion, by hand: fov 90 deg, so f = 80 / tan 45 deg = 80 px, centre
// (80, 60); with distortion_k2 = 20 an LED at forward 1 m, lateral -0.25 m (r^2 = 1/16) is scaled
// by 1 + 20/256 = 1.078125: px = 80 + 20 x 1.078125 = 101.5625, seen. Lateral -0.9: r^4 = 0.6561,
// scale 14.122, px = 80 + 72 x 14.122 = 1096.8: off the image (the pinhole would put it at 152).
// Rounding decides at the edge (k2 = 0 in a second file): lateral -0.99 gives 159.2, reported as
// 159; -0.997 gives 159.76, which rounds to 160: not seen; 1.006 gives -0.48, reported as 0;
// 1.007 gives -0.56, which rounds to -1: not seen.
TEST_F(CheckedOutputs, SimulateCameraDecidesTheImageEdgeAsTheRoundingDoes) {
  const std::string distorted = write("k2.json", R"({"kind": "camera", "parameters": {"fov_deg": 90, "cx_px": 80, "cy_px": 60},
    "effects": {"distortion_k2": {"k2": 20}}})");
  const std::string plain = write("pinhole.json", R"({"kind": "camera", "parameters": {"fov_deg": 90, "cx_px": 80, "cy_px": 60}})");
  const std::string log = write("k2.csv", "forward_m,lateral_m,vertical_m,px,py\n1,-0.25,0,0,0\n1,-0.9,0,0,0\n");
  const fs::path out = dir_ / "k2_sim.csv";
  CliRun r = run("simulate camera --like " + q_checked(log) + " --coefficients " + q_checked(distorted) + " -o " + q_checked(out.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  epuck2::logs::Log sim = epuck2::logs::read_log(out.string());
  ASSERT_EQ(sim.rows(), 1u);
  EXPECT_NEAR(sim.col("px")[0], 101.5625, 1e-9);
  EXPECT_NEAR(sim.col("py")[0], 60.0, 1e-9);
  const std::string edge = write("edge.csv", "forward_m,lateral_m,vertical_m,px,py\n1,-0.99,0,0,0\n1,-0.997,0,0,0\n1,1.006,0,0,0\n1,1.007,0,0,0\n");
  r = run("simulate camera --like " + q_checked(edge) + " --coefficients " + q_checked(plain) + " -o " + q_checked(out.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("2 of 4 rows left out"), std::string::npos) << r.err;
  sim = epuck2::logs::read_log(out.string());
  ASSERT_EQ(sim.rows(), 2u);
  EXPECT_EQ(sim.col("lateral_m")[0], -0.99);
  EXPECT_EQ(sim.col("px")[0], 159.0);
  EXPECT_EQ(sim.col("lateral_m")[1], 1.006);
  EXPECT_EQ(sim.col("px")[1], 0.0);
  // With noise the register is judged (rounded, then inside or not): still only what reads back.
  r = run("simulate camera --like " + q_checked(edge) + " --coefficients " + q_checked(plain) + " --noise --seed 7 -o " + q_checked(out.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NO_THROW(epuck2::logs::read_log(out.string()));
  // Every LED off the image: nothing to write, exit 2 at the log's first data line.
  const std::string none = write("none.csv", "forward_m,lateral_m,vertical_m,px,py\n1,-0.9,0,0,0\n");
  const fs::path none_out = dir_ / "none_sim.csv";
  r = run("simulate camera --like " + q_checked(none) + " --coefficients " + q_checked(distorted) + " -o " + q_checked(none_out.string()));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("none.csv:2:"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(none_out));
}

// The shipped camera log under distortion_k2 = 15 (pushes 30 of its 405 LEDs past column 159):
// what simulate writes, `diagnose` reads (it refused px 165 before).
TEST_F(CheckedOutputs, DiagnoseReadsWhatSimulateCameraWrites) {
  std::string model = slurp(fs::path(EPUCK2_SOURCE_DIR) / "data/fitted/camera.json");
  nlohmann::json j = nlohmann::json::parse(model);
  j["effects"] = {{"distortion_k2", {{"k2", 15}}}};
  const std::string coefficients = write("camera_k2.json", j.dump(2));
  const fs::path out = dir_ / "sim.csv";
  CliRun r = run("simulate camera --like " + src("data/raw/camera/camera_virtual-epuck2-1.csv") + " --coefficients " +
                 q_checked(coefficients) + " -o " + q_checked(out.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("rows left out"), std::string::npos) << r.err;
  r = run("diagnose --kind camera --json " + q_checked(out.string()));
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// ----- range messages state both bounds (issue #22 row 3a) ------------------------------------------

TEST_F(CheckedOutputs, RangeMessagesStateBothBounds) {
  struct Case {
    const char* command;
    std::string log;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {"camera", "forward_m,lateral_m,vertical_m,px,py\n1e300,0,0,80,60\n", "expected a forward distance in (0, 1000] m"},
      {"light", "distance_m,intensity,sensor,value\n0.1,2e6,0,3000\n", "expected an intensity in [0, 1e6]"},
      {"battery", "time_s,speed_cm_s,charge\n0,5,1\n2e9,5,0.5\n", "expected a time in [0, 1e9] s"},
      {"battery", "time_s,speed_cm_s,charge\n0,5,1\n1,5000,0.5\n", "expected a speed in [-1000, 1000] cm/s"},
      {"battery", "time_s,speed_cm_s,charge\n0,5,1\n1,5,1.2\n", "expected a normalised charge in [-1, 1.05]"},
      {"proximity", "distance_m,sensor,value\n1e4,0,100\n", "expected a distance in [0, 1000] m"},
  };
  int i = 0;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.log);
    const std::string log = write("range" + std::to_string(i++) + ".csv", c.log);
    const CliRun r = run(std::string(c.command) + " " + q_checked(log));
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
  }
}

}  // namespace
