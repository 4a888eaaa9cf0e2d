// Round 17 of the fresh slips (bench/fresh-slips.md): a test for each behaviour its slips changed
// that no test had pinned down. Every expected value comes from the docs, from the logs the test
// writes (counted by the test itself), or is worked by hand in the comment beside it, never from
// the code under test. The two ARGoS slips are caught by argos/tests/ground_pose.sh and the turned
// runs of argos/tests/camera.sh.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/fit/fit_curve.hpp"
#include "epuck2/fit/parameter.hpp"
#include "epuck2/fit/problem.hpp"
#include "epuck2/fit/readings.hpp"
#include "epuck2/models/camera.hpp"

namespace test_round_seventeen_cpp {

namespace fs = std::filesystem;
using nlohmann::json;
namespace ef = epuck2::fit;
namespace ms = epuck2::models::sensors;

const double kPi = std::acos(-1.0);
double rad(double deg) { return deg * kPi / 180.0; }
double deg(double r) { return r * 180.0 / kPi; }

// ----- the camera's aperture (docs/coefficient-files.md: aperture_deg = atan(tan(fov/2) 200/160)) -----

// By hand: fov 60 deg, tan 30 deg = 0.5773503, x 1.25 (the image diagonal 200 px over its width
// 160 px) = 0.7216878, atan = 35.8175 deg. The inverse gives the 60 deg back.
TEST(RoundSeventeen, TheApertureFollowsTheFieldOfViewOnTheImageDiagonal) {
  EXPECT_NEAR(deg(ms::aperture_from_horizontal_fov_rad(rad(60.0))), 35.8175256, 1e-6);
  EXPECT_NEAR(deg(ms::horizontal_fov_from_aperture_rad(rad(35.8175256444))), 60.0, 1e-6);
  for (double fov : {10.0, 30.796571, 45.0, 90.0, 150.0})
    EXPECT_NEAR(deg(ms::horizontal_fov_from_aperture_rad(ms::aperture_from_horizontal_fov_rad(rad(fov)))), fov, 1e-9) << fov;
  // The shipped calibration's aperture_deg from its fov_deg by the docs' formula.
  const json p = epuck2::testing::shipped_fitted("camera").at("parameters");
  const double fov = p.at("fov_deg").get<double>();
  EXPECT_NEAR(p.at("aperture_deg").get<double>(), deg(std::atan(std::tan(rad(fov) / 2) * 200.0 / 160.0)), 1e-6);
}

// ----- lib/fit -----

// parameter.hpp: names and starts of the same length, else std::invalid_argument.
TEST(RoundSeventeen, FreeParametersRefuseNamesAndStartsOfDifferentLengths) {
  EXPECT_THROW(ef::free_parameters({"a"}, {1.0, 2.0}), std::invalid_argument);
  EXPECT_THROW(ef::free_parameters({"a", "b"}, {1.0}), std::invalid_argument);
  const auto two = ef::free_parameters({"a", "b"}, {1.0, 2.0});
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[1].name, "b");
  EXPECT_EQ(two[1].value, 2.0);
}

// problem.hpp: readings_block takes one latent prediction and, when channels are given, one
// channel per reading.
TEST(RoundSeventeen, AReadingsBlockRefusesAChannelListOfAnotherLength) {
  auto latent = [] {
    ef::ResidualBlock b;
    b.residuals = 3;
    b.sizes = {1};
    b.evaluate = [](double const* const* p, double* r, double**) {
      for (int i = 0; i < 3; ++i) r[i] = p[0][0] * i;
      return true;
    };
    return b;
  };
  const ef::Channels two(std::vector<ef::Channel>(2));
  EXPECT_THROW(ef::readings_block(latent(), {1, 2, 3}, {0, 1}, two), std::invalid_argument);
  EXPECT_THROW(ef::readings_block(latent(), {1, 2, 3}, {0, 1, 1, 0}, two), std::invalid_argument);
  EXPECT_THROW(ef::readings_block(latent(), {1, 2}, {}, two), std::invalid_argument);
  EXPECT_NO_THROW(ef::readings_block(latent(), {1, 2, 3}, {0, 1, 1}, two));
  EXPECT_NO_THROW(ef::readings_block(latent(), {1, 2, 3}, {}, two));
}

struct Line {
  static constexpr int kParameters = 2;
  static constexpr bool kLinearInParameters = true;
  template <typename T>
  T operator()(const T* p, double x) const {
    return p[0] + p[1] * x;
  }
};

// A held parameter stays where it is held, the first one included. By hand: y = 1, 3, 5, 7 at
// x = 0..3 with p0 held at 0: the slope through the origin is sum(x y) / sum(x^2) = (0 + 3 + 10 +
// 21) / (0 + 1 + 4 + 9) = 34/14. (Free, the line is p0 = 1, p1 = 2 exactly.)
TEST(RoundSeventeen, ALinearFitKeepsItsFirstParameterWhereItIsHeld) {
  const std::vector<double> x{0, 1, 2, 3}, y{1, 3, 5, 7};
  const ef::FitResult held = ef::fit_curve(Line{}, x, y, {ef::fixed_parameter("p0", 0.0), ef::free_parameter("p1", 0.0)});
  ASSERT_TRUE(held.usable) << held.message;
  EXPECT_EQ(held.value("p0"), 0.0);
  EXPECT_NEAR(held.value("p1"), 34.0 / 14.0, 1e-9);
  EXPECT_EQ(held.free_parameters, 1);
  const ef::FitResult second = ef::fit_curve(Line{}, x, y, {ef::free_parameter("p0", 0.0), ef::fixed_parameter("p1", 3.0)});
  ASSERT_TRUE(second.usable) << second.message;
  // p1 held at 3: p0 = mean(y - 3x) = mean(1, 0, -1, -2) = -0.5.
  EXPECT_EQ(second.value("p1"), 3.0);
  EXPECT_NEAR(second.value("p0"), -0.5, 1e-9);
  const ef::FitResult free = ef::fit_curve(Line{}, x, y, {ef::free_parameter("p0", 0.0), ef::free_parameter("p1", 0.0)});
  ASSERT_TRUE(free.usable) << free.message;
  EXPECT_NEAR(free.value("p0"), 1.0, 1e-9);
  EXPECT_NEAR(free.value("p1"), 2.0, 1e-9);
}

// ----- lib/coefficients -----

// docs/coefficient-files.md: "Writing refuses what reading would refuse" -- and a refused write
// leaves the file's JSON as it was, whichever of its three states it was in.
TEST(RoundSeventeen, ARefusedRobotSetLeavesTheFileAsItWas) {
  const json shipped = epuck2::testing::shipped_fitted("ground");
  json bad_set = shipped.at("robots").begin().value();
  bad_set["parameters"]["gain"] = json::array({-5.0, -5.0, -5.0});  // gain in (0, 4092]
  {
    json j = shipped;
    j.erase("robots");
    const json before = j;
    EXPECT_THROW(epuck2::coefficients::add_robot_set(j, "ground", "r1", bad_set), std::domain_error);
    EXPECT_EQ(j, before);
    EXPECT_FALSE(j.contains("robots"));
  }
  {
    json j = shipped;
    const json before = j;
    EXPECT_THROW(epuck2::coefficients::add_robot_set(j, "ground", "r1", bad_set), std::domain_error);
    EXPECT_EQ(j, before);
  }
  {
    json j = shipped;
    const json before = j;
    const std::string id = shipped.at("robots").begin().key();
    EXPECT_THROW(epuck2::coefficients::add_robot_set(j, "ground", id, bad_set), std::domain_error);
    EXPECT_EQ(j, before);
  }
}

class RoundSeventeenCli : public epuck2::testing::CliTest {
 protected:
  static std::string raw(const std::string& kind, const std::string& file) {
    return "\"" + (fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / kind / file).string() + "\"";
  }
  static std::string lines_of(const fs::path& p) { return epuck2::testing::slurp(p); }
  static std::vector<std::string> data_lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line))
      if (!line.empty() && (std::isdigit(static_cast<unsigned char>(line[0])) || line[0] == '-')) out.push_back(line);
    return out;
  }
};

// docs/coefficient-files.md: a light calibration's per_sensor[i].sensor is "0 to 7": a sensor's
// number, so 2.5 is refused, not read as sensor 2.
TEST_F(RoundSeventeenCli, APerSensorEntryForSensorTwoAndAHalfIsRefused) {
  json l = epuck2::testing::shipped_fitted("light");
  json e = l.at("per_sensor").at(0);
  e["sensor"] = 2.5;
  l["per_sensor"] = json::array({e});
  const std::string f = write("half.json", l.dump(2));
  const auto r = run("simulate light --like " + raw("light", "light_intensity_0.50.csv") + " --coefficients \"" + f + "\" -o \"" +
                     (dir_ / "o.csv").string() + "\"");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("(at JSON path /per_sensor/0/sensor)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("0 to 7"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "o.csv"));
}

// docs/coefficient-files.md (unknown keys): the closest known key is named when it is near:
// within 2 edits, or a third of the key's length. `linear_slop_std_err` (19 letters: 6 edits
// allowed) is 3 insertions from `linear_slope_std_error`; `slip_tim_constnt` (16: 5) is 4 from
// `slip_time_constant_s`. `zzzz` (4 letters: 2 edits) is near nothing.
TEST_F(RoundSeventeenCli, AMisspeltKeyFarFromTwoEditsStillGetsItsHintWhenLong) {
  const std::string battery_log = raw("battery", "robot-a_speed-01.csv");
  json b = epuck2::testing::shipped_fitted("battery");
  b["speeds"][0]["linear_slop_std_err"] = 0.0;
  std::string f = write("b.json", b.dump(2));
  auto r = run("simulate battery --like " + battery_log + " --coefficients \"" + f + "\" -o \"" + (dir_ / "o.csv").string() + "\"");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("did you mean 'linear_slope_std_error'?"), std::string::npos) << r.err;

  json d = epuck2::testing::shipped_fitted("drive");
  d["parameters"]["slip_tim_constnt"] = 0.1;
  f = write("d.json", d.dump(2));
  const std::string drive_log = raw("drive", "drive_away_05.0_cm_s.csv");
  r = run("simulate drive --like " + drive_log + " --coefficients \"" + f + "\" -o \"" + (dir_ / "o.csv").string() + "\"");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("did you mean 'slip_time_constant_s'?"), std::string::npos) << r.err;

  b = epuck2::testing::shipped_fitted("battery");
  b["speeds"][0]["zzzz"] = 0.0;
  f = write("z.json", b.dump(2));
  r = run("simulate battery --like " + battery_log + " --coefficients \"" + f + "\" -o \"" + (dir_ / "o.csv").string() + "\"");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("zzzz"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("did you mean"), std::string::npos) << r.err;
}

// ----- lib/calibrate: the text reports -----

// The method line says what was done: proximity readings on a rail are censored (Tobit); a
// camera has no rails, so its report never says so (docs/fitting.md: rails per kind).
TEST_F(RoundSeventeenCli, TheMethodLineNamesCensoringOnlyWhereTheKindHasRails) {
  auto r = run("proximity" + shipped("proximity"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("readings on a rail censored (Tobit)"), std::string::npos) << r.out;
  r = run("camera" + shipped("camera"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("censored (Tobit)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("(no rails: none censored)"), std::string::npos) << r.out;
}

// docs/coefficient-files.md: ground replicates are "each log's readings of one sensor over one grey
// level"; groups holding a railed reading (0 or 1023) are left out. Counted here from the shipped
// logs; the text report gives the count of groups.
TEST_F(RoundSeventeenCli, TheNoiseLineCountsTheReplicateGroups) {
  std::map<std::tuple<std::string, std::string, std::string>, std::vector<int>> groups;
  for (const auto& p : epuck2::testing::shipped_logs("ground"))
    for (const std::string& line : data_lines(lines_of(p))) {
      std::istringstream in(line);
      std::string grey, sensor, value;
      std::getline(in, grey, ',');
      std::getline(in, sensor, ',');
      std::getline(in, value, ',');
      groups[{p.string(), grey, sensor}].push_back(std::stoi(value));
    }
  std::size_t usable = 0;
  for (const auto& [key, v] : groups) {
    bool railed = false;
    for (int x : v) railed = railed || x <= 0 || x >= 1023;
    if (!railed && v.size() >= 2) ++usable;
  }
  ASSERT_GT(usable, 10u);
  const auto r = run("ground" + shipped("ground"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string want = " in " + std::to_string(usable) + " groups)";
  const auto at = r.out.find("Reading noise (ground): sd ");
  ASSERT_NE(at, std::string::npos) << r.out;
  const std::string line = r.out.substr(at, r.out.find('\n', at) - at);
  EXPECT_NE(line.find("from replicates ("), std::string::npos) << line;
  EXPECT_NE(line.find(want), std::string::npos) << line << " (want" << want << ")";
}

// The proximity's range (docs/fitting.md): when readings are still detected (mean at least 1 % of
// 4095 = 40.95 counts) at the farthest distance logged, beyond the model's 50 mm, the range is only
// bounded below: "at least" that distance. The shipped logs cut at 55 mm with the 55 mm readings
// set to 60..64 counts (mean 62, detected).
TEST_F(RoundSeventeenCli, AProximityRangeStillDetectedAtTheFarthestDistanceIsALowerBound) {
  std::string args;
  for (const auto& p : epuck2::testing::shipped_logs("proximity")) {
    std::istringstream in(lines_of(p));
    std::string text, line;
    int k = 0;
    while (std::getline(in, line)) {
      if (!line.empty() && std::isdigit(static_cast<unsigned char>(line[0]))) {
        std::istringstream cells(line);
        std::string t, d, s, v;
        std::getline(cells, t, ',');
        std::getline(cells, d, ',');
        std::getline(cells, s, ',');
        const double dm = std::stod(d);
        if (dm > 0.0550001) continue;
        if (dm > 0.0549999) line = t + "," + d + "," + s + "," + std::to_string(60 + (k++ % 5));
      }
      text += line + "\n";
    }
    args += " \"" + write(p.filename().string(), text) + "\"";
  }
  const fs::path out = dir_ / "p.json";
  const auto r = run("proximity" + args + " -o \"" + out.string() + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json range = json::parse(lines_of(out)).at("range_fit");
  EXPECT_TRUE(range.at("lower_bound").get<bool>()) << range.dump();
  EXPECT_DOUBLE_EQ(range.at("value_m").get<double>(), 0.055);
  EXPECT_EQ(range.at("how").get<std::string>().rfind("at least 55 mm", 0), 0u) << range.dump();
}

// ----- lib/diagnose -----

// docs/diagnose.md: `image_row` is the image row the plug-in's camera projects the LED onto. A
// camera log (pinhole: fov 60 deg, f = 80 / tan 30 deg, centre (80, 60)) whose py reads 3 px low
// on every LED below the image's middle row, px exact: the residuals depend on the row, not on the
// column (the grid's lateral and vertical positions are crossed).
TEST_F(RoundSeventeenCli, TheCameraDiagnosisScoresTheResidualsAgainstTheImageRow) {
  const double f = 80.0 / std::tan(rad(30.0));
  const int jitter[8] = {-1, 0, 1, 0, 1, 0, -1, 1};
  std::ostringstream o;
  o << "# robot: hand-made\nforward_m,lateral_m,vertical_m,px,py\n";
  int k = 0;
  for (double x : {0.3, 0.4, 0.5})
    for (double y : {-0.06, -0.04, -0.02, 0.0, 0.02, 0.04, 0.06})
      for (double z : {-0.04, -0.02, 0.0, 0.02, 0.04}) {
        const double row = 60.0 - f * z / x, column = 80.0 - f * y / x;
        for (int s = 0; s < 4; ++s, ++k)
          o << x << ',' << y << ',' << z << ',' << std::lround(column) + jitter[k % 8] << ','
            << std::lround(row + (row > 60.0 ? 3.0 : 0.0)) + jitter[(k + 3) % 8] << '\n';
      }
  const std::string log = write("cam.csv", o.str());
  const fs::path out = dir_ / "d.json";
  const auto r = run("diagnose \"" + log + "\" -o \"" + out.string() + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::map<std::string, double> score;
  const json report = json::parse(lines_of(out));  // kept: a range-for over a temporary's member dangles
  for (const json& c : report.at("residual_structure_before"))
    score[c.at("covariate").get<std::string>()] = c.at("score").get<double>();
  ASSERT_TRUE(score.count("image_row") && score.count("lateral_m") && score.count("vertical_m"));
  EXPECT_GT(score["image_row"], 0.1);
  EXPECT_GT(score["image_row"], 3.0 * score["lateral_m"]);
  EXPECT_GE(score["image_row"], 0.9 * score["vertical_m"]);
}

// docs/fitting.md: the diagnosis leaves out a ToF spike only "on a row whose command repeats the
// previous row's (so that no command is lost)", and lists it with its two neighbours' readings.
// drive_away_05.0_cm_s.csv: line 17 is the first row commanding -5 cm/s (line 16 commands 0), line
// 30 repeats line 29's command; both get a ToF of 900 mm among readings near 300.
TEST_F(RoundSeventeenCli, AToFSpikeIsLeftOutOnlyWhereTheCommandRepeats) {
  std::istringstream in(lines_of(fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / "drive" / "drive_away_05.0_cm_s.csv"));
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line)) lines.push_back(line);
  auto cells = [](const std::string& l) {
    std::vector<std::string> c;
    std::istringstream s(l);
    std::string x;
    while (std::getline(s, x, ',')) c.push_back(x);
    return c;
  };
  // The premise, from the file: line 17's command differs from line 16's, line 30's repeats 29's.
  ASSERT_NE(cells(lines[15])[1], cells(lines[16])[1]);
  ASSERT_EQ(cells(lines[28])[1], cells(lines[29])[1]);
  ASSERT_EQ(cells(lines[28])[2], cells(lines[29])[2]);
  const std::string left = cells(lines[28])[5], right = cells(lines[30])[5];
  for (int n : {16, 29}) {
    auto c = cells(lines[static_cast<std::size_t>(n)]);
    c[5] = "900";
    lines[static_cast<std::size_t>(n)] = c[0] + "," + c[1] + "," + c[2] + "," + c[3] + "," + c[4] + "," + c[5];
  }
  std::string text;
  for (const auto& l : lines) text += l + "\n";
  const std::string log = write("spike.csv", text);
  const fs::path out = dir_ / "d.json";
  const auto r = run("diagnose \"" + log + "\" -o \"" + out.string() + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  bool at30 = false, at17 = false;
  const json report = json::parse(lines_of(out));
  for (const json& w : report.at("outliers").at("rows")) {
    const std::string s = w.get<std::string>();
    if (s.find("spike.csv:30: ") != std::string::npos) {
      at30 = true;
      EXPECT_NE(s.find("tof_mm 900 where its neighbours read " + left + " and " + right), std::string::npos) << s;
    }
    at17 = at17 || s.find("spike.csv:17: ") != std::string::npos;
  }
  EXPECT_TRUE(at30);
  EXPECT_FALSE(at17);
}

// ----- lib/logs -----

// A log with CRLF line ends counts one line per CRLF: the bad cell of the third line is at line 3,
// column 5 (`0.1,` is 4 characters).
TEST_F(RoundSeventeenCli, ACrlfLogCountsOneLinePerLineEnd) {
  const std::string log = write("crlf.csv", "time_s,distance_m,sensor,value\r\n0,0.01,0,4000\r\n0.1,abc,0,4000\r\n0.2,0.01,0,3990\r\n");
  const auto r = run("proximity \"" + log + "\"");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("crlf.csv:3:5:"), std::string::npos) << r.err;
}

// Metadata keeps its spaces (only control characters are escaped): `simulate --like` writes the
// robot's name as the log gave it.
TEST_F(RoundSeventeenCli, AMetadataValueKeepsItsSpaces) {
  const std::string log = write("g.csv", "# robot: e puck 7\n# seed: 7\ngrey,sensor,value\n0,0,64\n0,1,60\n0.5,0,500\n0.5,1,505\n1,0,900\n1,1,910\n");
  const fs::path out = dir_ / "s.csv";
  auto r = run("simulate ground --like \"" + log + "\" -o \"" + out.string() + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = lines_of(out);
  EXPECT_NE(text.find("# robot: e puck 7\n"), std::string::npos) << text;
  // docs/cli.md: the log's seed is not the simulation's; without --noise nothing was drawn, so no
  // seed is written; with --noise --seed 3, the one seed line is 3.
  EXPECT_EQ(text.find("# seed:"), std::string::npos) << text;
  r = run("simulate ground --like \"" + log + "\" --noise --seed 3 -o \"" + out.string() + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string noisy = lines_of(out);
  EXPECT_NE(noisy.find("# seed: 3\n"), std::string::npos) << noisy;
  EXPECT_EQ(noisy.find("# seed: 7"), std::string::npos) << noisy;
  EXPECT_EQ(noisy.find("# seed:"), noisy.rfind("# seed:")) << noisy;
}

// ----- apps/ -----

// `simulate camera --like`: rows whose LED falls off the image are left out and counted, and the
// first of them is named by its line. Lines 1-2 are the header; the LEDs of lines 5 and 9 sit
// 0.5 m to the side at 0.3 m forward (px = 80 - 138.6 x 0.5/0.3 < 0).
TEST_F(RoundSeventeenCli, SimulateNamesTheFirstRowTheCameraCannotSee) {
  std::string text = "# robot: hand-made\nforward_m,lateral_m,vertical_m,px,py\n";
  for (int line = 3; line <= 12; ++line)
    text += (line == 5 || line == 9) ? "0.3,0.5,0,0,60\n" : "0.3,0.01,0,75,60\n";
  const std::string log = write("cam.csv", text);
  const fs::path out = dir_ / "s.csv";
  const auto r = run("simulate camera --like \"" + log + "\" -o \"" + out.string() + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("2 of 10 rows left out"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("the first at " + log + ":5\n"), std::string::npos) << r.err;
  EXPECT_EQ(data_lines(lines_of(out)).size(), 8u);
}

// --skip-bad-rows: "the count, then the first 10 as file:line:column" (docs/cli.md). With exactly
// 10 bad rows all of them are listed, so none is called "the first 10"; with 11, ten are listed.
TEST_F(RoundSeventeenCli, SkippedRowsAreAllListedUpToTenAndTheFirstTenBeyond) {
  for (int bad : {10, 11}) {
    std::string text = "# robot: hand-made\ngrey,sensor,value\n";
    for (int i = 0; i < 30; ++i)
      for (int s = 0; s < 3; ++s) text += std::to_string(i % 3 * 0.5) + "," + std::to_string(s) + "," + std::to_string(100 + 400 * (i % 3) + i % 4) + "\n";
    for (int i = 0; i < bad; ++i) text += "0.5,1,x\n";
    const std::string log = write("g" + std::to_string(bad) + ".csv", text);
    const auto r = run("ground \"" + log + "\" --skip-bad-rows --accept-misfit");
    const std::string head = "skipped " + std::to_string(bad) + " bad rows (--skip-bad-rows)";
    const auto at = r.err.find(head);
    ASSERT_NE(at, std::string::npos) << r.err;
    const std::string rest = r.err.substr(at + head.size());
    if (bad == 10) EXPECT_EQ(rest.rfind(":\n", 0), 0u) << r.err;
    else EXPECT_EQ(rest.rfind(", the first 10:\n", 0), 0u) << r.err;
    std::size_t listed = 0;  // the lines "  FILE:LINE:COLUMN: reason"
    const std::string item = "\n  " + log + ":";
    for (std::size_t p = r.err.find(item); p != std::string::npos; p = r.err.find(item, p + 1)) ++listed;
    EXPECT_EQ(listed, 10u) << r.err;
  }
}

}  // namespace test_round_seventeen_cpp
