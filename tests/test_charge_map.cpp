// The voltage->charge map (lib/calibrate/charge_map.hpp): fitted to logs that carry both columns,
// checked against what is known independently of the fit: the shipped logs' charge is the
// firmware's (V - 3.4) / 0.8 of the same filtered voltage (data/raw/battery/README.md, step 5),
// and the virtual robot's terminal voltage sags by I(speed) R under load (its calibration's
// currents and path resistance).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "epuck2/calibrate/charge_map.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/virtual_robot/battery.hpp"

namespace fs = std::filesystem;
namespace cal = epuck2::calibrate;
namespace vb = epuck2::virtual_robot::battery;

namespace {

std::vector<epuck2::logs::Log> shipped_battery_logs() {
  std::vector<std::string> paths;
  for (const auto& e : fs::directory_iterator(fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / "battery"))
    if (e.path().extension() == ".csv") paths.push_back(e.path().string());
  std::sort(paths.begin(), paths.end());
  return epuck2::logs::read_logs(paths, epuck2::logs::Kind::battery);
}

// The firmware's definition of the logged charge (e-puck2 firmware; README step 5).
double firmware_charge(double voltage_v) { return (voltage_v - 3.4) / 0.8; }

}  // namespace

TEST(ChargeMap, TheShippedLogsGiveTheFirmwaresStraightLineWithoutALoadTerm) {
  std::vector<std::string> sources;
  const auto rows = cal::charge_samples(shipped_battery_logs(), &sources);
  ASSERT_EQ(sources.size(), 32u);
  const cal::ChargeMapFit fit = cal::fit_charge_map(rows, sources);
  ASSERT_TRUE(fit.usable) << fit.message;
  const cal::ChargeMap& m = fit.map;
  // Both columns come from one filtered voltage: charge does not depend on the speed beyond it.
  EXPECT_FALSE(m.has_load()) << m.load_why;
  EXPECT_NE(m.load_why.find("dropped"), std::string::npos) << m.load_why;
  // The logs round the voltage to 0.1 mV: a uniform error of sd 0.1e-3 / sqrt(12) V, i.e.
  // 3.6e-5 in charge units; the charge's 6 significant digits add 3e-7. Allow 1e-4.
  EXPECT_LT(m.residual_sd, 1e-4);
  EXPECT_LT(m.max_abs_residual, 1.0e-4);  // half a 0.1 mV step is 6.25e-5 in charge units
  // The map is the firmware's line over the whole range of the logs (3.3564..4.2348 V).
  EXPECT_NEAR(m.voltage_min_v, 3.3564, 1e-9);
  EXPECT_NEAR(m.voltage_max_v, 4.2348, 1e-9);
  for (int k = 0; k <= 50; ++k) {
    const double v = 3.3564 + (4.2348 - 3.3564) * k / 50.0;
    EXPECT_NEAR(cal::convert_voltage(m, v, 7).charge, firmware_charge(v), 1e-4) << v;
  }
  EXPECT_EQ(m.observations, rows.size());
}

TEST(ChargeMap, ALoadDependenceIsFoundAndSizedAsTheCurrentTimesThePathResistance) {
  // A fuel gauge's charge (the true state of charge) against the sagging terminal voltage, at
  // 0..15 cm/s: z = OCV^-1(V + I(speed) R + const). Noise off: the mean firmware reading.
  const vb::Calibration& c = vb::reference_calibration();
  const vb::RobotParameters robot = vb::robot_a();
  vb::SimulationOptions options;
  options.noise = false;
  std::vector<cal::ChargeSample> rows;
  for (int s = 0; s < 16; ++s) {
    const vb::Run run = vb::simulate_protocol(s, robot, 1, options);
    for (const vb::Row& r : run.rows) rows.push_back({r.voltage_v, r.speed_cm_s, r.state_of_charge});
  }
  const cal::ChargeMapFit fit = cal::fit_charge_map(rows, {"virtual"});
  ASSERT_TRUE(fit.usable) << fit.message;
  const cal::ChargeMap& m = fit.map;
  ASSERT_TRUE(m.has_load()) << m.load_why;
  ASSERT_EQ(m.load_speeds_cm_s.size(), 16u);
  // The offset at speed s is (I_s - I_0) R: what the voltage sagged by beyond the sag at rest.
  const double r_ohm = c.path_resistance_ohm * robot.resistance_scale;
  double largest = 0;
  for (int s = 0; s < 16; ++s) largest = std::max(largest, std::abs(c.current_a[s] - c.current_a[0]) * r_ohm);
  ASSERT_GT(largest, 0.03);  // about 0.045 V between 0 and 5 cm/s: a sag worth modelling
  // Within 1 mV, under the firmware's 1.22 mV ADC count (a sag error the logs could show), about
  // 2 % of the largest sag: the map's knots (at most 16, at quantiles of the voltage) only
  // approximate the OCV curve's 21 linear pieces, and that approximation leaks into the offsets.
  for (int s = 0; s < 16; ++s)
    EXPECT_NEAR(m.load_offset_v[static_cast<std::size_t>(s)], (c.current_a[s] - c.current_a[0]) * r_ohm, 1e-3) << s;
  // And it matters: the map without the load term leaves several times the error.
  EXPECT_LT(m.residual_sd_with_load * 3, m.residual_sd_without_load);
  EXPECT_LT(m.delta_bic_load, -10);
}

TEST(ChargeMap, TooFewRowsOrAConstantVoltageAreRefusedWithTheReason) {
  const std::vector<cal::ChargeSample> five{{4.0, 0, 0.75}, {3.9, 0, 0.6}, {3.8, 0, 0.5}, {3.7, 0, 0.4}, {3.6, 0, 0.25}};
  const cal::ChargeMapFit few = cal::fit_charge_map(five, {});
  EXPECT_FALSE(few.usable);
  EXPECT_NE(few.message.find("too few rows with both charge and voltage_v (5)"), std::string::npos) << few.message;
  EXPECT_NE(few.message.find("at least 6"), std::string::npos) << few.message;
  const std::vector<cal::ChargeSample> flat(10, cal::ChargeSample{3.9, 2, 0.6});
  const cal::ChargeMapFit constant = cal::fit_charge_map(flat, {});
  EXPECT_FALSE(constant.usable);
  EXPECT_NE(constant.message.find("voltage_v does not vary"), std::string::npos) << constant.message;
}

TEST(ChargeMap, ConversionClampsOutsideTheRangeAndSaysWhichSide) {
  cal::ChargeMap m;
  m.knots_v = {3.5, 3.8, 4.2};
  m.knot_charge = {0.0, 0.3, 1.0};
  m.voltage_min_v = 3.5;
  m.voltage_max_v = 4.2;
  EXPECT_NEAR(cal::convert_voltage(m, 3.65, 0).charge, 0.15, 1e-12);
  EXPECT_NEAR(cal::convert_voltage(m, 4.0, 0).charge, 0.65, 1e-12);
  EXPECT_EQ(cal::convert_voltage(m, 4.0, 0).side, 0);
  EXPECT_EQ(cal::convert_voltage(m, 3.2, 0).side, -1);
  EXPECT_EQ(cal::convert_voltage(m, 3.2, 0).charge, 0.0);
  EXPECT_EQ(cal::convert_voltage(m, 4.3, 0).side, 1);
  EXPECT_EQ(cal::convert_voltage(m, 4.3, 0).charge, 1.0);
  // A load term: +0.1 V at 10 cm/s, linear from 0 at 0 cm/s; not defined beyond 10 cm/s.
  m.load_speeds_cm_s = {0, 10};
  m.load_offset_v = {0, 0.1};
  EXPECT_NEAR(cal::convert_voltage(m, 3.95, 5).charge, 0.65, 1e-12);  // 3.95 + 0.05 = 4.0 V
  EXPECT_TRUE(cal::covers_speed(m, 10));
  EXPECT_FALSE(cal::covers_speed(m, 12));
}

TEST(ChargeMap, JsonRoundTripAndAHandWrittenMapFile) {
  cal::ChargeMap m;
  m.knots_v = {3.5, 3.8, 4.2};
  m.knot_charge = {0.0, 0.3, 1.0};
  m.voltage_min_v = 3.45;
  m.voltage_max_v = 4.25;
  m.residual_sd = 0.01;
  m.max_abs_residual = 0.03;
  m.load_speeds_cm_s = {0, 10};
  m.load_offset_v = {0, 0.1};
  const nlohmann::json file{{"kind", "battery"}, {"charge_map", cal::charge_map_to_json(m)}};
  const cal::ChargeMap back = cal::charge_map_from_json(file, "b.json");
  EXPECT_EQ(back.knots_v, m.knots_v);
  EXPECT_EQ(back.knot_charge, m.knot_charge);
  EXPECT_EQ(back.load_offset_v, m.load_offset_v);
  EXPECT_EQ(back.voltage_min_v, 3.45);
  EXPECT_EQ(back.voltage_max_v, 4.25);
  EXPECT_EQ(back.residual_sd, 0.01);
  // By hand: the firmware's line, the range defaulting to the knots.
  const auto hand = nlohmann::json::parse(
      R"({"kind": "charge_map", "charge_map": {"form": "monotone_piecewise_linear", "knots_v": [3.0, 4.5], "knot_charge": [-0.5, 1.375]}})");
  const cal::ChargeMap h = cal::charge_map_from_json(hand, "map.json");
  EXPECT_NEAR(cal::convert_voltage(h, 3.988, 0).charge, firmware_charge(3.988), 1e-12);
  EXPECT_FALSE(h.has_load());
  EXPECT_TRUE(std::isnan(h.residual_sd));
}

TEST(ChargeMap, ABadMapFileNamesTheEntry) {
  auto message = [](const std::string& text) {
    try {
      cal::charge_map_from_json(nlohmann::json::parse(text), "/nonexistent/m.json");
    } catch (const epuck2::logs::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(R"({"kind": "battery"})").find("no 'charge_map' section"), std::string::npos);
  EXPECT_NE(message(R"({"charge_map": {"form": "cubic", "knots_v": [3, 4], "knot_charge": [0, 1]}})").find("form"), std::string::npos);
  EXPECT_NE(message(R"({"charge_map": {"form": "monotone_piecewise_linear", "knots_v": [3, 3], "knot_charge": [0, 1]}})")
                .find("strictly ascending"),
            std::string::npos);
  EXPECT_NE(message(R"({"charge_map": {"form": "monotone_piecewise_linear", "knots_v": [3, 4], "knot_charge": [1, 0]}})")
                .find("must not decrease"),
            std::string::npos);
  EXPECT_NE(message(R"({"charge_map": {"form": "monotone_piecewise_linear", "knots_v": [3, 4], "knot_charge": [0]}})")
                .find("one charge per knot"),
            std::string::npos);
}

// Every refusal of the map reader names its entry by JSON path (the file does not exist, so no
// line:column): the arrays' presence, type and elements, the load terms' count and order, the
// voltage range's shape and order, and an optional number that is not one.
TEST(ChargeMap, EachMalformedEntryIsRefusedAtItsJsonPath) {
  auto message = [](const std::string& charge_map) {
    try {
      cal::charge_map_from_json(nlohmann::json::parse(R"({"charge_map": {"form": "monotone_piecewise_linear", )" + charge_map + "}}"),
                                "/nonexistent/m.json");
    } catch (const epuck2::logs::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string knots = R"("knots_v": [3, 4], "knot_charge": [0, 1])";
  struct Case {
    std::string entries, path, words;
  };
  const Case cases[] = {
      {R"("knot_charge": [0, 1])", "/charge_map", "expected an array of numbers 'knots_v'"},
      {R"("knots_v": [3, 4])", "/charge_map", "expected an array of numbers 'knot_charge'"},
      {R"("knots_v": 3, "knot_charge": [0, 1])", "/charge_map/knots_v", "'knots_v' must be an array of numbers"},
      {R"("knots_v": [3, "4"], "knot_charge": [0, 1])", "/charge_map/knots_v/1", "'knots_v' must hold finite numbers"},
      {R"("knots_v": [3, 4], "knot_charge": [0, null])", "/charge_map/knot_charge/1", "'knot_charge' must hold finite numbers"},
      {R"("knots_v": [3], "knot_charge": [0])", "/charge_map/knots_v", "at least 2 knots"},
      {R"("knots_v": [3, 4, 3.5], "knot_charge": [0, 0.5, 1])", "/charge_map/knots_v/2", "strictly ascending"},
      {R"("knots_v": [3, 4, 5], "knot_charge": [0, 0.5, 0.4])", "/charge_map/knot_charge/2", "must not decrease"},
      {knots + R"(, "load_speeds_cm_s": [0, 10], "load_offset_v": [0])", "/charge_map/load_offset_v", "one load_offset_v per load speed"},
      {knots + R"(, "load_offset_v": [0])", "/charge_map/load_offset_v", "one load_offset_v per load speed"},
      {knots + R"(, "load_speeds_cm_s": [0, 10, 10], "load_offset_v": [0, 0.1, 0.2])", "/charge_map/load_speeds_cm_s/2",
       "load_speeds_cm_s must be strictly ascending"},
      {knots + R"(, "load_speeds_cm_s": [5, 0], "load_offset_v": [0, 0.1])", "/charge_map/load_speeds_cm_s/1",
       "load_speeds_cm_s must be strictly ascending"},
      {knots + R"(, "voltage_range_v": [4.2, 3.4])", "/charge_map/voltage_range_v", "[min, max] with min < max"},
      {knots + R"(, "voltage_range_v": [3.4, 3.4])", "/charge_map/voltage_range_v", "[min, max] with min < max"},
      {knots + R"(, "voltage_range_v": [3.4])", "/charge_map/voltage_range_v", "[min, max] with min < max"},
      {knots + R"(, "voltage_range_v": [3.4, 4.2, 4.3])", "/charge_map/voltage_range_v", "[min, max] with min < max"},
      {knots + R"(, "residual_sd": "small")", "/charge_map/residual_sd", "'residual_sd' must be a number"},
  };
  for (const Case& c : cases) {
    const std::string m = message(c.entries);
    EXPECT_NE(m.find(c.words), std::string::npos) << c.entries << "\n" << m;
    EXPECT_NE(m.find("JSON path " + c.path + ")"), std::string::npos) << c.entries << "\n" << m;
  }
  // The same entries, well formed, are read: the range as given, the load terms in order.
  const std::string good = message(knots + R"(, "load_speeds_cm_s": [0, 10], "load_offset_v": [0, 0.1], "voltage_range_v": [3.4, 4.2], "residual_sd": 0.01)");
  EXPECT_EQ(good, "no error");
}
