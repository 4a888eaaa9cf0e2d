// Round 19 of the fresh slips (bench/fresh-slips.md): a test for each slip's behaviour, written
// during the round's run (after its GO: not in the run that scores it). Every expected value comes
// from the docs or the paper, is counted by the test from the files it writes, or is worked by hand
// in the comment beside it, never from the code under test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <variant>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "epuck2/coefficients/battery_tables.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/fit/report.hpp"
#include "epuck2/fit/robust.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/models/proximity.hpp"
#include "seeded_normal.hpp"
#include "../lib/diagnose/src/problem.hpp"

namespace test_round_nineteen_cpp {

namespace fs = std::filesystem;
using epuck2::testing::CliRun;
using epuck2::testing::slurp;
using nlohmann::json;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

fs::path raw(const std::string& kind, const std::string& file) { return fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / kind / file; }

// ---- lib/models ----

// Without the incidence effect the plug-in's model ignores the angle (paper Eq. 1 has none): a
// surface at 90 degrees or beyond reads as one facing the sensor. At 0.01 m: 4095 (197.8633e-4 -
// 0.3047182 + 1.011635) = 4095 x 0.72670313 = 2975.85 counts.
TEST(RoundNineteen, WithoutTheIncidenceEffectTheAngleIsIgnoredEvenAtNinetyDegrees) {
  namespace s = epuck2::models::sensors;
  const s::ProximityEffects<double> none{};
  for (const double cos_incidence : {1.0, 0.5, 0.0, -0.5})
    EXPECT_NEAR(s::proximity_mean_raw(s::kPluginProximity, none, 0, 0.01, cos_incidence), 4095 * 0.72670313, 1e-3) << cos_incidence;
}

// ---- lib/fit report.hpp: the reports' number formatting (docs/fitting.md, "How numbers are printed") ----

TEST(RoundNineteen, UnitsGetSquaresAndCubesAsSuperscripts) {
  EXPECT_EQ(epuck2::fit::pretty_unit("charge/s^3"), "charge/s³");
  EXPECT_EQ(epuck2::fit::pretty_unit("counts^2"), "counts²");
  EXPECT_EQ(epuck2::fit::pretty_unit("m^4"), "m^4");
}

// A value is printed to the place of its error's second significant digit: an error of 230 is
// "230" (tens), so 19743 is "19740", with no decimals.
TEST(RoundNineteen, AValueBesideAnErrorOfTensHasNoDecimals) {
  EXPECT_EQ(epuck2::fit::format_uncertain(19743.0, 230.0, "s"), "19740 ± 230 s");
  EXPECT_EQ(epuck2::fit::format_uncertain(19743.0, 2.3, "s"), "19743.0 ± 2.3 s");
}

// AIC and BIC: with no residual at all the reason is "no residual"; with residuals summing to 0
// (a fit through every reading) it is the RSS's.
TEST(RoundNineteen, InformationCriteriaSayWhyTheyAreUndefined) {
  const auto none = epuck2::fit::format_information_criteria(epuck2::fit::fit_statistics(0, 1, 0.0, std::nan("")), 1);
  EXPECT_TRUE(has(none, "(no residual)")) << none;
  const auto exact = epuck2::fit::format_information_criteria(epuck2::fit::fit_statistics(5, 2, 0.0, 1.0), 1);
  EXPECT_FALSE(has(exact, "no residual")) << exact;
  EXPECT_TRUE(has(exact, "undefined")) << exact;
}

// ---- lib/coefficients ----

// A robot's set is read with the file's pooled set checked too (docs/coefficient-files.md: the
// same file must be refused by every reader): a pooled gain of -5 is refused when robot r1 is asked for.
TEST(RoundNineteen, AskingForARobotStillChecksThePooledSet) {
  const json j = {{"kind", "ground"},
                  {"parameters", {{"gain", -5.0}, {"offset", 0.0}}},
                  {"robots", {{"r1", {{"parameters", {{"gain", 1000.0}, {"offset", 10.0}}}}}}}};
  EXPECT_THROW(epuck2::coefficients::ground_model_from_json(j, "g.json", "r1"), epuck2::logs::InputError);
  json ok = j;
  ok["parameters"]["gain"] = 900.0;
  const auto m = epuck2::coefficients::ground_model_from_json(ok, "g.json", "r1");
  EXPECT_EQ(m.sensors[0].gain_raw, 1000.0);
  EXPECT_EQ(m.sensors[0].offset_raw, 10.0);
}

// A standard error of exactly 0 (a value fixed by the protocol) is not negative: read.
TEST(RoundNineteen, AStandardErrorOfZeroIsRead) {
  const json j = {{"kind", "ground"}, {"parameters", {{"gain", 1000.0}, {"offset", 10.0}}}, {"std_errors", {{"gain", 0.0}, {"offset", 0.5}}}};
  EXPECT_NO_THROW(epuck2::coefficients::ground_model_from_json(j, "g.json"));
  json negative = j;
  negative["std_errors"]["gain"] = -0.1;
  EXPECT_THROW(epuck2::coefficients::ground_model_from_json(negative, "g.json"), epuck2::logs::InputError);
}

// A partial battery file (tables at some speeds): its one entry at 5 cm/s is the table at 5 cm/s,
// the plug-in's published one stays at 0 cm/s.
TEST(RoundNineteen, APartialBatteryFilesEntryIsItsSpeedsTable) {
  namespace co = epuck2::coefficients;
  namespace mb = epuck2::models::battery;
  const mb::Tables& plugin = mb::plugin_tables();
  mb::CubicRow cubic = plugin.cubic[5];
  cubic.d = 0.9;  // differs from every published row's
  const json entry = co::battery_speed_to_json(5.0, cubic, plugin.linear_slope_per_s[5], plugin.segments[5], 0.01);
  const json file = {{"kind", "battery"}, {"speeds", json::array({entry})}};
  co::TableSources sources;
  const mb::Tables t = co::battery_tables_from_json(file, "b.json", sources);
  EXPECT_EQ(t.cubic[5].d, 0.9);
  EXPECT_EQ(t.cubic[0].d, plugin.cubic[0].d);
  EXPECT_EQ(t.cubic[0].a, plugin.cubic[0].a);
  ASSERT_EQ(sources.fitted_speeds, std::vector<int>{5});
}

// ---- lib/logs ----

// A last row without a line end is a row (docs/logs.md: any line end, or none at the end).
TEST(RoundNineteen, ALastRowWithoutALineEndIsKept) {
  const auto log = epuck2::logs::parse_log("grey,sensor,value\n0,0,50\n1,0,900", "g.csv", epuck2::logs::Kind::ground);
  ASSERT_EQ(log.rows(), 2u);
  EXPECT_EQ(log.col("value")[1], 900.0);
  const auto one = epuck2::logs::parse_log("grey,sensor,value\n0.5,1,450", "g.csv", epuck2::logs::Kind::ground);
  ASSERT_EQ(one.rows(), 1u);
  EXPECT_EQ(one.col("sensor")[0], 1.0);
}

class RoundNineteenCli : public epuck2::testing::CliTest {};

// A number too large for a double is located at its first character, the minus sign of a negative
// one: `{"kind": "ground", "parameters": {"gain": -1e999, "offset": 0}}` has the '-' at column 43.
TEST_F(RoundNineteenCli, ANegativeNumberTooLargeIsLocatedAtItsSign) {
  const std::string text = R"({"kind": "ground", "parameters": {"gain": -1e999, "offset": 0}})";
  ASSERT_EQ(text.find('-'), 42u);
  const std::string file = write("g.json", text + "\n");
  const CliRun r = run("simulate ground --like \"" + raw("ground", "ground_virtual-epuck2-1.csv").string() + "\" --coefficients \"" +
                       file + "\" -o \"" + dir_.string() + "/out.csv\"");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(has(r.err, file + ":1:43")) << r.err;
}

// ---- lib/calibrate: the battery report ----

// Two runs at one speed that end at the same time: the lifetime's error is 0 because they agree,
// not because there is one run.
TEST_F(RoundNineteenCli, TwoRunsEndingTogetherAreNotCalledTheOnlyRun) {
  // The second run: the first's rows with ±0.003 on alternate charges, the same stop time.
  const std::string a = raw("battery", "robot-a_speed-05.csv").string();
  std::istringstream in(slurp(a));
  std::string text;
  bool header = false;
  int row = 0;
  for (std::string l; std::getline(in, l);) {
    if (l.empty() || l[0] == '#' || !header) {
      header = header || (!l.empty() && l[0] != '#');
      text += l + "\n";
      continue;
    }
    std::vector<std::string> c;
    std::stringstream cells(l);
    for (std::string cell; std::getline(cells, cell, ',');) c.push_back(cell);
    char charge[32];
    std::snprintf(charge, sizeof charge, "%.6f", std::stod(c[2]) + (row++ % 2 ? 0.003 : -0.003));
    text += c[0] + "," + c[1] + "," + charge + "," + c[3] + "\n";
  }
  const std::string copy = write("again.csv", text);
  // (Runs this close are replicates far tighter than the cubic's misfit at the start transient:
  // --accept-misfit, so that the report is printed.)
  const CliRun t = run("battery --accept-misfit \"" + a + "\" \"" + copy + "\"");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_TRUE(has(t.out, "Speed 5.00 cm/s: 2 runs")) << t.out.substr(0, 2000);
  EXPECT_FALSE(has(t.out, "the only run's log")) << t.out.substr(0, 2000);
}

/// A voltage-only battery log at 5 cm/s: one row every 10 s, voltages given.
std::string voltage_log(const std::vector<double>& volts) {
  std::string text = "time_s,speed_cm_s,voltage_v\n";
  for (std::size_t i = 0; i < volts.size(); ++i) text += std::to_string(10 * i) + ",5," + std::to_string(volts[i]) + "\n";
  return text;
}

const char* kHandMap =
    R"({"kind": "charge_map", "charge_map": {"form": "monotone_piecewise_linear", "knots_v": [3.5, 4.1], "knot_charge": [0.0, 1.0]}})";

// A map given with --charge-map: the coefficient file says which (from_file), and counts the rows
// clamped above and below its range apart: 3 voltages above 4.1 V and none below.
TEST_F(RoundNineteenCli, AGivenMapIsNamedAndItsClampedRowsCountedBySide) {
  const std::string map = write("map.json", kHandMap);
  std::vector<double> volts{4.15, 4.14, 4.12};
  for (int i = 0; i < 60; ++i) volts.push_back(4.09 - 0.009 * i);
  const std::string log = write("v.csv", voltage_log(volts));
  const CliRun j = run("battery --charge-map \"" + map + "\" --json \"" + log + "\"");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const json r = json::parse(j.out);
  EXPECT_EQ(r.at("charge_map").at("from_file"), map);
  const json& c = r.at("charge_conversion");
  EXPECT_EQ(c.at("clamped_above_range"), 3);
  EXPECT_EQ(c.at("clamped_below_range"), 0);
  // A map fitted to the logs names no file.
  const std::string both = raw("battery", "robot-a_speed-05.csv").string();
  const CliRun f = run("battery --json \"" + both + "\"");
  ASSERT_EQ(f.exit_code, 0) << f.err;
  EXPECT_FALSE(json::parse(f.out).at("charge_map").contains("from_file")) << json::parse(f.out).at("charge_map").dump();
}

// ---- lib/calibrate: robots ----

// Two logs of one robot are one robot: robot 1's log, robot 2's, and a copy of robot 1's under
// another name give two robots (robot 1 with both its logs), and the robots' spread has one degree
// of freedom (two robots), not two.
TEST_F(RoundNineteenCli, TwoLogsOfOneRobotAreOneRobot) {
  const std::string one = raw("ground", "ground_virtual-epuck2-1.csv").string();
  const std::string two = raw("ground", "ground_virtual-epuck2-2.csv").string();
  const std::string again = write("again.csv", slurp(one));
  const CliRun j = run("ground --json \"" + one + "\" \"" + two + "\" \"" + again + "\"");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const json r = json::parse(j.out);
  const json& robots = r.at("robots");
  ASSERT_EQ(robots.size(), 2u) << robots.dump().substr(0, 400);
  ASSERT_TRUE(robots.contains("virtual-epuck2-1"));
  EXPECT_EQ(robots.at("virtual-epuck2-1").at("logs").size(), 2u) << robots.at("virtual-epuck2-1").at("logs").dump();
  ASSERT_FALSE(r.at("robot_spread").empty());
  for (const json& p : r.at("robot_spread")) EXPECT_EQ(p.at("dof"), 1) << p.dump();
  // The figures tell the robots apart (docs/cli.md, "Figures"): one legend entry per robot, each
  // once, in the gnuplot script the run keeps with EPUCK2_PLOT_SCRIPT_DIR.
  for (const std::string kind : {"ground", "proximity"}) {
    SCOPED_TRACE(kind);
    const std::string a = raw(kind, kind + "_virtual-epuck2-1.csv").string(), b = raw(kind, kind + "_virtual-epuck2-2.csv").string();
    const std::string c = write(kind + "_again.csv", slurp(a));
    const fs::path scripts = dir_ / (kind + "_scripts");
    fs::create_directories(scripts);
    const std::string cmd = "EPUCK2_PLOT_SCRIPT_DIR='" + scripts.string() + "' '" EPUCK2_FIT_EXE "' " + kind + " --plot '" +
                            (dir_ / (kind + ".svg")).string() + "' '" + a + "' '" + b + "' '" + c + "' > /dev/null 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    const std::string gp = slurp(scripts / (kind + ".svg.gp"));
    ASSERT_FALSE(gp.empty());
    auto count = [&gp](const std::string& what) {
      std::size_t n = 0;
      for (std::size_t at = gp.find(what); at != std::string::npos; at = gp.find(what, at + 1)) ++n;
      return n;
    };
    EXPECT_EQ(count("title \"robot virtual-epuck2-1\""), count("title \"robot virtual-epuck2-2\""));
    EXPECT_GE(count("title \"robot virtual-epuck2-2\""), 1u);
    EXPECT_EQ(count("title \"robot "), 2 * count("title \"robot virtual-epuck2-2\""));
  }
}

// ---- apps: --accept-misfit ----

// Readings that follow grey² (50 + 900 grey², 20 replicates of noise sd 3 at each of 11 greys): the
// ground's straight line misses them by many replicate sd; -o refuses to write the calibration
// (exit 1) unless --accept-misfit is given.
TEST_F(RoundNineteenCli, AMisfitIsWrittenOnlyWithAcceptMisfit) {
  epuck2::testing::Normal noise(19);
  std::string text = "grey,sensor,value\n";
  for (int g = 0; g <= 10; ++g)
    for (int s = 0; s < 3; ++s)
      for (int k = 0; k < 20; ++k) {
        const double grey = g / 10.0;
        text += std::to_string(grey) + "," + std::to_string(s) + "," + std::to_string(std::lround(50 + 900 * grey * grey + 3 * noise())) + "\n";
      }
  const std::string log = write("sq.csv", text);
  const std::string out = dir_.string() + "/g.json";
  const CliRun refused = run("ground -o \"" + out + "\" \"" + log + "\"");
  EXPECT_EQ(refused.exit_code, 1) << refused.err;
  EXPECT_TRUE(has(refused.err, "Nothing was written; --accept-misfit writes it anyway.")) << refused.err;
  EXPECT_FALSE(fs::exists(out));
  const CliRun accepted = run("ground --accept-misfit -o \"" + out + "\" \"" + log + "\"");
  EXPECT_EQ(accepted.exit_code, 0) << accepted.err;
  EXPECT_TRUE(fs::exists(out));
  EXPECT_TRUE(has(slurp(out), "accepted by --accept-misfit")) << slurp(out).substr(0, 300);
}

// ---- the diagnosis ----

// A single-row battery log beside a full run: its row is compared too (charge 1.0 at 0 s: the
// simulation's start).
TEST_F(RoundNineteenCli, ASingleRowBatteryLogIsCompared) {
  const std::string full = raw("battery", "robot-a_speed-05.csv").string();
  std::size_t rows = 0;
  {
    std::istringstream in(slurp(full));
    bool header = false;
    for (std::string l; std::getline(in, l);) {
      if (l.empty() || l[0] == '#') continue;
      if (!header) {
        header = true;
        continue;
      }
      ++rows;
    }
  }
  // docs/logs.md: a run's last row is the moment it stopped (simulated, not compared): the full run
  // compares rows - 1 readings; a log of one row has no stop to leave out, its one row is compared.
  const CliRun alone = run("diagnose --json \"" + full + "\"");
  ASSERT_EQ(alone.exit_code, 0) << alone.err;
  EXPECT_EQ(json::parse(alone.out).at("rows").get<std::size_t>(), rows);
  EXPECT_EQ(json::parse(alone.out).at("residuals").get<std::size_t>(), rows - 1);
  const std::string one = write("one.csv", "time_s,speed_cm_s,charge\n0,5,1.0\n");
  const CliRun j = run("diagnose --json \"" + full + "\" \"" + one + "\"");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  EXPECT_EQ(json::parse(j.out).at("rows").get<std::size_t>(), rows + 1);
  EXPECT_EQ(json::parse(j.out).at("residuals").get<std::size_t>(), rows);
}

// A base model of another kind is refused naming both kinds, each as what it is.
TEST(RoundNineteen, ABaseModelOfAnotherKindIsRefusedNamingBoth) {
  const auto log = epuck2::logs::parse_log("grey,sensor,value\n0,0,50\n1,0,900\n0,1,50\n1,1,900\n", "g.csv", epuck2::logs::Kind::ground);
  epuck2::diagnose::Options o;
  o.base_model = epuck2::models::sensors::LightModel{};
  std::string why;
  EXPECT_EQ(epuck2::diagnose::detail::make_problem({log}, o, why), nullptr);
  EXPECT_EQ(why, "the base model given is of the kind light, the logs of the kind ground");
}

// A diagnosis file's discharge model is the base's when --battery-model is not given; the option
// overrides it.
TEST_F(RoundNineteenCli, ADiagnosisFilesDischargeModelIsUsedUnlessTheOptionGivesOne) {
  const std::string log = raw("battery", "robot-a_speed-05.csv").string();
  const std::string diag = dir_.string() + "/d.json";
  const CliRun first = run("diagnose --battery-model linear -o \"" + diag + "\" \"" + log + "\"");
  ASSERT_EQ(first.exit_code, 0) << first.err;
  ASSERT_EQ(json::parse(slurp(diag)).at("battery_model"), "linear");
  const CliRun again = run("diagnose --json --coefficients \"" + diag + "\" \"" + log + "\"");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(json::parse(again.out).at("battery_model"), "linear");
  const CliRun simple = run("diagnose --json --battery-model simple --coefficients \"" + diag + "\" \"" + log + "\"");
  ASSERT_EQ(simple.exit_code, 0) << simple.err;
  EXPECT_EQ(json::parse(simple.out).at("battery_model"), "simple");
}

// ---- every effect a file holds is the diagnosis's base (the class of the camera's slip) ----

// For each kind, each effect of the model's effect struct (iterated over the registry, lib/models
// effects.hpp) set alone to a value inside its range and not neutral, in the shipped calibration:
// a log simulated from that file without noise (`simulate --like`) is predicted by `diagnose
// --coefficients` with the same file to within the readings' printed rounding (its base MSE,
// `heldout_mse_plugin`), and the shipped file without the effect predicts it at least ten times worse
// (else the log cannot show the effect, and the case says nothing).
TEST_F(RoundNineteenCli, EveryEffectOfAFileIsInTheDiagnosissBase) {
  namespace co = epuck2::coefficients;
  namespace fx = epuck2::models::effects;
  struct Kind {
    std::string kind, log, search;
    double exact_below;
  };
  const std::vector<Kind> kinds = {{"proximity", "proximity/proximity_virtual-epuck2-1.csv", "saturation", 1.0},
                                   {"light", "light/light_intensity_1.00.csv", "falloff_exponent", 1.0},
                                   {"ground", "ground/ground_virtual-epuck2-1.csv", "black_offset", 1.0},
                                   {"camera", "camera/camera_virtual-epuck2-1.csv", "principal_offset", 0.01},
                                   {"drive", "drive/drive_toward_15.0_cm_s.csv", "latency", 1.0}};
  int cases = 0;
  for (const Kind& k : kinds) {
    const std::string shipped = (fs::path(EPUCK2_SOURCE_DIR) / "data" / "fitted" / (k.kind + ".json")).string();
    json file = json::parse(slurp(shipped));
    file.erase("robots");
    std::string log = (fs::path(EPUCK2_SOURCE_DIR) / "data" / "raw" / k.log).string();
    if (k.kind == "proximity") {  // the incidence effect needs angles: 0, 30 and 60 degrees in turn
      std::istringstream in(slurp(log));
      std::string text;
      bool header = false;
      int row = 0;
      for (std::string l; std::getline(in, l);) {
        if (l.empty() || l[0] == '#') {
          text += l + "\n";
        } else if (!header) {
          header = true;
          text += l + ",angle_deg\n";
        } else {
          text += l + "," + std::to_string(30 * (row++ % 3)) + "\n";
        }
      }
      log = write("proximity_angles.csv", text);
    }
    const std::string plain = write(k.kind + "_plain.json", file.dump(2));
    const co::AnyModel base = co::model_from_json(k.kind, file, shipped);
    std::visit(
        [&](const auto& model) {
          using Model = std::decay_t<decltype(model)>;
          const fx::Catalogue& cat = fx::catalogue_of(model);
          std::map<std::size_t, int> ids;
          Model probe = model;
          fx::for_each_param(fx::effects_of(probe), [&](std::size_t id, int, int, double&) { ids[id] += 1; });
          for (const auto& [effect, count] : ids) {
            if (cat[effect].home == fx::Home::base) continue;
            SCOPED_TRACE(k.kind + ": " + cat[effect].name);
            Model m = model;
            fx::for_each_param(fx::effects_of(m), [&](std::size_t id, int p, int s, double& v) {
              if (id != effect) return;
              const fx::Param& P = cat[id].params[static_cast<std::size_t>(p)];
              // A fit's start where it is not neutral (a saturation level of 4000 counts, a speed
              // limit of 14 cm/s: values a log shows), else a point of the range, per sensor apart.
              const double frac = 0.3 + 0.05 * s + 0.1 * p;
              v = P.start != P.neutral && std::isfinite(P.start) ? P.start : P.lower + frac * (P.upper - P.lower);
              if (v == P.neutral) v = P.lower + (frac + 0.1) * (P.upper - P.lower);
            });
            json moved = file;
            const json written = co::model_to_json(m);
            for (const char* key : {"parameters", "effects"})
              if (written.contains(key)) moved[key] = written.at(key);
            const std::string path = write(k.kind + "_" + cat[effect].name + ".json", moved.dump(2));
            const std::string sim = dir_.string() + "/" + k.kind + "_" + cat[effect].name + ".csv";
            const CliRun r = run("simulate " + k.kind + " --like \"" + log + "\" --coefficients \"" + path + "\" -o \"" + sim + "\"");
            ASSERT_EQ(r.exit_code, 0) << r.err;
            const CliRun own = run("diagnose \"" + sim + "\" --coefficients \"" + path + "\" --effects " + k.search + " --json");
            ASSERT_EQ(own.exit_code, 0) << own.err;
            const CliRun without = run("diagnose \"" + sim + "\" --coefficients \"" + plain + "\" --effects " + k.search + " --json");
            ASSERT_EQ(without.exit_code, 0) << without.err;
            const double mse_own = json::parse(own.out).at("heldout_mse_plugin").get<double>();
            const double mse_without = json::parse(without.out).at("heldout_mse_plugin").get<double>();
            EXPECT_LT(mse_own, k.exact_below) << "the file's effect is not in the diagnosis's base";
            EXPECT_GT(mse_without, 10 * mse_own) << "the log cannot show this effect (own " << mse_own << ")";
            std::printf("  %s %s: base MSE %.3g with the file's effect, %.3g without\n", k.kind.c_str(), cat[effect].name, mse_own, mse_without);
            ++cases;
          }
        },
        base);
  }
  EXPECT_GE(cases, 10);
}

// ---- found while writing these tests: replicates that agree exactly ----

// Two groups of readings that agree to the last digit carry no noise: the lack-of-fit test is not
// done (saying why) rather than a misfit of infinitely many sd; with a quantisation floor the test
// is done against the floor (docs/fitting.md, "Lack of fit").
TEST(RoundNineteen, ReplicatesThatAgreeExactlyAreNotANoiseScale) {
  std::vector<epuck2::fit::ReplicateGroup> groups(3);
  for (std::size_t g = 0; g < 3; ++g) {
    groups[g].condition = static_cast<double>(g);
    groups[g].readings = {10.0 + g, 10.0 + g};
    groups[g].predictions = {10.5 + g, 10.5 + g};
  }
  const auto exact = epuck2::fit::lack_of_fit(groups, 1);
  EXPECT_FALSE(exact.tested);
  EXPECT_TRUE(exact.replicates_agree_exactly);
  EXPECT_EQ(exact.why_not.rfind("the repeated readings agree exactly (3 groups", 0), 0u) << exact.why_not;
  EXPECT_EQ(epuck2::fit::misfit_verdict(exact, 0.99), "");
  const auto floored = epuck2::fit::lack_of_fit(groups, 1, {}, 0.25);
  ASSERT_TRUE(floored.tested);
  EXPECT_FALSE(floored.replicates_agree_exactly);
  EXPECT_DOUBLE_EQ(floored.replicate_sd, 0.25);
  EXPECT_DOUBLE_EQ(floored.misfit_ratio, 0.5 / 0.25);  // every reading 0.5 off: misfit rms 0.5
}

// The same battery log given twice under two names: calibrated, with a warning that says so, not
// refused as a misfit of "inf" sd.
TEST_F(RoundNineteenCli, TheSameBatteryLogTwiceIsSaidNotRefused) {
  const std::string a = raw("battery", "robot-a_speed-05.csv").string();
  const std::string copy = write("copy.csv", slurp(a));
  const CliRun t = run("battery \"" + a + "\" \"" + copy + "\"");
  EXPECT_EQ(t.exit_code, 0) << t.err;
  EXPECT_TRUE(has(t.out, "Warning: 5 cm/s: the 2 runs read the same charge at every time: the cubic's lack of fit is not tested"))
      << t.out.substr(t.out.size() > 1500 ? t.out.size() - 1500 : 0);
  EXPECT_FALSE(has(t.err, "inf times")) << t.err;
}

}  // namespace test_round_nineteen_cpp
