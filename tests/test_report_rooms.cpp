// Issue #19, items 4 and 5: the reports are written by the libraries that own the results, and
// every per-kind fact they print (units, rails, sensor counts and names) is lib/models' kind_facts.
// The expected values are the E-Puck2's hardware as docs/logs.md gives it (12-bit proximity and
// light registers, 10-bit ground, the VL53L0X's 20..2000 mm, ground sensors 0 right, 1 centre,
// 2 left) and the report's units as docs/diagnose.md lists them, typed here by hand.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <variant>
#include <vector>
#include <string>

#include "epuck2/calibrate/report_text.hpp"
#include "epuck2/diagnose/report_output.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/models/kind_facts.hpp"
#include "epuck2/models/simulate_log.hpp"

namespace {

using epuck2::models::kind_facts;

TEST(KindFacts, RailsSensorsAndNamesAreTheHardwares) {
  EXPECT_EQ(kind_facts("proximity")->channels.front().rails_text(), "0..4095");
  EXPECT_EQ(kind_facts("light")->channels.front().rails_text(), "0..4095");
  EXPECT_EQ(kind_facts("ground")->channels.front().rails_text(), "0..1023");
  EXPECT_EQ(kind_facts("drive")->channels.front().rails_text(), "20..2000");
  EXPECT_EQ(kind_facts("camera")->channels.front().rails_text(), "");  // pixels: no register rails
  EXPECT_FALSE(kind_facts("drive")->channels.back().has_rails());       // encoders wrap, never clamp
  EXPECT_EQ(kind_facts("proximity")->channels.front().sensors, 8);
  EXPECT_EQ(kind_facts("ground")->channels.front().sensors, 3);
  EXPECT_EQ(kind_facts("ground")->sensor_name(0), "0 (right)");
  EXPECT_EQ(kind_facts("ground")->sensor_name(1), "1 (centre)");
  EXPECT_EQ(kind_facts("ground")->sensor_name(2), "2 (left)");
  EXPECT_EQ(kind_facts("proximity")->sensor_name(5), "5");  // unnamed sensors are numbered
}

TEST(ReportTextBuffer, AppendsWhatPrintfWouldPrintWithoutTruncating) {
  epuck2::calibrate::Text t;
  t("%zu readings, %.3f counts\n", std::size_t{12}, 1.5);
  const std::string long_part(5000, 'x');  // longer than any fixed buffer the old printers used
  t("[%s]", long_part.c_str());
  t("%s", "");
  EXPECT_EQ(t.str(), "12 readings, 1.500 counts\n[" + long_part + "]");
}

/// The units a diagnosis report gives for a kind judged on too few rows (no fit: only the units).
std::string mse_units(epuck2::logs::Kind kind) {
  epuck2::diagnose::Report r;
  r.kind = kind;
  r.too_few_rows = true;
  r.message = "only 3 rows";
  return epuck2::diagnose::report_json(r, {"a.csv"}, {})["mse_units"].get<std::string>();
}

TEST(DiagnosisReport, MseUnitsAreTheKindsFirstChannelSquared) {
  using epuck2::logs::Kind;
  EXPECT_EQ(mse_units(Kind::proximity), "counts^2");
  EXPECT_EQ(mse_units(Kind::light), "counts^2");
  EXPECT_EQ(mse_units(Kind::ground), "counts^2");
  EXPECT_EQ(mse_units(Kind::camera), "px^2");
  EXPECT_EQ(mse_units(Kind::drive), "mm^2 (ToF)");  // two channels: the held-out MSE is the ToF's
  EXPECT_EQ(mse_units(Kind::battery), "charge^2");
}

TEST(DiagnosisReport, TextNamesTheUnitPrettyPrinted) {
  epuck2::diagnose::Report r;
  r.kind = epuck2::logs::Kind::drive;
  r.too_few_rows = true;
  r.message = "only 3 rows";
  r.heldout_mse_plugin = 2.5;
  r.mse_plugin_reading = 3.5;
  const std::string text = epuck2::diagnose::report_text(r, "The plug-in's model");
  EXPECT_NE(text.find("before recalibration: MSE 2.5 mm² (ToF) against its expected reading"), std::string::npos) << text;
  EXPECT_NE(text.find("; 3.5 mm² (ToF) against its reading as `simulate --like` writes it."), std::string::npos) << text;
  EXPECT_NE(text.find("Only 3 rows."), std::string::npos) << text;
}

/// Writes `text` to a temporary log and returns the reader's error ("" when it reads).
std::string read_error(const std::string& name, const std::string& text, epuck2::logs::Kind kind) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << text;
  try {
    (void)epuck2::logs::read_log(path.string(), kind);
  } catch (const epuck2::logs::InputError& e) {
    std::filesystem::remove(path);
    return e.what();
  }
  std::filesystem::remove(path);
  return "";
}

TEST(LogReader, RangesComeFromTheKindsRailsAndSensorCounts) {
  using epuck2::logs::Kind;
  const std::string ground_ok = "sensor,grey,value\n0,0.5,1023\n2,0.5,0\n";
  EXPECT_EQ(read_error("rr_ground_ok.csv", ground_ok, Kind::ground), "");
  const std::string high = read_error("rr_ground_high.csv", "sensor,grey,value\n0,0.5,1024\n", Kind::ground);
  EXPECT_NE(high.find("a raw reading 0..1023"), std::string::npos) << high;
  const std::string sensor = read_error("rr_ground_sensor.csv", "sensor,grey,value\n3,0.5,10\n", Kind::ground);
  EXPECT_NE(sensor.find("a ground sensor index 0..2"), std::string::npos) << sensor;
  const std::string prox = read_error("rr_prox.csv", "distance_m,sensor,value\n0.01,8,100\n", Kind::proximity);
  EXPECT_NE(prox.find("a proximity sensor index 0..7"), std::string::npos) << prox;
  const std::string tof = read_error("rr_tof.csv",
                                     "# obstacle_distance_m: 0.5\ntime_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n"
                                     "0,5,5,0,0,19\n",
                                     Kind::drive);
  EXPECT_NE(tof.find("a ToF reading 20..2000 mm, or >= 8190 (no target in range)"), std::string::npos) << tof;
}

// Issue #19, the last rooms: a reading on a rail as both the calibration and the diagnosis read it
// (the VL53L0X's 20..2000 mm; its "no target" codes >= 8190 read as the ceiling), the one
// dispatch from a kind's name to its model type, and a kind's model run on a log's rows without
// the CLI switching on the kind. Expected values worked by hand from the plug-in's published
// models (docs/logs.md, docs/coefficient-files.md).
namespace rooms {

namespace s = epuck2::models::sensors;
namespace co = epuck2::coefficients;

TEST(KindFacts, AReadingOnARailReadsAsTheRail) {
  const auto& tof = kind_facts("drive")->channels.front();
  EXPECT_EQ(tof.on_rails(8190.0), 2000.0);  // a "no target" code: nothing within 2000 mm
  EXPECT_EQ(tof.on_rails(2000.0), 2000.0);
  EXPECT_EQ(tof.on_rails(12.0), 20.0);
  EXPECT_EQ(tof.on_rails(437.0), 437.0);
  EXPECT_EQ(kind_facts("camera")->channels.front().on_rails(-1234.5), -1234.5);  // pixels: no rails
}

TEST(AnyModel, TheKindsNameChoosesItsModelType) {
  for (const char* kind : {"proximity", "light", "ground", "camera", "drive", "battery"}) {
    EXPECT_EQ(co::kind_of(co::plugin_model(kind)), kind);
    const std::string file = std::string(EPUCK2_SOURCE_DIR) + "/data/fitted/" + kind + ".json";
    EXPECT_EQ(co::kind_of(co::model_from_json(kind, co::read_json_file(file), file)), kind) << file;
  }
  EXPECT_THROW(co::plugin_model("sonar"), std::invalid_argument);
  // The plug-in's published ground model: offset 0 and gain 1023 on every sensor.
  const auto ground = std::get<s::GroundModel>(co::plugin_model("ground"));
  EXPECT_EQ(ground.sensors[2].offset_raw, 0.0);
  EXPECT_EQ(ground.sensors[2].gain_raw, 1023.0);
  // A file of another kind is refused, as the kind's own reader refuses it.
  const std::string light = std::string(EPUCK2_SOURCE_DIR) + "/data/fitted/light.json";
  EXPECT_ANY_THROW(co::model_from_json("ground", co::read_json_file(light), light));
}

/// The table simulated_readings reads (a logs::Log has the same four members).
struct Table {
  std::map<std::string, std::vector<double>> columns;
  std::map<std::string, double> metadata;
  bool has(const std::string& c) const { return columns.count(c) > 0; }
  const std::vector<double>& col(const std::string& c) const { return columns.at(c); }
  std::size_t rows() const { return columns.begin()->second.size(); }
  double metadata_number(const std::string& k) const { return metadata.at(k); }
};

TEST(SimulatedReadings, ThePluginsModelsOnALogsRows) {
  s::StandardNormal normal(1);
  // Ground: offset + gain grey = 0 + 1023 x 0.5 on every sensor, then 1023 x 1 = 1023 (the rail).
  const Table grey{{{"grey", {0.5, 1.0}}, {"sensor", {0, 2}}}, {}};
  const auto g = s::simulated_readings(std::get<s::GroundModel>(co::plugin_model("ground")), grey, {0.0, 0.0}, false, normal);
  ASSERT_EQ(g.size(), 2u);
  EXPECT_DOUBLE_EQ(g[0][0], 511.5);
  EXPECT_DOUBLE_EQ(g[1][0], 1023.0);
  // A covariate offset of +3 counts on the first row.
  EXPECT_DOUBLE_EQ(s::simulated_readings(std::get<s::GroundModel>(co::plugin_model("ground")), grey, {3.0, 0.0}, false, normal)[0][0],
                   514.5);
  // Drive, standing still 0.5 m from the obstacle: the encoders at 0 and the ToF at 1000 x 0.5 mm.
  const Table still{{{"time_s", {0.0, 0.1}}, {"left_speed_cm_s", {0, 0}}, {"right_speed_cm_s", {0, 0}}}, {{"obstacle_distance_m", 0.5}}};
  const auto d = s::simulated_readings(std::get<s::DriveModel>(co::plugin_model("drive")), still, {0.0, 0.0}, false, normal);
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d[1], (std::vector<double>{0.0, 0.0, 500.0}));  // left_steps, right_steps, tof_mm (kind_facts' order)
}

}  // namespace rooms

}  // namespace
