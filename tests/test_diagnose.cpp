// epuck2-fit diagnose (docs/diagnose.md): seeded logs with an effect hidden in them, drawn
// from the catalogue with a random size and realistic noise (tests/diagnose_generators.hpp); rates
// over seeds of the right verdict and of parameters within 10 %, `none` on logs without an effect,
// `unexplained` with the right covariate first for an effect outside the catalogue. This is the
// fast subset; bench/diagnose_sweep.cpp runs the full sweep. Then the CLI on the shipped logs.
#include <gtest/gtest.h>

#include <set>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "diagnose_generators.hpp"

// This file's `using namespace` stays in its own named namespace, so it opens nothing to the
// files compiled after it in the same unity unit (tests/CMakeLists.txt).
namespace test_diagnose_cpp {
namespace {

using namespace epuck2;
namespace gen = epuck2::testing::diagnose;

/// Seeds per hidden effect in CI (the sweep runs 40 and more).
constexpr int kSeeds = 8;
/// The brief's targets: right verdict in at least 95 % of the logs; parameters within 10 % in at
/// least 95 % of the logs whose verdict is right.
constexpr double kMinVerdictRate = 0.95;
constexpr double kMinParameterRate = 0.95;

struct Rates {
  int logs = 0, right = 0, checked = 0, params_right = 0;
  int none_logs = 0, none_right = 0;
  std::string failures;
};

Rates sweep(logs::Kind kind, int seeds, const std::vector<std::string>& skip_parameters = {}) {
  Rates r;
  for (const std::string& cause : gen::hidden_effects(kind))
    for (int s = 0; s < seeds; ++s) {
      gen::Hidden h = gen::hidden(cause);
      const std::uint64_t seed = 7919ULL * static_cast<std::uint64_t>(s + 1) + 31ULL * cause.size();
      const auto log = logs::parse_log(gen::make_log(kind, seed, h), "generated.csv", kind);
      const auto report = diagnose::diagnose({log});
      const gen::Outcome o = gen::judge(h, report);
      ++r.logs;
      r.right += o.verdict_right;
      if (cause == "none") {
        ++r.none_logs;
        r.none_right += o.verdict_right;
      }
      if (!o.verdict_right) r.failures += cause + " seed " + std::to_string(seed) + " -> " + o.verdict + " (" + o.first_covariate + "); ";
      bool skip = false;
      for (const auto& k : skip_parameters) skip = skip || k == cause;
      if (o.parameters_checked && !skip) {
        ++r.checked;
        r.params_right += o.parameters_right;
        if (!o.parameters_right) r.failures += cause + " seed " + std::to_string(seed) + " parameters off by " + std::to_string(o.worst_relative_error) + "; ";
      }
    }
  return r;
}

void expect_rates(const Rates& r) {
  ASSERT_GT(r.logs, 0);
  EXPECT_GE(double(r.right) / r.logs, kMinVerdictRate) << r.right << "/" << r.logs << ": " << r.failures;
  EXPECT_GE(double(r.none_right) / r.none_logs, kMinVerdictRate) << r.none_right << "/" << r.none_logs;
  if (r.checked) EXPECT_GE(double(r.params_right) / r.checked, kMinParameterRate) << r.params_right << "/" << r.checked << ": " << r.failures;
}

TEST(DiagnoseHidden, Ground) { expect_rates(sweep(logs::Kind::ground, kSeeds)); }
TEST(DiagnoseHidden, Light) { expect_rates(sweep(logs::Kind::light, kSeeds)); }
TEST(DiagnoseHidden, Camera) { expect_rates(sweep(logs::Kind::camera, kSeeds)); }
TEST(DiagnoseHidden, Proximity) { expect_rates(sweep(logs::Kind::proximity, 6)); }

TEST(DiagnoseHidden, NoEffectGivesNoneAndNoFinding) {
  for (int s = 0; s < 10; ++s) {
    gen::Hidden h = gen::hidden("none");
    const auto log = logs::parse_log(gen::make_log(logs::Kind::ground, 100 + s, h), "g.csv", logs::Kind::ground);
    const auto r = diagnose::diagnose({log});
    EXPECT_EQ(r.verdict_name(), "none");
    EXPECT_TRUE(r.findings.empty());
  }
}

// Drive and battery logs are longer to simulate: fewer seeds in CI (the sweep runs 40).
TEST(DiagnoseHidden, Drive) { expect_rates(sweep(logs::Kind::drive, 6)); }
TEST(DiagnoseHidden, Battery) { expect_rates(sweep(logs::Kind::battery, 10)); }

TEST(DiagnoseHidden, EveryKindIsSupported) {
  for (logs::Kind k : {logs::Kind::battery, logs::Kind::proximity, logs::Kind::light, logs::Kind::ground, logs::Kind::camera,
                       logs::Kind::drive}) {
    EXPECT_TRUE(diagnose::supported(k)) << logs::to_string(k);
    EXPECT_FALSE(gen::hidden_effects(k).empty()) << logs::to_string(k);
  }
}

// The drive model integrates the ramps and the lag in closed form; a hidden effect's parameters
// come back from a log the generator simulated step by step (1 ms), for each effect alone.
TEST(DiagnoseHidden, DriveWithoutAnEffectLeavesNoStructure) {
  for (int s = 0; s < 4; ++s) {
    gen::Hidden h = gen::hidden("none");
    const auto log = logs::parse_log(gen::make_log(logs::Kind::drive, 500 + s, h), "d.csv", logs::Kind::drive);
    const auto r = diagnose::diagnose({log});
    EXPECT_EQ(r.verdict_name(), "none") << (r.structure_after.empty() ? "" : r.structure_after.front().covariate);
    ASSERT_EQ(r.channel_noise_sd.size(), 2u);
    // ToF noise 2 mm + 3 mm per metre at 0.1..1.2 m; encoders: rounding only.
    EXPECT_GT(r.channel_noise_sd[0].value, 2.0);
    EXPECT_LT(r.channel_noise_sd[0].value, 6.0);
    EXPECT_LT(r.channel_noise_sd[1].value, 0.4);
  }
}

// ----- the command line -------------------------------------------------------------------------

class DiagnoseCli : public epuck2::testing::CliTest {
 protected:
  /// Robot 1's shipped logs of a kind, without the files whose name holds one of `leave_out`:
  /// robot 2 differs on purpose (data/raw/<kind>/README.md), and a diagnosis of both robots
  /// pooled rightly answers that the residuals depend on the log.
  static std::string robot1(const std::string& kind, const std::vector<std::string>& leave_out = {}) {
    std::vector<std::string> paths;
    for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / kind)) {
      const std::string name = e.path().filename().string();
      if (e.path().extension() != ".csv" || name.find("virtual-epuck2-2") != std::string::npos) continue;
      bool skip = false;
      for (const auto& l : leave_out) skip = skip || name.find(l) != std::string::npos;
      if (!skip) paths.push_back(e.path().string());
    }
    std::sort(paths.begin(), paths.end());
    std::string args;
    for (const auto& p : paths) args += " \"" + p + "\"";
    return args;
  }
};

TEST_F(DiagnoseCli, ShippedCameraNamesThePrincipalOffset) {
  const std::string json = (dir_ / "camera.json").string();
  const auto r = run("diagnose --json \"" + json + "\" --plot \"" + dir_.string() + "\"" + robot1("camera"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(epuck2::testing::slurp(json));
  // data/raw/camera/README.md: optical axis at column 81.6, row 57.9; field of view 30.8 deg.
  constexpr double kPixelTolerance = 0.2;  // px: 6 standard errors of the fit
  EXPECT_EQ(j.at("verdict"), "principal_offset");
  EXPECT_NEAR(j.at("findings").at(0).at("parameters").at("dx_px").get<double>(), 1.6, kPixelTolerance);
  EXPECT_NEAR(j.at("findings").at(0).at("parameters").at("dy_px").get<double>(), -2.1, kPixelTolerance);
  EXPECT_NEAR(j.at("recalibrated").at("fov_deg").get<double>(), 30.8, 0.1);
  EXPECT_LT(j.at("findings").at(0).at("heldout_mse_after").get<double>(), j.at("findings").at(0).at("heldout_mse_before").get<double>());
  EXPECT_TRUE(j.at("residual_structure").is_array());
  EXPECT_TRUE(std::filesystem::exists(dir_ / "diagnose_camera.png"));
}

// The camera's residuals are tested against the image row the LED falls on (`image_row`), a
// covariate apart from the log's row number (`log_row`): both are in the residual structure.
TEST_F(DiagnoseCli, CameraTestsTheImageRowApartFromTheLogRow) {
  const auto r = run("diagnose --json -" + shipped("camera"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  std::set<std::string> names;
  for (const auto& s : j.at("residual_structure")) names.insert(s.at("covariate").get<std::string>());
  EXPECT_TRUE(names.count("image_row")) << j.at("residual_structure").dump();
  EXPECT_TRUE(names.count("log_row")) << j.at("residual_structure").dump();
  EXPECT_FALSE(names.count("row"));
}

TEST_F(DiagnoseCli, ShippedLightNamesSensorGainAndAmbientLight) {
  const auto r = run("diagnose --json -" + shipped("light"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  // data/raw/light/README.md: sensor 7 has gain 0.94 against sensor 0, stray light 12 counts.
  std::map<std::string, nlohmann::json> found;
  for (const auto& f : j.at("findings")) found[f.at("cause").get<std::string>()] = f;
  ASSERT_TRUE(found.count("sensor_gain"));
  ASSERT_TRUE(found.count("ambient_offset"));
  EXPECT_NEAR(found["sensor_gain"].at("parameters").at("gains").at(7).get<double>(), 0.94, 0.01);
  EXPECT_NEAR(found["ambient_offset"].at("parameters").at("offset").get<double>(), 12.0, 3.0);
}

TEST_F(DiagnoseCli, ShippedDriveNamesTheVirtualRobotsImperfections) {
  // Robot 1's runs towards and away from the obstacle at 0.3 m (the far, floor and static runs
  // exercise the fits' censoring and identifiability; data/raw/drive/README.md). Its four wild ToF
  // readings are left out as spikes before the diagnosis.
  const auto r = run("diagnose --json -" + robot1("drive", {"far", "floor", "static"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  // data/raw/drive/README.md lists robot 1's four wild ToF readings (lines 52, 53, 20 of three runs).
  EXPECT_EQ(j.at("outliers").at("count").get<int>(), 3) << j.at("outliers");
  std::map<std::string, nlohmann::json> found;
  for (const auto& f : j.at("findings")) found[f.at("cause").get<std::string>()] = f;
  // data/raw/drive/README.md: the firmware caps the wheels at 1100 steps/s (14.17 cm/s), the body
  // lags the wheels with tau = 0.12 s, the ToF reads 0.985 d + 9 mm.
  ASSERT_TRUE(found.count("speed_limit"));
  EXPECT_NEAR(found["speed_limit"].at("parameters").at("max_cm_s").get<double>(), 1100.0 / 77.63656, 0.05);
  ASSERT_TRUE(found.count("wheel_slip"));
  EXPECT_NEAR(found["wheel_slip"].at("parameters").at("tau_s").get<double>(), 0.12, 0.01);
  ASSERT_TRUE(found.count("tof_offset"));
  // With one obstacle distance in every log, a ToF scale and a wheel scale differ by a constant
  // that the offset absorbs: either may be named, the other is listed as its alternative.
  const std::string scale = found.count("tof_scale") ? "tof_scale" : "speed_scale";
  ASSERT_TRUE(found.count(scale));
  EXPECT_NEAR(found[scale].at("parameters").at("k").get<double>(), 0.985, 0.002);
  const auto& alts = found[scale].at("alternatives");
  EXPECT_NE(std::find(alts.begin(), alts.end(), scale == "tof_scale" ? "speed_scale" : "tof_scale"), alts.end()) << alts;
  EXPECT_LT(j.at("heldout_mse_final").get<double>(), 0.2 * j.at("heldout_mse_recalibrated").get<double>());
}

TEST_F(DiagnoseCli, ShippedBatteryOfOneRobotNamesItsCapacity) {
  // data/raw/battery/README.md: robot a's cell and battery path make it last about 1 % longer
  // than the average of the two robots, which the fitted tables describe.
  const auto r = run("diagnose --json -" + shipped("battery", "robot-a"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j.at("verdict"), "capacity_scale");
  const double k = j.at("findings").at(0).at("parameters").at("k").get<double>();
  EXPECT_GT(k, 1.003);
  EXPECT_LT(k, 1.025);
}

TEST_F(DiagnoseCli, DriveWithoutObstacleDistanceExitsTwo) {
  const std::string bad = write("d.csv", "time_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n0,0,0,0,0,300\n");
  const auto r = run("diagnose \"" + bad + "\"");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("obstacle_distance_m"), std::string::npos) << r.err;
  EXPECT_EQ(run("diagnose --battery-model nonsense \"" + bad + "\"").exit_code, 2);
}

TEST_F(DiagnoseCli, BadInputExitsTwo) {
  const std::string bad = write("bad.csv", "grey,sensor,value\n0.5,1,abc\n");
  const auto r = run("diagnose \"" + bad + "\"");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad.csv:2"), std::string::npos) << r.err;
  EXPECT_EQ(run("diagnose --kind nonsense \"" + bad + "\"").exit_code, 2);
  EXPECT_EQ(run("diagnose").exit_code, 2);
}

}  // namespace
}  // namespace test_diagnose_cpp
