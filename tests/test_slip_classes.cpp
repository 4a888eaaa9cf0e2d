// The classes of slips that survived rounds 2-5 (bench/fresh-slips.md, "Classes of survivors";
// issue #22 item 6), closed across the code rather than line by line. Each test is table-driven
// over every kind, field, sensor or edge of its class, against values worked by hand or computed
// here apart from the code under test:
//
//   A  a field written with a sibling's value where only a byte-for-byte comparison looked:
//      every number of every kind's model through `codegen` and a compiled program; every number
//      of a calibration report recomputed from a hand-made log;
//   B  per-sensor values equal in every fixture: fixtures whose sensors all differ (gains,
//      offsets, noise, row counts), through the real binary and the library;
//   C  boundaries never sat on: every documented range of the log reader and of a model file, on
//      each edge and just outside it; every rail of the light readings;
//   E  an option's non-default value never given: --reject-sd changing which readings are kept,
//      as worked by hand.
//
// File-local names carry the prefix sc (one unity test program).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "cli_harness.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/models/kind_facts.hpp"
#include "slip_classes_dump.hpp"

namespace {

namespace scs = epuck2::models::sensors;
namespace scfx = epuck2::models::effects;
namespace scco = epuck2::coefficients;
namespace scd = epuck2_slip_classes_dump;
using sc_json = nlohmann::json;

const epuck2::testing::Scratch& sc_scratch() {
  static const epuck2::testing::Scratch s("epuck2_slip_classes");
  return s;
}

// ----- fixtures: every number of a model different from every other ------------------------------

/// Every effect parameter of `m` set inside its range, away from its neutral value, each element
/// its own value (the fraction of the range steps by an irrational amount, from `seed`).
template <class Model>
void sc_all_effects_on(Model& m, double seed) {
  const scfx::Catalogue& c = scfx::catalogue_of(m);
  int n = 0;
  scfx::for_each_param(scfx::effects_of(m), [&](std::size_t id, int p, int, double& v) {
    const scfx::Param& par = c[id].params[static_cast<std::size_t>(p)];
    const double f = 0.1 + 0.8 * std::fmod(seed + 0.6180339887 * ++n, 1.0);
    v = par.lower + (par.upper - par.lower) * f;
  });
}

std::vector<scs::CovariateEffect> sc_covariates(double k) {
  return {{"temperature_c", 0.75 * k, 21.5 + k}, {"humidity", -0.125 * k, 43.25 - k}};
}

scs::ProximityModel sc_proximity() {
  scs::ProximityModel m;
  m.base = {-52345.5, 1234.25, 0.875, 0.0625};
  sc_all_effects_on(m, 0.05);
  for (std::size_t k = 0; k < m.noise_sd_raw.size(); ++k) m.noise_sd_raw[k] = 1.5 + 0.75 * static_cast<double>(k);
  m.covariates = sc_covariates(1.0);
  return m;
}

scs::LightModel sc_light() {
  scs::LightModel m;
  m.base.gamma_m = 0.0825;
  m.base.range_m = 0.4375;
  sc_all_effects_on(m, 0.15);
  for (std::size_t k = 0; k < m.noise_sd_raw.size(); ++k) m.noise_sd_raw[k] = 2.25 + 0.5 * static_cast<double>(k);
  m.covariates = sc_covariates(2.0);
  return m;
}

scs::GroundModel sc_ground() {
  scs::GroundModel m;
  m.sensors = {{{912.5, 21.25}, {987.75, 8.5}, {1040.125, 33.75}}};
  sc_all_effects_on(m, 0.25);
  m.noise_sd_raw = {3.5, 1.25, 2.75};
  m.covariates = sc_covariates(3.0);
  return m;
}

scs::CameraModel sc_camera() {
  scs::CameraModel m;
  m.base.horizontal_fov_rad = 0.6125;
  m.base.cx_px = 81.25;
  m.base.cy_px = 58.5;
  m.base.range_m = 2.5;
  sc_all_effects_on(m, 0.35);
  m.noise_sd_px = 0.4375;
  m.covariates = sc_covariates(4.0);
  return m;
}

scs::DriveModel sc_drive() {
  scs::DriveModel m;
  m.steps_per_m = 7650.5;
  sc_all_effects_on(m, 0.45);
  m.tof_noise_sd_mm = 3.25;
  m.encoder_noise_sd_steps = 0.625;
  m.covariates = sc_covariates(5.0);
  return m;
}

scs::BatteryModel sc_battery() {
  // The shipped tables (16 speeds, every entry its own number), a model other than the default.
  scs::BatteryModel m = scco::read_model_file<scs::BatteryModel>(std::string(EPUCK2_SOURCE_DIR) + "/data/fitted/battery.json");
  m.model = epuck2::models::battery::Model::approximated;
  sc_all_effects_on(m, 0.55);
  m.noise_sd = 0.0123;
  m.covariates = sc_covariates(6.0);
  return m;
}

std::vector<std::pair<std::string, double>> sc_lines(const std::string& dump) {
  std::vector<std::pair<std::string, double>> v;
  std::istringstream in(dump);
  std::string name;
  double x = 0;
  while (in >> name >> x) v.emplace_back(name, x);
  return v;
}

// ----- A, B: every number of every kind through codegen -----------------------------------------

TEST(SlipClassesCodegen, EveryNumberOfEveryKindIsWhatTheCompiledHeaderHolds) {
  const auto& sc = sc_scratch();
  const std::vector<std::pair<std::string, scco::AnyModel>> models = {
      {"proximity", sc_proximity()}, {"light", sc_light()}, {"ground", sc_ground()},
      {"camera", sc_camera()},       {"drive", sc_drive()}, {"battery", sc_battery()}};
  std::string files, expected;
  for (const auto& [kind, model] : models) {
    const sc_json j = std::visit([](const auto& m) { return scco::model_to_json(m); }, model);
    files += " " + sc.write(kind + ".json", j.dump(2));
    expected += std::visit([](const auto& m) { return scd::dump(m); }, model);
    if (kind == "battery") continue;
    // The fixture's power: no two of the kind's numbers are equal, so a field given a sibling's
    // value cannot go unseen.
    std::map<double, std::string> seen;
    for (const auto& [name, v] : sc_lines(std::visit([](const auto& m) { return scd::dump(m); }, model))) {
      const auto [it, fresh] = seen.emplace(v, name);
      EXPECT_TRUE(fresh) << kind << ": " << name << " and " << it->second << " are both " << v;
    }
  }
  const std::string header = sc.dir() + "/fitted_all.hpp";
  const std::string cg = std::string(EPUCK2_FIT_EXE) + " codegen" + files + " -o " + header + " > " + sc.dir() + "/cg.txt 2>&1";
  ASSERT_EQ(std::system(cg.c_str()), 0) << epuck2::testing::slurp(sc.dir() + "/cg.txt");
  const std::string main_cpp = sc.write("dump_main.cpp", "#include \"" + header +
                                                             "\"\n#include \"slip_classes_dump.hpp\"\n#include <cstdio>\n"
                                                             "int main() {\n  namespace f = epuck2::fitted;\n"
                                                             "  for (const std::string& s : {epuck2_slip_classes_dump::dump(f::proximity_model()),\n"
                                                             "       epuck2_slip_classes_dump::dump(f::light_model()), epuck2_slip_classes_dump::dump(f::ground_model()),\n"
                                                             "       epuck2_slip_classes_dump::dump(f::camera_model()), epuck2_slip_classes_dump::dump(f::drive_model()),\n"
                                                             "       epuck2_slip_classes_dump::dump(f::battery_model())})\n"
                                                             "    std::fputs(s.c_str(), stdout);\n}\n");
  const std::string exe = sc.dir() + "/dump_main";
  const std::string cc = std::string(EPUCK2_CXX) + " -std=c++17 -O0 -I" + EPUCK2_SOURCE_DIR + "/lib/models/include -I" + EPUCK2_SOURCE_DIR +
                         "/tests -I/usr/include/eigen3 " + main_cpp + " -o " + exe + " > " + sc.dir() + "/cc.txt 2>&1 && " + exe + " > " +
                         sc.dir() + "/compiled.txt";
  ASSERT_EQ(std::system(cc.c_str()), 0) << epuck2::testing::slurp(sc.dir() + "/cc.txt");
  // By name: a file's effects (covariates among them) are a JSON object, read back in its keys'
  // order, not the model's.
  const auto want_lines = sc_lines(expected), got_lines = sc_lines(epuck2::testing::slurp(sc.dir() + "/compiled.txt"));
  const std::map<std::string, double> want(want_lines.begin(), want_lines.end()), got(got_lines.begin(), got_lines.end());
  ASSERT_EQ(want.size(), want_lines.size());
  EXPECT_EQ(got.size(), want.size());
  for (const auto& [name, value] : want) {
    const auto it = got.find(name);
    ASSERT_NE(it, got.end()) << name << " is not in what the compiled program holds";
    EXPECT_EQ(it->second, value) << name << " is " << value << " in the model, " << it->second
                                 << " in the program compiled against codegen's header";
  }
  // The battery alone: 16 speeds of 31 numbers (a cubic 5, four segments of 6, a slope, a lifetime).
  EXPECT_GT(want.size(), 16u * 31u);
}

// ----- B: per-sensor values that all differ, through simulate --like ----------------------------

TEST(SlipClassesSimulateLike, EverySensorReadsWithItsOwnCoefficientsGroundAndLight) {
  const auto& sc = sc_scratch();
  // Ground: reading = offset_s + gain_s grey^p (p the nonlinear_response's exponent), rows in a
  // sensor order that is not 0, 1, 2 and does not start at 0.
  scs::GroundModel g = sc_ground();
  g.covariates.clear();
  const double p = g.effects.exponent;
  const std::string gfile = sc.write("ground_like.json", scco::model_to_json(g).dump());
  const std::vector<std::pair<double, int>> grows = {{0.25, 2}, {0.5, 0}, {0.81, 1}, {0.25, 1}, {0.64, 2}, {0.09, 0}, {1.0, 1}};
  std::string glog = "grey,sensor,value\n";
  for (const auto& [grey, s] : grows) glog += std::to_string(grey) + "," + std::to_string(s) + ",0\n";
  const auto gsim = sc.simulate_like("ground", sc.write("ground_like.csv", glog), gfile);
  ASSERT_EQ(gsim.rows(), grows.size());
  for (std::size_t i = 0; i < grows.size(); ++i) {
    const auto& k = g.sensors[static_cast<std::size_t>(grows[i].second)];
    const double want = std::clamp(k.offset_raw + k.gain_raw * std::pow(grows[i].first, p), 0.0, 1023.0);
    EXPECT_NEAR(gsim.col("value")[i], want, 1e-9 * want) << "row " << i << ", sensor " << grows[i].second;
  }
  // Light: reading = 4095 (1 - gain_s (gamma I / d)^e) - ambient offset within the range, 4095 -
  // offset beyond it; clamped to 0..4095.
  scs::LightModel l = sc_light();
  l.covariates.clear();
  l.effects.ambient.offset_raw = 12.5;
  l.effects.falloff.exponent = 2.5;
  for (std::size_t k = 0; k < 8; ++k) l.effects.gains.gain[k] = 0.55 + 0.125 * static_cast<double>(k);
  const std::string lfile = sc.write("light_like.json", scco::model_to_json(l).dump());
  struct Row {
    double d, intensity;
    int sensor;
  };
  const std::vector<Row> lrows = {{0.2, 0.5, 7}, {0.15, 1.0, 0}, {0.3, 2.0, 3}, {0.2, 0.5, 1}, {0.45, 1.0, 5}, {0.25, 0.75, 6}};
  std::string llog = "distance_m,intensity,sensor,value\n";
  for (const Row& r : lrows) llog += std::to_string(r.d) + "," + std::to_string(r.intensity) + "," + std::to_string(r.sensor) + ",0\n";
  const auto lsim = sc.simulate_like("light", sc.write("light_like.csv", llog), lfile);
  ASSERT_EQ(lsim.rows(), lrows.size());
  for (std::size_t i = 0; i < lrows.size(); ++i) {
    const Row& r = lrows[i];
    const double ratio = 0.0825 * r.intensity / r.d;
    const double gain = 0.55 + 0.125 * r.sensor;
    const double want = std::clamp(r.d <= 0.4375 ? 4095.0 * (1.0 - gain * std::pow(ratio, 2.5)) - 12.5 : 4095.0 - 12.5, 0.0, 4095.0);
    EXPECT_NEAR(lsim.col("value")[i], want, 1e-9 * want) << "row " << i << ", sensor " << r.sensor;
  }
}

// ----- A, B: a calibration report's numbers recomputed from a hand-made log ----------------------

/// A ground log with three sensors whose gains, offsets, noise and row counts all differ: each
/// reading is offset_s + gain_s grey +- d_s, in pairs at the same grey (the pair's mean is the
/// line, so least squares returns the line exactly and every residual is +-d_s).
struct ScGroundTruth {
  double gain, offset, d;
  std::vector<double> greys;
};
const std::vector<ScGroundTruth>& sc_ground_truth() {
  static const std::vector<ScGroundTruth> t = {{700, 30, 2, {0.2, 0.4, 0.6, 0.8, 1.0}},
                                               {850, 10, 3, {0.1, 0.3, 0.5, 0.7}},
                                               {990, 55, 4, {0.2, 0.4, 0.6, 0.8, 0.6, 0.4}}};
  return t;
}
std::string sc_ground_log(const std::string& extra = "") {
  std::string log = "grey,sensor,value\n";
  for (std::size_t s = 0; s < sc_ground_truth().size(); ++s) {
    const auto& t = sc_ground_truth()[s];
    for (double grey : t.greys)
      for (double sign : {1.0, -1.0})
        log += std::to_string(grey) + "," + std::to_string(s) + "," + std::to_string(t.offset + t.gain * grey + sign * t.d) + "\n";
  }
  return log + extra;
}

class SlipClassesReports : public epuck2::testing::CliTest {};

TEST_F(SlipClassesReports, GroundFileEveryPerSensorNumberByHand) {
  const std::string log = write("g.csv", sc_ground_log());
  const auto r = run("ground \"" + log + "\" -o g.json", dir_.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const sc_json j = sc_json::parse(epuck2::testing::slurp(dir_ / "g.json"));
  double rss_all = 0, plugin_all = 0, ss_groups = 0, dof_groups = 0;
  std::size_t n_all = 0;
  for (std::size_t s = 0; s < 3; ++s) {
    const auto& t = sc_ground_truth()[s];
    const std::size_t n = 2 * t.greys.size();
    EXPECT_NEAR(j["parameters"]["gain"][s].get<double>(), t.gain, 1e-6) << "sensor " << s;
    EXPECT_NEAR(j["parameters"]["offset"][s].get<double>(), t.offset, 1e-6) << "sensor " << s;
    EXPECT_EQ(j["observations_per_sensor"][s].get<std::size_t>(), n) << "sensor " << s;
    // Every residual is +-d: MSE = RSS / n = d^2 (docs/coefficient-files.md: MSE is RSS / n).
    EXPECT_NEAR(j["mse_per_sensor"][s].get<double>(), t.d * t.d, 1e-9) << "sensor " << s;
    // The fit's statistics (class D: each a formula of n, k = 2 and RSS = n d^2; docs/fitting.md and
    // the report's own words: reduced chi2 RSS/(n-k), AIC n ln(RSS/n) + 2k, BIC n ln(RSS/n) + k ln n,
    // R^2 1 - RSS/TSS, TSS about the readings' mean).
    const auto& fit = j["fits"]["sensor_" + std::to_string(s)];
    const double nn = static_cast<double>(n), rss = nn * t.d * t.d;
    EXPECT_EQ(fit["n"].get<std::size_t>(), n);
    EXPECT_EQ(fit["free_parameters"].get<int>(), 2);
    EXPECT_NEAR(fit["rss"].get<double>(), rss, 1e-9 * rss);
    EXPECT_NEAR(fit["reduced_chi2"].get<double>(), rss / (nn - 2), 1e-9) << "sensor " << s;
    EXPECT_NEAR(fit["aic"].get<double>(), nn * std::log(t.d * t.d) + 4, 1e-6) << "sensor " << s;
    EXPECT_NEAR(fit["bic"].get<double>(), nn * std::log(t.d * t.d) + 2 * std::log(nn), 1e-6) << "sensor " << s;
    double mean = 0, tss = 0;
    for (double grey : t.greys) mean += 2 * (t.offset + t.gain * grey) / nn;
    for (double grey : t.greys)
      for (double sign : {1.0, -1.0}) tss += std::pow(t.offset + t.gain * grey + sign * t.d - mean, 2);
    EXPECT_NEAR(fit["r2"].get<double>(), 1 - rss / tss, 1e-9) << "sensor " << s;
    // The plug-in (offset 0, gain 1023): its error (offset + (gain - 1023) grey +- d)^2; the +-d
    // terms cancel in pairs.
    double plugin = 0;
    for (double grey : t.greys) plugin += 2 * (std::pow(t.offset + (t.gain - 1023.0) * grey, 2) + t.d * t.d);
    EXPECT_NEAR(j["reference_mse"]["plugin"][s].get<double>(), plugin / static_cast<double>(n), 1e-6) << "sensor " << s;
    // Replicate noise: the groups at the same grey (a grey logged twice makes a group of 4), each
    // reading +-d from the group's mean: sum of squares d^2 per reading, n - groups degrees.
    const std::set<double> groups(t.greys.begin(), t.greys.end());
    const double ss = static_cast<double>(n) * t.d * t.d, dof = static_cast<double>(n - groups.size());
    EXPECT_NEAR(j["noise"]["ground"]["per_sensor_sd"][s].get<double>(), std::sqrt(ss / dof), 1e-9) << "sensor " << s;
    EXPECT_EQ(j["noise"]["ground"]["per_sensor_n"][s].get<std::size_t>(), n) << "sensor " << s;
    rss_all += ss;
    plugin_all += plugin;
    ss_groups += ss;
    dof_groups += dof;
    n_all += n;
  }
  EXPECT_EQ(j["observations"].get<std::size_t>(), n_all);
  EXPECT_EQ(j["readings"].get<std::size_t>(), n_all);
  EXPECT_NEAR(j["mse"].get<double>(), rss_all / static_cast<double>(n_all), 1e-9);
  EXPECT_NEAR(j["noise"]["ground"]["sd"].get<double>(), std::sqrt(ss_groups / dof_groups), 1e-9);
}

TEST_F(SlipClassesReports, ProximityPointsAreEachDistancesMaxMeanAndMinByHand) {
  // Per distance, sensors with readings that all differ, and not every sensor at every distance.
  std::map<double, std::vector<double>> by_distance;
  std::string log = "distance_m,sensor,value\n";
  const std::vector<double> distances = {0.005, 0.01, 0.015, 0.02, 0.025, 0.03, 0.035, 0.04, 0.045};
  for (std::size_t i = 0; i < distances.size(); ++i) {
    const double d = distances[i];
    const double base = std::round(3900.0 * std::pow(1.0 - d / 0.05, 2) + 20.0);
    for (int s = 0; s < 8; ++s) {
      if ((s + static_cast<int>(i)) % 5 == 4) continue;  // a sensor missing here and there
      // Evenly spaced, 3 counts apart: none is wild among its distance's replicates (kept = readings).
      const double v = base + 3.0 * s - 10.0 + static_cast<double>(i % 3);
      by_distance[d].push_back(v);
      log += std::to_string(d) + "," + std::to_string(s) + "," + std::to_string(v) + "\n";
    }
  }
  write("p.csv", log);
  const auto r = run("proximity p.csv -o p.json", dir_.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const sc_json j = sc_json::parse(epuck2::testing::slurp(dir_ / "p.json"));
  ASSERT_EQ(j["points"].size(), distances.size());
  for (const auto& pt : j["points"]) {
    const auto& v = by_distance.at(pt["distance_m"].get<double>());
    double sum = 0;
    for (double x : v) sum += x;
    EXPECT_EQ(pt["readings"].get<std::size_t>(), v.size());
    EXPECT_EQ(pt["kept"].get<std::size_t>(), v.size());
    EXPECT_NEAR(pt["max"].get<double>(), *std::max_element(v.begin(), v.end()) / 4095.0, 1e-12) << pt.dump();
    EXPECT_NEAR(pt["min"].get<double>(), *std::min_element(v.begin(), v.end()) / 4095.0, 1e-12) << pt.dump();
    EXPECT_NEAR(pt["mean"].get<double>(), sum / static_cast<double>(v.size()) / 4095.0, 1e-12) << pt.dump();
  }
}

TEST_F(SlipClassesReports, LightPerSensorGammaAndMseByHand) {
  // Three sensors with their own gamma; readings 4095 (1 - (gamma_s I / d)^2) +- d_s in pairs:
  // each sensor's own fit returns its gamma, its MSE d_s^2 / 4095^2 (normalised units).
  const std::vector<std::pair<double, double>> truth = {{0.07, 3.0}, {0.08, 5.0}, {0.09, 8.0}};
  std::string log = "distance_m,intensity,sensor,value\n";
  for (std::size_t s = 0; s < truth.size(); ++s)
    for (double d : {0.1, 0.15, 0.2, 0.3, 0.4})
      for (double sign : {1.0, -1.0}) {
        const double v = 4095.0 * (1.0 - std::pow(truth[s].first * 1.0 / d, 2)) + sign * truth[s].second;
        log += std::to_string(d) + ",1," + std::to_string(s) + "," + std::to_string(v) + "\n";
      }
  write("l.csv", log);
  // One gamma for all sensors misses these logs by far more than their noise: --accept-misfit.
  const auto r = run("light l.csv -o l.json --accept-misfit", dir_.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const sc_json j = sc_json::parse(epuck2::testing::slurp(dir_ / "l.json"));
  ASSERT_EQ(j["per_sensor"].size(), truth.size());
  for (std::size_t s = 0; s < truth.size(); ++s) {
    const auto& e = j["per_sensor"][s];
    EXPECT_EQ(e["sensor"].get<int>(), static_cast<int>(s));
    EXPECT_NEAR(e["gamma"].get<double>(), truth[s].first, 1e-6) << "sensor " << s;
    EXPECT_NEAR(e["mse"].get<double>(), std::pow(truth[s].second / 4095.0, 2), 1e-6 * std::pow(truth[s].second / 4095.0, 2))
        << "sensor " << s;
  }
}

TEST_F(SlipClassesReports, DriveFileSummariesAreTheirOwnFitsRssOverN) {
  // The shipped drive logs: the encoders' and the ToF's fits each summarised with its own
  // numbers, MSE = RSS / n (docs/coefficient-files.md), and the two differ.
  const auto r = run("drive" + shipped("drive") + " -o d.json", dir_.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const sc_json j = sc_json::parse(epuck2::testing::slurp(dir_ / "d.json"));
  for (const auto& [top, fit] : {std::pair<const char*, const char*>{"mse", "tof"}, {"steps_mse", "steps"}}) {
    const auto& f = j["fits"][fit];
    EXPECT_NEAR(j[top].get<double>(), f["rss"].get<double>() / f["n"].get<double>(), 1e-12 * j[top].get<double>()) << top;
  }
  EXPECT_EQ(j["steps_observations"], j["fits"]["steps"]["observations"]);
  EXPECT_EQ(j["observations"], j["fits"]["tof"]["observations"]);
  EXPECT_GT(std::abs(j["mse"].get<double>() - j["steps_mse"].get<double>()), 1.0);
}

TEST_F(SlipClassesReports, DiagnosisHeldOutErrorsOfTheRecalibratedModelAndThePlugins) {
  // A light log whose three sensors share gamma 0.09 m, readings 4095 (1 - (0.09 / d)^2) +- 5 in
  // pairs at 10 distances: the recalibrated base (gamma alone) fits every pair's mean, so its
  // held-out MSE is 5^2 = 25 (a little more if a fold split a pair); the plug-in's gamma 0.075
  // misses by 4095 ((0.075 / d)^2 - (0.09 / d)^2), tens of thousands of counts^2.
  std::string log = "distance_m,intensity,sensor,value\n";
  double plugin = 0;
  for (int s = 0; s < 3; ++s)
    for (int i = 0; i < 10; ++i) {
      const double d = 0.1 + 0.035 * i, v = 4095 * (1 - std::pow(0.09 / d, 2));
      for (double sign : {1.0, -1.0}) {
        log += std::to_string(d) + ",1," + std::to_string(s) + "," + std::to_string(v + 5 * sign) + "\n";
        plugin += std::pow(v + 5 * sign - 4095 * (1 - std::pow(0.075 / d, 2)), 2);
      }
    }
  plugin /= 60;
  write("ld.csv", log);
  const auto r = run("diagnose ld.csv -o ld.json", dir_.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const sc_json j = sc_json::parse(epuck2::testing::slurp(dir_ / "ld.json"));
  ASSERT_TRUE(j["heldout_mse_recalibrated"].is_number()) << j.dump();
  EXPECT_NEAR(j["recalibrated"]["gamma_m"].get<double>(), 0.09, 1e-6);
  EXPECT_GE(j["heldout_mse_recalibrated"].get<double>(), 25.0 * 0.99);
  EXPECT_LE(j["heldout_mse_recalibrated"].get<double>(), 25.0 * 1.5);
  EXPECT_GT(j["heldout_mse_plugin"].get<double>(), 0.5 * plugin);
  EXPECT_LT(j["heldout_mse_plugin"].get<double>(), 2.0 * plugin);
}

// ----- E: an option's non-default value, as worked by hand ---------------------------------------

TEST_F(SlipClassesReports, RejectSdTwoLeavesOutAReadingTheDefaultFourKeeps) {
  // Sensor 0 of the ground log with one more reading, 9 counts above its line at grey 0.5. Kept
  // (default --reject-sd 4), it moves sensor 0's least-squares line: +9 at x0 = 0.5 moves
  // (offset, gain) by 9 (X'X)^-1 (1, x0); left out (--reject-sd 2: 9 counts is more than 2 but
  // less than 4 of the residuals' sd, about 2.7 to 3.5 counts), the line is the truth again.
  write("g.csv", sc_ground_log("0.500000,0,389.000000\n"));  // 30 + 700 * 0.5 + 9
  const auto& t = sc_ground_truth()[0];
  // X'X over sensor 0's 11 rows: pairs at its greys and the extra one at 0.5.
  double n = 1, sx = 0.5, sxx = 0.25;
  for (double g : t.greys) {
    n += 2;
    sx += 2 * g;
    sxx += 2 * g * g;
  }
  const double det = n * sxx - sx * sx;
  const double d_offset = 9 * (sxx - sx * 0.5) / det, d_gain = 9 * (n * 0.5 - sx) / det;
  for (const auto& [args, left_out] : {std::pair<std::string, int>{"", 0}, {" --reject-sd 2", 1}}) {
    const auto r = run("ground g.csv -o g.json" + args, dir_.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const sc_json j = sc_json::parse(epuck2::testing::slurp(dir_ / "g.json"));
    EXPECT_EQ(j["fits"]["sensor_0"]["outliers"].get<int>(), left_out) << args;
    EXPECT_NEAR(j["parameters"]["offset"][0].get<double>(), t.offset + (left_out ? 0.0 : d_offset), 1e-5) << args;
    EXPECT_NEAR(j["parameters"]["gain"][0].get<double>(), t.gain + (left_out ? 0.0 : d_gain), 1e-5) << args;
    // The other sensors never had a wild reading: their lines are the truth either way.
    EXPECT_NEAR(j["parameters"]["gain"][2].get<double>(), 990.0, 1e-6) << args;
  }
}

// ----- C: every documented range of the log reader, on each edge and just outside --------------

struct ScCell {
  const char* kind;
  const char* header;       ///< the columns, and metadata lines before them
  std::string row;          ///< one row with {} where the value goes
  std::string value;        ///< the value written
  bool read;                ///< docs/logs.md: inside the column's range
};

TEST(SlipClassesBoundaries, EveryColumnRangeOfDocsLogsOnBothEdges) {
  const char* prox = "distance_m,sensor,value,angle_deg\n";
  const char* light = "distance_m,intensity,sensor,value\n";
  const char* ground = "grey,sensor,value\n";
  const char* camera = "forward_m,lateral_m,vertical_m,px,py\n";
  const char* drive = "time_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n";
  // docs/logs.md's tables: proximity distance_m 0..1000, value 0..4095, angle_deg -90..90; light
  // distance_m 0.001..1000, intensity 0..1e6; ground grey 0..1, value 0..1023; camera forward_m
  // > 0 up to 1000, lateral_m and vertical_m -1000..1000, px 0..159, py 0..119; drive speeds
  // -1000..1000, steps -32768..32767, tof_mm 20..2000 or >= 8190.
  const std::vector<ScCell> cells = {
      {"proximity", prox, "{},3,1000,0", "0", true},       {"proximity", prox, "{},3,1000,0", "1000", true},
      {"proximity", prox, "{},3,1000,0", "-0.001", false}, {"proximity", prox, "{},3,1000,0", "1000.001", false},
      {"proximity", prox, "0.02,3,{},0", "0", true},       {"proximity", prox, "0.02,3,{},0", "4095", true},
      {"proximity", prox, "0.02,3,{},0", "-0.5", false},   {"proximity", prox, "0.02,3,{},0", "4095.5", false},
      {"proximity", prox, "0.02,3,1000,{}", "-90", true},  {"proximity", prox, "0.02,3,1000,{}", "90", true},
      {"proximity", prox, "0.02,3,1000,{}", "-90.01", false}, {"proximity", prox, "0.02,3,1000,{}", "90.01", false},
      {"light", light, "{},1,2,3000", "0.001", true},      {"light", light, "{},1,2,3000", "1000", true},
      {"light", light, "{},1,2,3000", "0.000999", false},  {"light", light, "{},1,2,3000", "1000.001", false},
      {"light", light, "0.2,{},2,3000", "0", true},        {"light", light, "0.2,{},2,3000", "1000000", true},
      {"light", light, "0.2,{},2,3000", "-0.001", false},  {"light", light, "0.2,{},2,3000", "1000000.5", false},
      {"light", light, "0.2,1,2,{}", "4095", true},        {"light", light, "0.2,1,2,{}", "4095.5", false},
      {"ground", ground, "{},1,500", "0", true},           {"ground", ground, "{},1,500", "1", true},
      {"ground", ground, "{},1,500", "-0.001", false},     {"ground", ground, "{},1,500", "1.001", false},
      {"ground", ground, "0.5,1,{}", "0", true},           {"ground", ground, "0.5,1,{}", "1023", true},
      {"ground", ground, "0.5,1,{}", "-0.5", false},       {"ground", ground, "0.5,1,{}", "1023.5", false},
      {"camera", camera, "{},0.1,0.05,80,60", "1e-06", true}, {"camera", camera, "{},0.1,0.05,80,60", "1000", true},
      {"camera", camera, "{},0.1,0.05,80,60", "0", false},  {"camera", camera, "{},0.1,0.05,80,60", "1000.001", false},
      {"camera", camera, "0.5,{},0.05,80,60", "-1000", true}, {"camera", camera, "0.5,{},0.05,80,60", "1000", true},
      {"camera", camera, "0.5,{},0.05,80,60", "-1000.001", false}, {"camera", camera, "0.5,{},0.05,80,60", "1000.001", false},
      {"camera", camera, "0.5,0.1,{},80,60", "-1000", true}, {"camera", camera, "0.5,0.1,{},80,60", "1000", true},
      {"camera", camera, "0.5,0.1,{},80,60", "-1000.001", false}, {"camera", camera, "0.5,0.1,{},80,60", "1000.001", false},
      {"camera", camera, "0.5,0.1,0.05,{},60", "0", true},  {"camera", camera, "0.5,0.1,0.05,{},60", "159", true},
      {"camera", camera, "0.5,0.1,0.05,{},60", "-0.5", false}, {"camera", camera, "0.5,0.1,0.05,{},60", "159.5", false},
      {"camera", camera, "0.5,0.1,0.05,80,{}", "0", true},  {"camera", camera, "0.5,0.1,0.05,80,{}", "119", true},
      {"camera", camera, "0.5,0.1,0.05,80,{}", "-0.5", false}, {"camera", camera, "0.5,0.1,0.05,80,{}", "119.5", false},
      {"drive", drive, "1,{},5,10,10,300", "-1000", true}, {"drive", drive, "1,{},5,10,10,300", "1000", true},
      {"drive", drive, "1,{},5,10,10,300", "-1000.5", false}, {"drive", drive, "1,{},5,10,10,300", "1000.5", false},
      {"drive", drive, "1,5,{},10,10,300", "1000", true},  {"drive", drive, "1,5,{},10,10,300", "1000.5", false},
      {"drive", drive, "1,5,5,{},10,300", "-32768", true}, {"drive", drive, "1,5,5,{},10,300", "32767", true},
      {"drive", drive, "1,5,5,{},10,300", "-32769", false}, {"drive", drive, "1,5,5,{},10,300", "32768", false},
      {"drive", drive, "1,5,5,10,{},300", "32767", true},  {"drive", drive, "1,5,5,10,{},300", "32768", false},
      {"drive", drive, "1,5,5,10,10,{}", "20", true},      {"drive", drive, "1,5,5,10,10,{}", "2000", true},
      {"drive", drive, "1,5,5,10,10,{}", "19", false},     {"drive", drive, "1,5,5,10,10,{}", "2001", false},
      {"drive", drive, "1,5,5,10,10,{}", "8190", true},    {"drive", drive, "1,5,5,10,10,{}", "8189", false},
  };
  const auto& sc = sc_scratch();
  int i = 0;
  for (const ScCell& c : cells) {
    std::string row = c.row;
    const std::size_t at = row.find("{}");
    row.replace(at, 2, c.value);
    // The first row is a plain one (line 2 after the header; the drive's metadata line first).
    const bool is_drive = std::string(c.kind) == "drive";
    const std::string first = is_drive ? "0,5,5,0,0,300\n" : "";
    const std::string text = std::string(is_drive ? "# obstacle_distance_m: 0.5\n" : "") + c.header + first + row + "\n";
    const std::string path = sc.write("range_" + std::to_string(i++) + ".csv", text);
    const int line = is_drive ? 4 : 2;
    const int column = static_cast<int>(std::count(row.begin(), row.begin() + static_cast<long>(at), ',')) + 1;
    const std::string what = std::string(c.kind) + " row '" + row + "'";
    try {
      (void)epuck2::logs::read_log(path, epuck2::logs::parse_kind(c.kind));
      EXPECT_TRUE(c.read) << what << " was read; docs/logs.md puts " << c.value << " outside the column's range";
    } catch (const epuck2::logs::InputError& e) {
      EXPECT_FALSE(c.read) << what << " was refused: " << e.what();
      if (!c.read) {
        EXPECT_EQ(e.line(), line) << what << ": " << e.what();
        // The column is the cell's first character: count the characters before it.
        std::size_t chars = 0;
        for (int k = 1; k < column; ++k) chars = row.find(',', chars) + 1;
        EXPECT_EQ(e.column(), static_cast<int>(chars) + 1) << what << ": " << e.what();
      }
    }
  }
}

TEST(SlipClassesBoundaries, TheDrivesObstacleDistanceFromZeroToAThousandMetres) {
  // docs/logs.md: `obstacle_distance_m` a number in 0..1000, 0 accepted (the robot starts
  // touching the obstacle).
  const auto& sc = sc_scratch();
  int i = 0;
  for (const auto& [value, read] : std::vector<std::pair<std::string, bool>>{{"0", true}, {"1000", true}, {"-0.001", false}, {"1000.001", false}}) {
    const std::string path = sc.write("obstacle_" + std::to_string(i++) + ".csv",
                                      "# obstacle_distance_m: " + value +
                                          "\ntime_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm\n0,0,0,0,0,20\n");
    try {
      (void)epuck2::logs::read_log(path, epuck2::logs::Kind::drive);
      EXPECT_TRUE(read) << value << " read";
    } catch (const epuck2::logs::InputError& e) {
      EXPECT_FALSE(read) << value << " refused: " << e.what();
      EXPECT_EQ(e.line(), 1) << e.what();
    }
  }
}

// ----- C: every documented range of a model file, on each edge and just outside -----------------

/// Reads `j` as a file of `kind`: "" when read, else the reader's message.
std::string sc_refusal(const std::string& kind, const sc_json& j) {
  try {
    (void)scco::model_from_json(kind, j, "edge.json");
    return "";
  } catch (const std::exception& e) {
    return e.what()[0] ? e.what() : "refused";
  }
}

TEST(SlipClassesBoundaries, EveryBaseCoefficientRangeOfTheDocsOnBothEdges) {
  // docs/coefficient-files.md, "What a reader refuses": proximity |a| <= 1e6, |b| <= 1e5,
  // |c| <= 100, range_m in (0, 1]; light gamma in (0, 10]; ground gain in (0, 4092], offset in
  // [-1023, 1023]; camera fov_deg in (0, 180), cx_px in [0, 160], cy_px in [0, 120].
  struct Edge {
    const char* kind;
    const char* key;
    double value;
    bool read;
  };
  const double below = -1e-9, above = 1e-9;  // just outside an edge (relative for the large ones)
  const std::vector<Edge> edges = {
      {"proximity", "a", 1e6, true},      {"proximity", "a", -1e6, true},      {"proximity", "a", 1e6 * (1 + above), false},
      {"proximity", "a", -1e6 * (1 + above), false}, {"proximity", "b", 1e5, true}, {"proximity", "b", -1e5, true},
      {"proximity", "b", 1e5 * (1 + above), false}, {"proximity", "c", 100, true}, {"proximity", "c", -100, true},
      {"proximity", "c", 100 * (1 + above), false}, {"proximity", "range_m", 1, true}, {"proximity", "range_m", 1 + above, false},
      {"proximity", "range_m", 0, false},  {"proximity", "range_m", 1e-9, true},
      {"light", "gamma", 10, true},        {"light", "gamma", 10 * (1 + above), false}, {"light", "gamma", 0, false},
      {"light", "gamma", 1e-9, true},
      {"ground", "gain", 4092, true},      {"ground", "gain", 4092 * (1 + above), false}, {"ground", "gain", 0, false},
      {"ground", "gain", 1e-9, true},      {"ground", "offset", 1023, true},    {"ground", "offset", -1023, true},
      {"ground", "offset", 1023 * (1 + above), false}, {"ground", "offset", -1023 * (1 + above), false},
      {"camera", "fov_deg", 180, false},   {"camera", "fov_deg", 180 * (1 + below), true}, {"camera", "fov_deg", 0, false},
      {"camera", "fov_deg", 1e-6, true},   {"camera", "cx_px", 0, true},        {"camera", "cx_px", 160, true},
      {"camera", "cx_px", -1e-9, false},   {"camera", "cx_px", 160 * (1 + above), false}, {"camera", "cy_px", 0, true},
      {"camera", "cy_px", 120, true},      {"camera", "cy_px", -1e-9, false},   {"camera", "cy_px", 120 * (1 + above), false},
  };
  for (const Edge& e : edges) {
    sc_json j = std::visit([](const auto& m) { return scco::model_to_json(m); }, scco::plugin_model(e.kind));
    sc_json& p = j["parameters"];
    ASSERT_TRUE(p.contains(e.key)) << e.kind << " " << e.key << ": " << j.dump();
    if (p[e.key].is_array()) {
      p[e.key][1] = e.value;  // one sensor of three (ground), the others as the plug-in's
    } else {
      p[e.key] = e.value;
    }
    if (std::string(e.key) == "fov_deg") {
      // The aperture follows the field of view (atan(tan(fov/2) 200/160), the docs' rule).
      const double half = e.value / 2 * M_PI / 180;
      p["aperture_deg"] = std::atan(std::tan(half) * 200.0 / 160.0) * 180 / M_PI;
    }
    const std::string why = sc_refusal(e.kind, j);
    EXPECT_EQ(why.empty(), e.read) << e.kind << " parameters." << e.key << " = " << e.value << ": "
                                   << (why.empty() ? "read" : why);
    if (!why.empty() && !e.read) EXPECT_NE(why.find(e.key), std::string::npos) << why;
  }
}

TEST(SlipClassesBoundaries, EveryEffectParameterOnBothEdgesOfItsClosedRange) {
  // docs/coefficient-files.md: an effect's parameter outside its physical range, other than its
  // neutral value, is refused; the range is closed (effects.hpp, Param). Each kind's fixture
  // above (every effect on), one parameter moved to each edge and to the next double beyond.
  const std::vector<std::pair<std::string, scco::AnyModel>> models = {
      {"proximity", sc_proximity()}, {"light", sc_light()}, {"camera", sc_camera()}, {"drive", sc_drive()}, {"ground", sc_ground()}};
  int checked = 0;
  for (const auto& [kind, model] : models) {
    const sc_json base = std::visit([](const auto& m) { return scco::model_to_json(m); }, model);
    const scfx::Catalogue& c = *scfx::catalogue(kind);
    for (const scfx::Effect& e : c) {
      if (e.home == scfx::Home::base) continue;
      for (const scfx::Param& p : e.params) {
        const double lo = p.lower, hi = p.upper;
        for (const auto& [v, read] : std::vector<std::pair<double, bool>>{
                 {lo, true}, {hi, true}, {std::nextafter(lo, -HUGE_VAL), false}, {std::nextafter(hi, HUGE_VAL), false}}) {
          sc_json j = base;
          sc_json& slot = e.home == scfx::Home::parameters ? j["parameters"][p.file_key] : j["effects"][e.name][p.key];
          ASSERT_FALSE(slot.is_null()) << kind << " " << e.name << "." << p.key << " is not in the fixture's file: " << base.dump();
          (slot.is_array() ? slot[0] : slot) = v;
          const bool want = read || v == p.neutral;
          const std::string why = sc_refusal(kind, j);
          EXPECT_EQ(why.empty(), want) << kind << " " << e.name << "." << p.key << " = " << v << " (range " << lo << ".." << hi
                                       << "): " << (why.empty() ? "read" : why);
          ++checked;
        }
      }
    }
  }
  EXPECT_GE(checked, 4 * 16);
}

// ----- C: the light readings' rails -------------------------------------------------------------

TEST(SlipClassesBoundaries, LightReadingsOnEitherRailAreCountedCensoredOneInsideAreNot) {
  // docs/logs.md: light readings 0 (saturated) and 4095 (dark) are on the rails; 1 and 4094 are
  // inside. Rows within the range (0.5 m) with light, so every one enters the fits.
  const auto& sc = sc_scratch();
  std::string log = "distance_m,intensity,sensor,value\n";
  for (int s = 0; s < 3; ++s)
    for (double d : {0.1, 0.2, 0.3, 0.4}) log += std::to_string(d) + ",1," + std::to_string(s) + "," + std::to_string(std::round(4095 * (1 - std::pow(0.075 / d, 2)))) + "\n";
  for (const auto& [extra, censored] : std::vector<std::pair<std::string, std::size_t>>{
           {"", 0}, {"0.02,1,4,0\n", 1}, {"0.02,1,4,1\n", 0}, {"0.45,0.01,5,4095\n", 1}, {"0.45,0.01,5,4094\n", 0},
           {"0.02,1,4,0\n0.45,0.01,5,4095\n", 2}}) {
    const std::string path = sc.write("rails.csv", log + extra);
    const auto f = epuck2::calibrate::fit_light({epuck2::logs::read_log(path)});
    EXPECT_EQ(f.censored, censored) << "extra rows: " << extra;
    EXPECT_EQ(f.observations.size(), 12 + static_cast<std::size_t>(std::count(extra.begin(), extra.end(), '\n')));
  }
}

}  // namespace
