// Every refusal the libraries and the CLI can make, reached with its reason, beside the case at its
// limit that must be accepted. A scan of the product code (session 20) listed the `throw`s whose
// message no test quoted: a check dropped, inverted or moved by one at its limit would have gone
// unnoticed. Each test below writes the input by hand; the expected messages are the ones docs/
// and the functions' own comments promise, and the limits are the documented ones (a map needs 2
// knots, a battery file's 16 speeds, a tick > 0, ...).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "epuck2/calibrate/battery.hpp"
#include "epuck2/calibrate/charge_map.hpp"
#include "epuck2/coefficients/battery_tables.hpp"
#include "epuck2/coefficients/model_sets.hpp"
#include "epuck2/fit/fit_curve.hpp"
#include "epuck2/fit/parameter.hpp"
#include "epuck2/fit/problem.hpp"
#include "epuck2/fit/readings.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/logs/output.hpp"
#include "epuck2/models/battery_simulation.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"

namespace test_every_refusal_cpp {

namespace fs = std::filesystem;
using epuck2::testing::CliRun;
using nlohmann::json;
namespace logs = epuck2::logs;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// The InputError a call throws (a failure when it throws none or another type).
template <class F>
logs::InputError input_error(F f) {
  try {
    f();
  } catch (const logs::InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError";
  return logs::InputError("", 0, 0, "");
}

// ---- the log reader (lib/logs log.cpp; docs/logs.md "Header", "Rows") ----

// An empty column name: refused at its line and character column ("time_s," is 7 characters: the
// empty name starts at column 8).
TEST(Refusals, AnEmptyColumnNameIsRefusedWhereItIs) {
  const auto e = input_error([] { logs::parse_log("time_s,,sensor,value\n0,1,0,5\n", "h.csv"); });
  EXPECT_EQ(e.line(), 1);
  EXPECT_EQ(e.column(), 8);
  EXPECT_TRUE(has(e.message(), "empty column name in the header")) << e.message();
}

// A column named twice is refused at the second; letter case is ignored, and then both spellings
// are named.
TEST(Refusals, AColumnNamedTwiceIsRefusedAtTheSecond) {
  const std::string same = "time_s,distance_m,sensor,value,value\n0,0.01,0,5,6\n";
  const auto e = input_error([&] { logs::parse_log(same, "d.csv", logs::Kind::proximity); });
  EXPECT_EQ(e.line(), 1);
  EXPECT_EQ(e.column(), 32);  // "time_s,distance_m,sensor,value," is 31 characters
  EXPECT_TRUE(has(e.message(), "column 'value' appears twice in the header")) << e.message();
  EXPECT_FALSE(has(e.message(), "letter case")) << e.message();
  const auto c = input_error([] {
    logs::parse_log("time_s,distance_m,sensor,Value,value\n0,0.01,0,5,6\n", "c.csv", logs::Kind::proximity);
  });
  EXPECT_TRUE(has(c.message(), "(as 'Value' and 'value': letter case is ignored)")) << c.message();
}

// No header: an empty file, or one of comments and blank lines only, is refused at line 1; a
// header without rows at the header's line.
TEST(Refusals, AFileWithoutHeaderOrRowsIsRefused) {
  for (const std::string text : {std::string(), std::string("# obstacle_distance_m: 0.05\n\n# a comment\n")}) {
    const auto e = input_error([&] { logs::parse_log(text, "e.csv", logs::Kind::proximity); });
    EXPECT_EQ(e.line(), 1);
    EXPECT_TRUE(has(e.message(), "empty file: expected a header line and data rows")) << e.message();
  }
  const auto h = input_error([] { logs::parse_log("# a comment\ntime_s,distance_m,sensor,value\n", "h.csv", logs::Kind::proximity); });
  EXPECT_EQ(h.line(), 2);
  EXPECT_TRUE(has(h.message(), "no data rows after the header")) << h.message();
}

// --skip-bad-rows that leaves nothing: refused, saying how many rows were skipped and where the
// first was; one good row left is a log.
TEST(Refusals, SkippingEveryRowIsRefusedOneRowLeftIsALog) {
  logs::ReadOptions skip;
  skip.skip_bad_rows = true;
  const std::string head = "time_s,distance_m,sensor,value\n";
  const auto e = input_error([&] { logs::parse_log(head + "0,0.01,0,abc\n0.1,0.01,0,\n", "s.csv", logs::Kind::proximity, skip); });
  EXPECT_TRUE(has(e.message(), "no data rows left: all 2 were skipped as bad (--skip-bad-rows); the first, line 2, column 10"))
      << e.message();
  const logs::Log one = logs::parse_log(head + "0,0.01,0,abc\n0.1,0.01,0,7\n", "s.csv", logs::Kind::proximity, skip);
  ASSERT_EQ(one.rows(), 1u);
  EXPECT_EQ(one.col("value")[0], 7.0);
  ASSERT_EQ(one.skipped.size(), 1u);
  EXPECT_EQ(one.skipped[0].line, 2);
}

// A column the log does not hold, or a metadata line it lacks, is an error naming it.
TEST(Refusals, AMissingColumnOrMetadataLineIsNamed) {
  const logs::Log log = logs::parse_log("# robot: r1\ntime_s,distance_m,sensor,value\n0,0.01,0,5\n", "m.csv", logs::Kind::proximity);
  const auto c = input_error([&] { (void)log.col("angle_deg"); });
  EXPECT_TRUE(has(c.message(), "no numeric column 'angle_deg'")) << c.message();
  const auto m = input_error([&] { (void)log.metadata_number("obstacle_distance_m"); });
  EXPECT_EQ(m.line(), 2);  // the header's line: the metadata belongs before it
  EXPECT_TRUE(has(m.message(), "missing metadata line '# obstacle_distance_m: VALUE' (before the header)")) << m.message();
}

// ---- the fit engine's argument checks (lib/fit) ----

TEST(Refusals, TheEnginesListsMustAgreeInLength) {
  using namespace epuck2::fit;
  EXPECT_THROW(Channels(std::vector<Channel>{}), std::invalid_argument);
  EXPECT_NO_THROW(Channels(std::vector<Channel>(1)));

  ResidualBlock latent;
  latent.residuals = 3;
  latent.sizes = {1};
  latent.evaluate = [](double const* const*, double*, double**) { return true; };
  EXPECT_THROW(readings_block(latent, {1, 2}, std::vector<int>{}, Channels(std::vector<Channel>(1))), std::invalid_argument);
  EXPECT_THROW(readings_block(latent, {1, 2, 3}, std::vector<int>{0, 0}, Channels(std::vector<Channel>(1))), std::invalid_argument);
  EXPECT_NO_THROW(readings_block(latent, {1, 2, 3}, std::vector<int>{}, Channels(std::vector<Channel>(1))));
  EXPECT_NO_THROW(readings_block(latent, {1, 2, 3}, std::vector<int>{0, 0, 0}, Channels(std::vector<Channel>(1))));

  const std::vector<Censoring> none3(3, Censoring::none);
  EXPECT_THROW(readings_block(latent, {1, 2}, std::vector<Censoring>(2, Censoring::none), {1, 1}, 1.0), std::invalid_argument);
  EXPECT_THROW(readings_block(latent, {1, 2, 3}, std::vector<Censoring>(2, Censoring::none), {1, 1, 1}, 1.0), std::invalid_argument);
  EXPECT_THROW(readings_block(latent, {1, 2, 3}, none3, {1, 1}, 1.0), std::invalid_argument);
  EXPECT_NO_THROW(readings_block(latent, {1, 2, 3}, none3, {1, 1, 1}, 1.0));
}

TEST(Refusals, AParameterThatIsNotThereIsNamedWithTheKnownOnes) {
  using namespace epuck2::fit;
  try {
    free_parameters({"a", "b"}, {1.0});
    ADD_FAILURE() << "2 names for 1 start accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(has(e.what(), "2 parameter names for 1 starts")) << e.what();
  }
  const auto p = free_parameters({"a", "b"}, {1.0, 2.0});
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(index_of(p, "b"), 1u);
  try {
    (void)index_of(p, "c");
    ADD_FAILURE() << "no parameter c found";
  } catch (const std::out_of_range& e) {
    EXPECT_TRUE(has(e.what(), "no parameter named 'c' (the parameters are: a, b)")) << e.what();
  }

  FitResult r;
  r.parameters = {ParameterEstimate("a", 1.0, 0.5), ParameterEstimate("b", 2.0, 0.25)};
  EXPECT_EQ(r.std_error("b"), 0.25);
  EXPECT_EQ(r.value("a"), 1.0);
  try {
    (void)r.std_error("B");
    ADD_FAILURE() << "B found";
  } catch (const std::out_of_range& e) {
    EXPECT_TRUE(has(e.what(), "no parameter named 'B' in this fit (its parameters are: a, b)")) << e.what();
  }
  FitResult empty;
  try {
    (void)empty.value("a");
    ADD_FAILURE() << "a found in an empty fit";
  } catch (const std::out_of_range& e) {
    EXPECT_TRUE(has(e.what(), "(its parameters are: none)")) << e.what();
  }
}

// ---- the battery simulation's tick (lib/models battery_simulation.hpp) ----

TEST(Refusals, TheBatteryTickMustBeAFinitePositiveNumber) {
  namespace mb = epuck2::models::battery;
  const std::vector<mb::ProfilePoint> profile{{0, 5}, {1, 5}};
  for (const double dt : {0.0, -0.1, std::nan(""), std::numeric_limits<double>::infinity()})
    EXPECT_THROW(mb::simulate_discharge(mb::Model::linear, mb::Behaviour::corrected, mb::plugin_tables(), profile, dt), std::invalid_argument)
        << dt;
  // 1 s of a 0.25 s tick: the start and 4 ticks; 0.3 s of a 0.1 s tick: the start and 3 ticks
  // (0.3 / 0.1 is 2.9999999999999996 in doubles: the third tick is still in the profile); an empty
  // profile: none.
  const auto quarter = mb::simulate_discharge(mb::Model::linear, mb::Behaviour::corrected, mb::plugin_tables(), profile, 0.25);
  ASSERT_EQ(quarter.size(), 5u);
  EXPECT_EQ(quarter.front().time_s, 0.0);
  EXPECT_EQ(quarter.back().time_s, 1.0);
  const auto tenth =
      mb::simulate_discharge(mb::Model::linear, mb::Behaviour::corrected, mb::plugin_tables(), {{0, 5}, {0.3, 5}}, 0.1);
  ASSERT_EQ(tenth.size(), 4u);
  EXPECT_NEAR(tenth.back().time_s, 0.3, 1e-12);
  try {
    mb::simulate_discharge(mb::Model::linear, mb::Behaviour::corrected, mb::plugin_tables(), {{0, 0}, {1e300, 0}}, 1.0);
    ADD_FAILURE() << "1e300 ticks accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(has(e.what(), "more than 2^53 ticks")) << e.what();
  }
  EXPECT_TRUE(mb::simulate_discharge(mb::Model::linear, mb::Behaviour::corrected, mb::plugin_tables(), {}, 0.25).empty());
}

// ---- the voltage->charge map's file (docs/fitting.md: at least 2 knots, strictly ascending) ----

TEST(Refusals, AChargeMapNeedsTwoAscendingKnotsEachWithItsCharge) {
  namespace cal = epuck2::calibrate;
  // A map file as docs/coefficient-files.md#charge-map describes it, written by hand.
  const json two = {{"kind", "charge_map"},
                    {"charge_map", {{"form", "monotone_piecewise_linear"}, {"knots_v", {3.5, 4.1}}, {"knot_charge", {0.0, 1.0}}}}};
  const cal::ChargeMap back = cal::charge_map_from_json(two, "m.json");
  EXPECT_EQ(back.knots_v, (std::vector<double>{3.5, 4.1}));
  EXPECT_EQ(back.knot_charge, (std::vector<double>{0.0, 1.0}));
  EXPECT_EQ(back.voltage_min_v, 3.5);  // no voltage_range_v: the knots' ends
  EXPECT_EQ(back.voltage_max_v, 4.1);
  // Halfway between the knots, no load term: half the charge.
  EXPECT_NEAR(cal::convert_voltage(back, 3.8, 0.0).charge, 0.5, 1e-12);

  auto refused = [](json file, const std::string& key, const json& value, const std::string& why, const std::string& where) {
    if (value.is_null()) file["charge_map"].erase(key);
    else file["charge_map"][key] = value;
    const auto e = input_error([&] { cal::charge_map_from_json(file, "m.json"); });
    EXPECT_TRUE(has(e.what(), why)) << key << ": " << e.what();
    EXPECT_TRUE(has(e.what(), "(at JSON path " + where + ")")) << key << ": " << e.what();
  };
  json one = two;
  one["charge_map"]["knot_charge"] = {0.5};
  refused(one, "knots_v", {3.5}, "charge_map: expected at least 2 knots", "/charge_map/knots_v");
  refused(two, "knots_v", {3.5, 3.5}, "charge_map: knots_v must be strictly ascending", "/charge_map/knots_v/1");
  refused(two, "knot_charge", {0.6, 0.4}, "charge_map: knot_charge must not decrease", "/charge_map/knot_charge/1");
  refused(two, "knot_charge", nullptr, "charge_map: expected an array of numbers 'knot_charge'", "/charge_map");
  refused(two, "knot_charge", {0.0}, "charge_map: expected one charge per knot (2)", "/charge_map/knot_charge");
  refused(two, "voltage_range_v", {4.1, 4.1}, "voltage_range_v must be [min, max] with min < max", "/charge_map/voltage_range_v");
  refused(two, "load_speeds_cm_s", {5.0}, "charge_map: expected one load_offset_v per load speed", "/charge_map/load_offset_v");
  json flat = two;
  flat["charge_map"]["knot_charge"] = {0.5, 0.5};  // equal charges: flat, allowed
  EXPECT_NO_THROW(cal::charge_map_from_json(flat, "m.json"));
}

// ---- the battery tables' file (docs/models.md: 16 speeds 0..15 cm/s; a segment runs forward) ----

TEST(Refusals, BatteryTablesHoldSixteenSpeedsAndSegmentsRunForward) {
  namespace co = epuck2::coefficients;
  namespace mb = epuck2::models::battery;
  const json full = co::battery_tables_to_json(mb::plugin_tables());
  ASSERT_EQ(full.at("speeds").size(), 16u);
  EXPECT_NO_THROW(co::battery_tables_from_json(full, "t.json"));
  json fifteen = full;
  fifteen["speeds"].erase(15);
  const auto e = input_error([&] { co::battery_tables_from_json(fifteen, "t.json"); });
  EXPECT_TRUE(has(e.what(), "expected 16 entries in 'speeds' (0..15 cm/s), found 15")) << e.what();

  // The partial reader (a calibration of some speeds over the plug-in's): 1 to 16.
  co::TableSources sources;
  json one = full;
  while (one["speeds"].size() > 1) one["speeds"].erase(1);
  EXPECT_NO_THROW(co::battery_tables_from_json(one, "t.json", sources));
  json none = full;
  none["speeds"] = json::array();
  const auto z = input_error([&] { co::battery_tables_from_json(none, "t.json", sources); });
  EXPECT_TRUE(has(z.what(), "expected 1 to 16 entries in 'speeds' (0..15 cm/s), found 0")) << z.what();
  json seventeen = full;
  seventeen["speeds"].push_back(full["speeds"][15]);
  const auto s = input_error([&] { co::battery_tables_from_json(seventeen, "t.json", sources); });
  EXPECT_TRUE(has(s.what(), "found 17")) << s.what();
}

// ---- battery calibration's runs (lib/calibrate battery_fit.cpp) ----

TEST(Refusals, ABatteryRunMustBeABatteryLogThatLasts) {
  namespace cal = epuck2::calibrate;
  const logs::Log ground = logs::parse_log("grey,sensor,value\n0.5,0,500\n", "g.csv", logs::Kind::ground);
  const auto g = input_error([&] { cal::battery_runs({ground}); });
  EXPECT_TRUE(has(g.what(), "is not a battery log (time_s, speed_cm_s, charge)")) << g.what();

  const logs::Log instant = logs::parse_log("time_s,speed_cm_s,charge\n0,5,1\n", "b.csv", logs::Kind::battery);
  const auto i = input_error([&] { cal::battery_runs({instant}); });
  EXPECT_EQ(i.line(), 2);
  EXPECT_TRUE(has(i.what(), "column 'time_s': the run must last longer than 0 s")) << i.what();
  const logs::Log lasts = logs::parse_log("time_s,speed_cm_s,charge\n0,5,1\n10,5,0.99\n", "b.csv", logs::Kind::battery);
  const auto runs = cal::battery_runs({lasts});
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].lifetime_s, 10.0);
  EXPECT_EQ(runs[0].speed_cm_s, 5.0);
}

// ---- coefficient files' robot sets (docs/argos.md: robot_map only with robot="auto") ----

TEST(Refusals, ARobotMapWithoutAutoOrWithoutAMatchIsRefused) {
  namespace co = epuck2::coefficients;
  const json root = {{"kind", "ground"}, {"robots", {{"a", json::object()}, {"b", json::object()}}}};
  const auto fixed = input_error([&] { co::choose_robot(root, "m.json", "a", "ep*:b", "ep1"); });
  EXPECT_TRUE(has(fixed.what(), "robot_map is used only with robot=\"auto\"")) << fixed.what();
  EXPECT_TRUE(has(fixed.what(), "/robots")) << fixed.what();
  const auto no_match = input_error([&] { co::choose_robot(root, "m.json", "auto", "fb*:b", "ep1"); });
  EXPECT_TRUE(has(no_match.what(), "no robot_map pattern matches the entity 'ep1' (robot_map \"fb*:b\")")) << no_match.what();
  EXPECT_EQ(co::choose_robot(root, "m.json", "auto", "fb*:a,ep*:b", "ep1").robot, "b");  // the first that matches
  EXPECT_EQ(co::choose_robot(root, "m.json", "a", "", "ep1").robot, "a");
}

TEST(Refusals, ACoefficientFileMustBeAJsonObject) {
  const fs::path p = fs::temp_directory_path() / ("epuck2_refusals_array_" + std::to_string(::getpid()) + ".json");
  std::ofstream(p) << "[1, 2]\n";
  const auto e = input_error([&] { epuck2::coefficients::shared_json_file(p.string()); });
  EXPECT_TRUE(has(e.what(), "not a coefficient file (expected a JSON object)")) << e.what();
  std::ofstream(p) << "{\"kind\": \"ground\"}\n";
  EXPECT_EQ(epuck2::coefficients::shared_json_file(p.string())->at("kind"), "ground");
  fs::remove(p);
}

// ---- the output stage (lib/logs output.cpp: every file of a run written to a temporary first) ----

TEST(Refusals, TheOutputStageRefusesWhatCannotBeAFileOfThisRun) {
  const fs::path dir = fs::temp_directory_path() / ("epuck2_refusals_out_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "sub");
  auto message = [](auto f) {
    try {
      f();
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  {
    logs::OutputStage s;
    EXPECT_TRUE(has(message([&] { s.write("", "x"); }), "an output file name is empty"));
    EXPECT_TRUE(has(message([&] { s.write((dir / "sub").string(), "x"); }), "is a folder, not a file"));
    EXPECT_TRUE(has(message([&] { s.write((dir / "none" / "a.txt").string(), "x"); }), "does not exist"));
    s.write((dir / "a.txt").string(), "one");
    const std::string twice = message([&] { s.write((dir / "sub" / ".." / "a.txt").string(), "two"); });
    EXPECT_TRUE(has(twice, "given for two outputs of the same run")) << twice;
    s.write((dir / "b.txt").string(), "two");
    s.commit();
  }
  {
    logs::OutputStage s;  // written in place (a device): the same device twice is refused too
    s.write("/dev/null", "x");
    const std::string twice = message([&] { s.write("/dev/null", "y"); });
    EXPECT_TRUE(has(twice, "given for two outputs of the same run")) << twice;
  }
  EXPECT_EQ(epuck2::testing::slurp(dir / "a.txt"), "one");
  EXPECT_EQ(epuck2::testing::slurp(dir / "b.txt"), "two");
  fs::remove_all(dir);
}

// ---- the CLI's usage errors (docs/cli.md) ----

class RefusalsCli : public epuck2::testing::CliTest {};

TEST_F(RefusalsCli, RequiredOptionsAreNamed) {
  const CliRun g = run("generate ground");
  EXPECT_EQ(g.exit_code, 2);
  EXPECT_TRUE(has(g.err, "--out-dir DIR is required")) << g.err;
  const CliRun p = run("simulate battery --model linear");
  EXPECT_EQ(p.exit_code, 2);
  EXPECT_TRUE(has(p.err, "--profile is required")) << p.err;
  const std::string profile = write("p.csv", "time_s,speed_cm_s\n0,5\n10,5\n");
  const CliRun m = run("simulate battery --profile \"" + profile + "\"");
  EXPECT_EQ(m.exit_code, 2);
  EXPECT_TRUE(has(m.err, "--model is required with --profile")) << m.err;
  const CliRun ok = run("simulate battery --profile \"" + profile + "\" --model linear");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
}

TEST_F(RefusalsCli, AnUnknownSimulatedKindIsNamedWithTheNearestKnown) {
  const CliRun r = run("simulate groud --like x.csv");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(has(r.err, "simulate: unknown kind 'groud'; did you mean 'ground'?")) << r.err;
  const CliRun far = run("simulate zzzzzzzz --like x.csv");
  EXPECT_EQ(far.exit_code, 2);
  EXPECT_TRUE(has(far.err, "simulate: unknown kind 'zzzzzzzz'; kinds that can be simulated: ")) << far.err;
  EXPECT_FALSE(has(far.err, "did you mean")) << far.err;
}

}  // namespace test_every_refusal_cpp
