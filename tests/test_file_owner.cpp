// One owner of the coefficient file (issue #19, item 2): what a calibration writes that a reader
// turns into a model (each sensor's `parameters` and `noise`, every robot's set, the battery's
// tables) is written by lib/coefficients, and every such key is one the owner's reader reads and
// checks; the robots are compared from their fits, not from their files.
//
// Expected values come from elsewhere than the writer under test: the fits' own results (what the
// file must read back to, bit for bit), the virtual robot's generator truths (each robot's gains,
// set apart in sensor_truth.hpp), and sums worked by hand in the comments.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "epuck2/calibrate/no_usable_fit.hpp"
#include "epuck2/calibrate/report_json.hpp"
#include "epuck2/calibrate/sensor_reports.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/coefficients/battery_tables.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/virtual_robot/sensor_truth.hpp"

namespace {

namespace co = epuck2::coefficients;
namespace cal = epuck2::calibrate;
namespace s = epuck2::models::sensors;
namespace mb = epuck2::models::battery;
namespace vr = epuck2::virtual_robot;
namespace fsys = std::filesystem;
using nlohmann::json;

/// The shipped logs of a kind, read.
std::vector<epuck2::logs::Log> owner_shipped_logs(const std::string& kind) {
  std::vector<std::string> paths;
  for (const auto& e : fsys::directory_iterator(fsys::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / kind))
    if (e.path().extension() == ".csv") paths.push_back(e.path().string());
  std::sort(paths.begin(), paths.end());
  return epuck2::logs::read_logs(paths);
}

std::string owner_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// ----- every key the calibration writes into the model sections is read and checked ------------

// The report fields a calibration writes inside the model sections, which no reader turns into a
// model (docs/coefficient-files.md, "Informational keys"): a noise channel's measurement, a battery
// speed's statistics and texts, the Simple model's errors and texts.
const std::set<std::string> kOwnerReportOnlyNoise{"from", "n", "groups", "per_sensor_n", "argos_uniform_level"};
const std::set<std::string> kOwnerReportOnlySpeed{
    "runs", "observations", "lifetime_std_error_s", "lifetime_h", "lifetime", "cubic_std_errors", "cubic_std_errors_corrected",
    "cubic_rounded", "cubic_std_error_why", "cubic_std_errors_corrected_why", "linear_slope_std_error", "linear_slope_rounded",
    "free_line", "breakpoints", "mse", "fit", "outliers"};
const std::set<std::string> kOwnerReportOnlySimple{"static_std_error", "moving_std_error", "static_rounded", "moving_rounded"};

/// Every leaf (a number, a string, a null) under `v`, as JSON pointers from `at`.
void owner_leaves(const json& v, const std::string& at, std::vector<std::string>& out) {
  if (v.is_object()) {
    for (auto it = v.begin(); it != v.end(); ++it) owner_leaves(it.value(), at + "/" + it.key(), out);
  } else if (v.is_array()) {
    for (std::size_t i = 0; i < v.size(); ++i) owner_leaves(v.at(i), at + "/" + std::to_string(i), out);
  } else {
    out.push_back(at);
  }
}

/// The pointers of a calibration file's model sections that a reader must read and check, and
/// those it must leave alone (report fields); a key in neither list is a failure (it is reported).
struct OwnerKeys {
  std::vector<std::string> read, report_only;
};
OwnerKeys owner_model_keys(const json& j) {
  OwnerKeys k;
  auto set_keys = [&](const json& set, const std::string& at) {
    for (const char* section : {"parameters", "std_errors"})
      if (set.contains(section)) owner_leaves(set.at(section), at + "/" + section, k.read);
    if (!set.contains("noise")) return;
    for (auto c = set.at("noise").begin(); c != set.at("noise").end(); ++c)
      for (auto e = c.value().begin(); e != c.value().end(); ++e) {
        const std::string p = at + "/noise/" + c.key() + "/" + e.key();
        if (kOwnerReportOnlyNoise.count(e.key())) k.report_only.push_back(p);
        else owner_leaves(e.value(), p, k.read);
      }
  };
  set_keys(j, "");
  if (j.contains("robots"))
    for (auto r = j.at("robots").begin(); r != j.at("robots").end(); ++r) set_keys(r.value(), "/robots/" + r.key());
  if (j.contains("speeds"))
    for (std::size_t i = 0; i < j.at("speeds").size(); ++i)
      for (auto e = j.at("speeds").at(i).begin(); e != j.at("speeds").at(i).end(); ++e) {
        const std::string p = "/speeds/" + std::to_string(i) + "/" + e.key();
        if (kOwnerReportOnlySpeed.count(e.key())) k.report_only.push_back(p);
        else owner_leaves(e.value(), p, k.read);
      }
  if (j.contains("simple"))
    for (auto e = j.at("simple").begin(); e != j.at("simple").end(); ++e) {
      const std::string p = "/simple/" + e.key();
      if (kOwnerReportOnlySimple.count(e.key())) k.report_only.push_back(p);
      else k.read.push_back(p);
    }
  return k;
}

/// Every model key of the file `j` of the kind `kind` is read and checked: replaced by a string,
/// the owner's reader refuses the file at that very key (its JSON path in the message), whichever
/// robot's set is asked for; a report field replaced so is read as before. Returns how many keys
/// were tried.
std::size_t expect_every_model_key_checked(const std::string& kind, const json& j) {
  const OwnerKeys keys = owner_model_keys(j);
  EXPECT_NO_THROW(co::model_from_json(kind, j, "fresh.json")) << kind;
  for (const std::string& p : keys.read) {
    json bad = j;
    bad[json::json_pointer(p)] = "not a number";
    const std::string e = owner_error([&] { co::model_from_json(kind, bad, "fresh.json"); });
    EXPECT_NE(e.find("(at JSON path " + p + ")"), std::string::npos) << kind << ": " << p << " is not read and checked: " << e;
  }
  for (const std::string& p : keys.report_only) {
    json other = j;
    other[json::json_pointer(p)] = "not a number";
    EXPECT_EQ(owner_error([&] { co::model_from_json(kind, other, "fresh.json"); }), "") << kind << ": report field " << p;
  }
  return keys.read.size();
}

TEST(FileOwner, EveryModelKeyOfEveryShippedFileIsReadAndChecked) {
  for (const std::string kind : {"proximity", "light", "ground", "camera", "drive", "battery"}) {
    const json j = co::read_json_file(std::string(EPUCK2_SOURCE_DIR) + "/data/fitted/" + kind + ".json");
    // At least the base coefficients, the noise and (sensors) both robots' sets.
    EXPECT_GE(expect_every_model_key_checked(kind, j), kind == "battery" ? 16u * 14u : 8u) << kind;
  }
}

class FreshCalibration : public epuck2::testing::CliTest {};

TEST_F(FreshCalibration, EveryModelKeyOfAFreshFileIsReadAndChecked) {
  for (const std::string kind : {"proximity", "light", "ground", "camera", "drive", "battery"}) {
    const std::string out = (dir_ / (kind + ".json")).string();
    const auto r = run(kind + shipped(kind) + " -o \"" + out + "\"");
    ASSERT_EQ(r.exit_code, 0) << kind << ": " << r.err;
    const json j = co::read_json_file(out);
    if (kind != "battery") {
      ASSERT_TRUE(j.contains("robots")) << kind;
      EXPECT_EQ(j.at("robots").size(), 2u) << kind;
      // No empty `effects` section: a calibration fits the base model (the diagnosis writes them).
      EXPECT_FALSE(j.contains("effects")) << kind;
    }
    expect_every_model_key_checked(kind, j);
  }
}

// ----- what is written reads back to the fit's values, bit for bit ------------------------------

/// The fresh file of a fit, read back through the owner with robot "" (the pooled set).
template <class Fit>
json owner_file(const Fit& f, const std::vector<epuck2::logs::Log>& logs) {
  return cal::coefficient_json(f, logs);
}

TEST(FileOwner, AGroundCalibrationReadsBackToItsFit) {
  const auto logs = owner_shipped_logs("ground");
  const cal::GroundFit f = cal::fit_ground(logs);
  const json j = owner_file(f, logs);
  const auto m = std::get<s::GroundModel>(co::model_from_json("ground", j, "fresh.json"));
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(m.sensors[k].gain_raw, f.sensors[k].value("gain")) << k;
    EXPECT_EQ(m.sensors[k].offset_raw, f.sensors[k].value("offset")) << k;
    EXPECT_EQ(m.noise_sd_raw[k], f.noise.per_sensor_sd[k]) << k;
  }
  // The pooled sd is the calibration's (not the sensors' root mean square), and every sensor has its own.
  EXPECT_EQ(j["noise"]["ground"]["sd"].get<double>(), f.noise.sd);
  EXPECT_EQ(j["noise"]["ground"]["per_sensor_sd"].size(), 3u);
  EXPECT_EQ(j["noise"]["ground"]["n"].get<std::size_t>(), f.noise.n);
}

TEST(FileOwner, AProximityCalibrationReadsBackToBothCurves) {
  const auto logs = owner_shipped_logs("proximity");
  const cal::ProximityFit f = cal::fit_proximity(logs);
  const json j = owner_file(f, logs);
  const s::ProximityModel maxima = co::proximity_model_from_json(j, "fresh.json", "", co::ProximityCurve::maxima);
  const s::ProximityModel means = co::proximity_model_from_json(j, "fresh.json", "", co::ProximityCurve::means);
  EXPECT_EQ(maxima.base.a_per_m2, f.maxima.value("a"));
  EXPECT_EQ(maxima.base.b_per_m, f.maxima.value("b"));
  EXPECT_EQ(maxima.base.c, f.maxima.value("c"));
  EXPECT_EQ(means.base.a_per_m2, f.means.value("a"));
  EXPECT_EQ(means.base.b_per_m, f.means.value("b"));
  EXPECT_EQ(means.base.c, f.means.value("c"));
  EXPECT_EQ(maxima.base.range_m, 0.05);  // the plug-in's range, held (paper Eq. 1's domain)
  for (std::size_t k = 0; k < 8; ++k) EXPECT_EQ(maxima.noise_sd_raw[k], f.noise.per_sensor_sd[k]) << k;
}

TEST(FileOwner, ALightCalibrationReadsBackToItsFit) {
  const auto logs = owner_shipped_logs("light");
  const cal::LightFit f = cal::fit_light(logs);
  const json j = owner_file(f, logs);
  const auto m = std::get<s::LightModel>(co::model_from_json("light", j, "fresh.json"));
  EXPECT_EQ(m.base.gamma_m, f.gamma.value("gamma"));
  EXPECT_EQ(m.base.range_m, 0.5);  // the plug-in's, held
  for (std::size_t k = 0; k < 8; ++k) EXPECT_EQ(m.noise_sd_raw[k], f.noise.per_sensor_sd[k]) << k;
}

TEST(FileOwner, ACameraCalibrationReadsBackToItsFitAndRange) {
  const auto logs = owner_shipped_logs("camera");
  const cal::CameraFit f = cal::fit_camera(logs);
  const json j = owner_file(f, logs);
  const auto m = std::get<s::CameraModel>(co::model_from_json("camera", j, "fresh.json"));
  // fov_deg is written as fitted, and is the model's radians exactly.
  EXPECT_EQ(j["parameters"]["fov_deg"].get<double>(), f.result.value("fov_deg"));
  EXPECT_EQ(m.base.horizontal_fov_rad, f.result.value("fov_deg") * (s::kPi / 180.0));
  EXPECT_EQ(m.base.cx_px, f.result.value("cx_px"));
  EXPECT_EQ(m.base.cy_px, f.result.value("cy_px"));
  EXPECT_EQ(m.noise_sd_px, f.noise.sd);
  // The camera's range is the owner's to read (the ARGoS camera takes it from camera_range_m).
  ASSERT_TRUE(co::camera_range_m(j, "fresh.json").has_value());
  EXPECT_EQ(*co::camera_range_m(j, "fresh.json"), 1.0);
}

TEST(FileOwner, ADriveCalibrationReadsBackToItsFit) {
  const auto logs = owner_shipped_logs("drive");
  const cal::DriveFit f = cal::fit_drive(logs);
  const json j = owner_file(f, logs);
  const auto m = std::get<s::DriveModel>(co::model_from_json("drive", j, "fresh.json"));
  EXPECT_EQ(m.steps_per_m, f.steps.value("steps_per_m"));
  EXPECT_EQ(m.effects.tof_scale.k, f.tof.value("tof_scale"));
  EXPECT_EQ(m.effects.tof_offset.offset_mm, f.tof.value("tof_offset_mm"));
  EXPECT_EQ(m.effects.slip.tau_s, f.tof.value("slip_time_constant_s"));
  EXPECT_EQ(m.tof_noise_sd_mm, f.tof_noise.sd);
  EXPECT_EQ(m.encoder_noise_sd_steps, f.encoder_noise.sd);
}

// ----- the owner's calibration writer refuses what does not read back -------------------------

TEST(FileOwner, TheCalibrationWriterRefusesWhatItCannotWriteFaithfully) {
  s::GroundModel g;
  g.sensors = {{{900.0, 60.0}, {940.0, 48.0}, {870.0, 75.0}}};
  g.noise_sd_raw = {4.0, 5.0, 6.0};
  co::CalibrationExtras x;
  x.pooled_sd["ground"] = 5.2;
  const json j = co::calibration_model_json(g, x);
  EXPECT_EQ(j["noise"]["ground"]["sd"].get<double>(), 5.2);
  EXPECT_EQ(j["noise"]["ground"]["per_sensor_sd"], json::parse("[4.0, 5.0, 6.0]"));
  EXPECT_FALSE(j.contains("effects"));
  // The same model through model_to_json: sd the sensors' root mean square, sqrt((16 + 25 + 36) / 3)
  // = sqrt(25.666...) = 5.0662..., and the (empty) effects section a diagnosis file has.
  const json plain = co::model_to_json(g);
  EXPECT_NEAR(plain["noise"]["ground"]["sd"].get<double>(), 5.066228051190222, 1e-12);
  EXPECT_TRUE(plain.contains("effects"));
  // Equal sensors: model_to_json writes sd alone, the calibration each sensor's too.
  g.noise_sd_raw = {5.0, 5.0, 5.0};
  EXPECT_FALSE(co::model_to_json(g)["noise"]["ground"].contains("per_sensor_sd"));
  EXPECT_TRUE(co::calibration_model_json(g, x)["noise"]["ground"].contains("per_sensor_sd"));

  // A channel of one sensor has one sd, the model's: a calibration's other one is refused.
  s::DriveModel d;
  d.tof_noise_sd_mm = 2.5;
  d.encoder_noise_sd_steps = 0.3;
  co::CalibrationExtras dx;
  dx.pooled_sd["tof"] = 2.6;
  EXPECT_NE(owner_error([&] { co::calibration_model_json(d, dx); }).find("noise.tof.sd"), std::string::npos);
  dx.pooled_sd = {{"no_such_channel", 1.0}};
  EXPECT_NE(owner_error([&] { co::calibration_model_json(d, dx); }).find("no such channel"), std::string::npos);

  // A camera's degrees must be the model's radians exactly.
  s::CameraModel c;
  c.base.horizontal_fov_rad = 30.8 * (s::kPi / 180.0);
  co::CalibrationExtras cx;
  cx.fov_deg = 30.8;
  const json cj = co::calibration_model_json(c, cx);
  EXPECT_EQ(cj["parameters"]["fov_deg"].get<double>(), 30.8);
  EXPECT_EQ(cj["parameters"]["width_px"].get<int>(), 160);
  EXPECT_EQ(cj["parameters"]["height_px"].get<int>(), 120);
  EXPECT_EQ(cj["parameters"]["range_m"].get<double>(), 1.0);
  cx.fov_deg = 31.0;
  EXPECT_NE(owner_error([&] { co::calibration_model_json(c, cx); }).find("not the model's field of view"), std::string::npos);

  // A noise the reader would refuse (at the light's full scale, 4095 counts) is refused at write.
  s::LightModel l;
  co::CalibrationExtras lx;
  lx.pooled_sd["light"] = 4095.0;
  EXPECT_NE(owner_error([&] { co::calibration_model_json(l, lx); }).find("a reader would refuse it"), std::string::npos);
}

TEST(FileOwner, ANoiseSdBesidePerSensorSdsIsChecked) {
  json j = co::model_to_json(s::GroundModel{});
  j["noise"]["ground"] = {{"sd", -1.0}, {"per_sensor_sd", {4.0, 5.0, 6.0}}, {"unit", "counts"}};
  EXPECT_NE(owner_error([&] { co::model_from_json("ground", j, "g.json"); }).find("(at JSON path /noise/ground/sd)"), std::string::npos);
  j["noise"]["ground"]["sd"] = 5.0;
  const auto m = std::get<s::GroundModel>(co::model_from_json("ground", j, "g.json"));
  EXPECT_EQ(m.noise_sd_raw[2], 6.0);  // each sensor's own is what is read
}

TEST(FileOwner, TheCameraRangeIsTheFilesOrNone) {
  json j = co::model_to_json(s::CameraModel{});
  EXPECT_FALSE(j["parameters"].contains("range_m"));  // the plug-in's 1 m is not written
  EXPECT_FALSE(co::camera_range_m(j, "c.json").has_value());
  j["parameters"]["range_m"] = 2.5;
  EXPECT_EQ(*co::camera_range_m(j, "c.json"), 2.5);
  // A robot's set first.
  j["robots"]["r2"] = {{"parameters", {{"range_m", 3.0}}}};
  EXPECT_EQ(*co::camera_range_m(j, "c.json", "r2"), 3.0);
  EXPECT_EQ(*co::camera_range_m(j, "c.json"), 2.5);
  // Checked as the reader checks it: (0, 10] m.
  j["robots"]["r2"]["parameters"]["range_m"] = 11.0;
  EXPECT_NE(owner_error([&] { co::camera_range_m(j, "c.json"); }).find("(at JSON path /robots/r2/parameters/range_m)"), std::string::npos);
}

// ----- the battery's tables -----------------------------------------------------------------

std::array<mb::Segment, mb::kSegmentCount> owner_segments() {
  // Four segments of the line 1 - 0.01 t, each 10 s long: h 1, m -0.01.
  return {{{1, -0.01, 0, 10, 1, 0.9}, {1, -0.01, 10, 20, 0.9, 0.8}, {1, -0.01, 20, 30, 0.8, 0.7}, {1, -0.01, 30, 40, 0.7, 0.6}}};
}

TEST(FileOwner, ABatterySpeedsTablesAndNoiseReadBack) {
  const mb::CubicRow q{0.98, -1e-4, 2e-9, -1e-13, 5000};
  json j = {{"kind", "battery"},
            {"speeds", {co::battery_speed_to_json(3, q, -2e-4, owner_segments(), 0.03),
                        co::battery_speed_to_json(5, q, -2e-4, owner_segments(), 0.04)}}};
  co::TableSources src;
  const s::BatteryModel m = co::battery_model_from_json(j, "b.json", "", src);
  EXPECT_EQ(src.fitted_speeds, (std::vector<int>{3, 5}));
  EXPECT_EQ(m.tables.lifetime_s[3], 5000.0);
  EXPECT_EQ(m.tables.cubic[5].b, 2e-9);
  EXPECT_EQ(m.tables.linear_slope_per_s[5], -2e-4);
  EXPECT_EQ(m.tables.segments[3][2].x2_s, 30.0);
  // The speeds' noise_sd: their root mean square, sqrt((0.03^2 + 0.04^2) / 2) = sqrt(0.00125).
  EXPECT_NEAR(m.noise_sd, 0.035355339059327376, 1e-15);
  // Without noise_sd (NaN): no key; a rising charge is refused at write.
  EXPECT_FALSE(co::battery_speed_to_json(3, q, -2e-4, owner_segments()).contains("noise_sd"));
  EXPECT_NE(owner_error([&] { co::battery_speed_to_json(3, q, 2e-4, owner_segments()); }).find("a reader would refuse it"),
            std::string::npos);
  EXPECT_NE(owner_error([&] { co::battery_speed_to_json(3, q, -2e-4, owner_segments(), 2.0); }).find("noise_sd"), std::string::npos);
  EXPECT_NE(owner_error([&] { co::battery_simple_to_json(-1e-4, 1e-4); }).find("a reader would refuse them"), std::string::npos);
  // Unchecked (a calibration reporting tables fitted to a few rows, and saying no reader takes
  // them): written as given, and the reader refuses them where it would.
  const json rising = co::battery_speed_to_json(3, q, 2e-4, owner_segments(), 0.03, false);
  EXPECT_EQ(rising.at("linear_slope").get<double>(), 2e-4);
  json file = {{"kind", "battery"}, {"speeds", {rising}}};
  co::TableSources src3;
  EXPECT_NE(owner_error([&] { co::battery_model_from_json(file, "b.json", "", src3); }).find("(at JSON path /speeds/0/linear_slope)"),
            std::string::npos);
  EXPECT_NE(owner_error([&] { co::battery_speed_to_json(3, mb::CubicRow{std::nan(""), 0, 0, 0, 10}, -2e-4, owner_segments(), 0.03, false); })
                .find("not finite"),
            std::string::npos);
  EXPECT_EQ(co::battery_simple_to_json(-1e-4, -2e-4), json::parse(R"({"static_slope_per_s": -1e-4, "moving_slope_per_s": -2e-4})"));
}

// ----- the robots, compared from their fits ------------------------------------------------

/// A ground file for robot files in add_robots: its gains and their standard errors.
json owner_ground_file(double gain0, double se0) {
  s::GroundModel g;
  g.sensors = {{{gain0, 60.0}, {940.0, 48.0}, {870.0, 75.0}}};
  g.noise_sd_raw = {5.0, 5.0, 5.0};
  co::CalibrationExtras x;
  x.pooled_sd["ground"] = 5.0;
  json j = co::calibration_model_json(g, x);
  j["std_errors"] = {{"gain", {se0, 1.0, 1.0}}, {"offset", {0.5, 0.5, 0.5}}};
  return j;
}

TEST(FileOwner, RobotsAreComparedFromTheirFitsAndWrittenFromTheirOwnFiles) {
  std::vector<epuck2::logs::Log> all(4);
  for (std::size_t i = 0; i < all.size(); ++i) {
    all[i].robot = std::string(1, static_cast<char>('A' + i));
    all[i].path = std::string(1, static_cast<char>('a' + i)) + ".csv";
  }
  json pooled = owner_ground_file(925.0, 1.0);
  // Each robot's fit: gain[0] 900 ± 3 (A), 950 ± 4 (B); C has no usable fit; D's set no reader
  // would take (a negative gain), and it is not compared. What the robots' files say is not what
  // they are compared by: the estimates are.
  cal::add_robots(pooled, all, [](const std::vector<epuck2::logs::Log>& mine) {
    if (mine.front().robot == "C") throw cal::NoUsableFit("too few readings");
    if (mine.front().robot == "D") {
      cal::RobotCalibration d;
      d.file = owner_ground_file(925.0, 1.0);
      d.file["parameters"]["gain"][0] = -5.0;
      d.estimates = {{"gain[0]", 5000.0, 1.0}};
      return d;
    }
    const bool a = mine.front().robot == "A";
    cal::RobotCalibration r;
    r.file = owner_ground_file(a ? 900.0 : 950.0, a ? 3.0 : 4.0);
    r.estimates = {{"gain[0]", a ? 900.0 : 950.0, a ? 3.0 : 4.0}, {"offset[0]", 60.0, 0.5}, {"held", 1.0, 0.0}};
    return r;
  });
  // Each set is its own robot's file's.
  EXPECT_EQ(pooled["robots"]["A"]["parameters"]["gain"][0].get<double>(), 900.0);
  EXPECT_EQ(pooled["robots"]["B"]["parameters"]["gain"][0].get<double>(), 950.0);
  EXPECT_EQ(pooled["robots"]["A"]["logs"], json::parse(R"(["a.csv"])"));
  EXPECT_EQ(pooled["robots"]["C"]["usable"], false);
  EXPECT_EQ(pooled["robots"]["D"]["usable"], false);
  EXPECT_NE(pooled["robots"]["D"]["why"].get<std::string>().find("a reader would refuse it"), std::string::npos);
  EXPECT_FALSE(pooled["robots"]["D"].contains("parameters"));
  EXPECT_EQ(std::get<s::GroundModel>(co::model_from_json("ground", pooled, "p.json", "B")).sensors[0].gain_raw, 950.0);
  // gain[0]: inverse-variance mean x_w = (900/9 + 950/16) / (1/9 + 1/16) = 159.375 / 0.1736111 = 918.0;
  // Q = (900 - 918)^2 / 9 + (950 - 918)^2 / 16 = 36 + 64 = 100; the robots' sd |950 - 900| / sqrt(2).
  // offset[0] agrees (Q 0); `held` has no standard error: not compared.
  ASSERT_EQ(pooled["robot_spread"].size(), 2u);
  const json& gain = pooled["robot_spread"][0];
  EXPECT_EQ(gain["parameter"], "gain[0]");
  EXPECT_NEAR(gain["q"].get<double>(), 100.0, 1e-9);
  EXPECT_NEAR(gain["spread_sd"].get<double>(), 50.0 / std::sqrt(2.0), 1e-9);
  EXPECT_EQ(gain["dof"].get<int>(), 1);
  EXPECT_TRUE(gain["exceeds_uncertainty"].get<bool>());
  EXPECT_EQ(pooled["robot_spread"][1]["parameter"], "offset[0]");
  EXPECT_FALSE(pooled["robot_spread"][1]["exceeds_uncertainty"].get<bool>());
  ASSERT_TRUE(pooled.contains("warnings"));
  // C and D have no set of their own: said first (A and B were compared), then the comparison's.
  ASSERT_EQ(pooled["warnings"].size(), 3u) << pooled["warnings"].dump();
  EXPECT_EQ(pooled["warnings"][0].get<std::string>().rfind("robot C has no set of its own (too few readings)", 0), 0u);
  EXPECT_EQ(pooled["warnings"][1].get<std::string>().rfind("robot D has no set of its own (", 0), 0u);
  EXPECT_NE(pooled["warnings"][1].get<std::string>().find("it is left out of the robots' comparison."), std::string::npos);
  EXPECT_NE(pooled["warnings"][2].get<std::string>().find("gain[0]"), std::string::npos);
}

TEST(FileOwner, AModelTheOwnerRefusesIsNoUsableFit) {
  EXPECT_THROW(cal::owned_model([]() -> json { throw std::domain_error("parameters.gain[0] = -5 is outside its physical range"); }),
               cal::NoUsableFit);
  EXPECT_EQ(cal::owned_model([] { return json{{"kind", "ground"}}; }), json({{"kind", "ground"}}));
}

TEST(FileOwner, ARobotSetAReaderWouldRefuseIsNotWritten) {
  json pooled = owner_ground_file(925.0, 1.0);
  const json before = pooled;
  // A gain outside its physical range: refused by the reader, the file left as it was.
  json set = {{"parameters", {{"gain", {-5.0, 940.0, 870.0}}, {"offset", {60.0, 48.0, 75.0}}}}};
  EXPECT_NE(owner_error([&] { co::add_robot_set(pooled, "ground", "A", set); }).find("a reader would refuse it"), std::string::npos);
  EXPECT_EQ(pooled, before);
  set = {{"parameters", {{"gian", {900.0, 940.0, 870.0}}}}};  // misspelt
  EXPECT_NE(owner_error([&] { co::add_robot_set(pooled, "ground", "A", set); }).find("did you mean 'gain'"), std::string::npos);
  EXPECT_EQ(pooled, before);
}

// Seven rows at 3 cm/s through a charge map (the firmware's line over 3.5..4.2 V) whose voltage
// rises (a battery being charged): the Approximated model's segments rise, which no reader takes.
// The calibration reports the tables as fitted and says so, with the reader's reason. (A first
// segment ending above a full charge was the case here; the fit now holds the knots in [0, 1].)
TEST_F(FreshCalibration, BatteryTablesNoReaderTakesAreWrittenAndSaid) {
  const std::string map = write("map.json", R"({"kind": "charge_map", "charge_map": {"form": "monotone_piecewise_linear",
    "knots_v": [3.5, 4.2], "knot_charge": [0.125, 1.0], "load_speeds_cm_s": [0, 5], "load_offset_v": [0, 0]}})");
  const std::string log = write("v.csv", "time_s,speed_cm_s,voltage_v\n0,3,3.45\n10,3,3.6\n20,3,3.7\n30,3,3.8\n40,3,3.9\n50,3,4.1\n60,3,4.25\n");
  const std::string out = (dir_ / "b.json").string();
  const auto r = run("battery \"" + log + "\" --charge-map \"" + map + "\" -o \"" + out + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = co::read_json_file(out);
  std::string said;
  for (const auto& w : j.at("warnings"))
    if (w.get<std::string>().find("written as fitted though no reader takes it") != std::string::npos) said = w.get<std::string>();
  ASSERT_FALSE(said.empty()) << j.at("warnings").dump();
  EXPECT_NE(r.err.find(said), std::string::npos) << r.err;  // on standard error too
  // The reason is the reader's own: reading the file fails where the warning says.
  const std::string e = owner_error([&] {
    co::TableSources src;
    co::battery_model_from_json(j, out, "", src);
  });
  ASSERT_FALSE(e.empty());
  const std::string path = e.substr(e.find("(at JSON path"));
  EXPECT_NE(said.find(path), std::string::npos) << said << " / " << e;
}

class TwoRobotsCalibration : public epuck2::testing::CliTest {};

// Two robots whose generator truths differ (robot 2's ground gains 10 % below robot 1's, the same
// offsets; below, so that no white reading reaches the 1023 rail): the calibration gives each robot's set its own truth, and the spread flags the gains.
TEST_F(TwoRobotsCalibration, EachRobotsSetHoldsItsOwnTruth) {
  vr::GroundTruth truth;
  truth.robot_gain_scale = {1.00, 0.90};
  truth.white_rail_raw = 0;  // no rail: both robots' gains as drawn
  truth.wild_fraction = 0;
  std::string args;
  for (const auto& f : vr::ground_logs(truth, 4242)) args += " \"" + write(f.name, f.content) + "\"";
  const std::string out = (dir_ / "ground.json").string();
  const auto r = run("ground" + args + " -o \"" + out + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = co::read_json_file(out);
  ASSERT_TRUE(j.contains("robots"));
  for (std::size_t robot = 0; robot < 2; ++robot) {
    const std::string id = vr::robot_id(robot);
    const auto m = std::get<s::GroundModel>(co::model_from_json("ground", j, out, id));
    for (std::size_t k = 0; k < 3; ++k) {
      // Within 1 % of this robot's truth: the other robot's is 10 % away, a swapped set fails.
      const double expected = truth.gain_raw[k] * truth.robot_gain_scale[robot];
      EXPECT_NEAR(m.sensors[k].gain_raw, expected, 0.01 * expected) << id << " sensor " << k;
      EXPECT_NEAR(m.sensors[k].offset_raw, truth.offset_raw[k], 3.0) << id << " sensor " << k;
    }
  }
  // Every gain differs beyond the robots' uncertainties, and by about the truths' difference:
  // |g - 0.9 g| / sqrt(2) = 0.1 g / sqrt(2) (within 20 %).
  std::size_t gains = 0;
  for (const json& e : j.at("robot_spread")) {
    const std::string p = e.at("parameter");
    if (p.rfind("gain[", 0) != 0) continue;
    const std::size_t k = static_cast<std::size_t>(p[5] - '0');
    EXPECT_TRUE(e.at("exceeds_uncertainty").get<bool>()) << p;
    EXPECT_NEAR(e.at("spread_sd").get<double>(), 0.1 * truth.gain_raw[k] / std::sqrt(2.0), 0.2 * 0.1 * truth.gain_raw[k] / std::sqrt(2.0)) << p;
    ++gains;
  }
  EXPECT_EQ(gains, 3u);
}

}  // namespace
