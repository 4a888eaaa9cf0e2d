// The loop the runtime library closes: a generated log hides an effect; `diagnose` on half of its
// rows writes the extended model (its report doubles as a coefficient file); `simulate KIND
// --like` with that file reproduces the other half's readings to within their noise, where the
// plug-in's published model does not; and the noise it draws has the generator's standard
// deviation. The generators (diagnose_generators.hpp) draw their readings with their own
// arithmetic (std::pow, their own clamps), not lib/models'.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "cli_harness.hpp"
#include "diagnose_generators.hpp"
#include "epuck2/calibrate/model_file.hpp"

using epuck2::testing::CliRun;
using epuck2::testing::CliTest;
using epuck2::testing::slurp;
namespace gen = epuck2::testing::diagnose;
namespace logs = epuck2::logs;
namespace s = epuck2::models::sensors;

namespace {

struct Csv {
  std::vector<std::string> preamble;  ///< comment and metadata lines, then the header
  std::vector<std::string> header;
  std::vector<std::string> rows;
};

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) out.push_back(cell);
  return out;
}

Csv parse(const std::string& text) {
  Csv c;
  std::stringstream ss(text);
  std::string line;
  while (std::getline(ss, line)) {
    if (line.empty()) continue;
    if (c.header.empty()) {
      c.preamble.push_back(line);
      if (line[0] != '#') c.header = split(line);
    } else {
      c.rows.push_back(line);
    }
  }
  return c;
}

std::string join(const Csv& c, int parity) {
  std::string out;
  for (const auto& p : c.preamble) out += p + "\n";
  for (std::size_t i = 0; i < c.rows.size(); ++i)
    if (static_cast<int>(i % 2) == parity) out += c.rows[i] + "\n";
  return out;
}

/// The values of `columns` of every row, flattened.
std::vector<double> values(const Csv& c, const std::vector<std::string>& columns) {
  std::vector<std::size_t> at;
  for (const auto& name : columns)
    for (std::size_t k = 0; k < c.header.size(); ++k)
      if (c.header[k] == name) at.push_back(k);
  std::vector<double> v;
  for (const auto& r : c.rows) {
    const auto cells = split(r);
    for (std::size_t k : at) v.push_back(std::stod(cells.at(k)));
  }
  return v;
}

double mse(const std::vector<double>& a, const std::vector<double>& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
  return sum / static_cast<double>(a.size());
}

struct Case {
  logs::Kind kind;
  std::string cause;
  std::uint64_t seed;
  double noise_sd;  ///< the generator's reading noise (diagnose_generators.hpp), reading units
};

std::ostream& operator<<(std::ostream& os, const Case& c) { return os << logs::to_string(c.kind) << "/" << c.cause; }

class ModelLoop : public CliTest, public ::testing::WithParamInterface<Case> {};

/// MSE <= 1.2 x the generator's noise variance (the bound): the readings' own noise is
/// 1 x; the rest allows for the fitted model's error and the readings' rounding.
constexpr double kMseBound = 1.2;
/// The drawn noise's sd within 10 % of the generator's.
constexpr double kNoiseTolerance = 0.10;

TEST_P(ModelLoop, DiagnoseOnHalfSimulatesTheOtherHalfWithinItsNoise) {
  const Case c = GetParam();
  gen::Hidden h = gen::hidden(c.cause);
  const Csv log = parse(gen::make_log(c.kind, c.seed, h));
  ASSERT_GT(log.rows.size(), 100u);
  const std::string fit_half = write("fit.csv", join(log, 0));
  const std::string check_half = write("check.csv", join(log, 1));
  const std::string kind(logs::to_string(c.kind));
  const std::string ext = (dir_ / "ext.json").string();

  const CliRun d = run("diagnose --kind " + kind + " --json \"" + ext + "\" \"" + fit_half + "\"");
  ASSERT_EQ(d.exit_code, 0) << d.err;
  ASSERT_NE(d.out.find(c.cause), std::string::npos) << "the diagnosis did not name " << c.cause << ":\n" << d.out;
  // The report reads back as a model of its kind (lib/calibrate's reader).
  ASSERT_NO_THROW(
      (void)[&] {
        const auto j = nlohmann::json::parse(slurp(ext));
        switch (c.kind) {
          case logs::Kind::proximity: (void)epuck2::calibrate::proximity_model_from_json(j, ext); break;
          case logs::Kind::light: (void)epuck2::calibrate::light_model_from_json(j, ext); break;
          case logs::Kind::ground: (void)epuck2::calibrate::ground_model_from_json(j, ext); break;
          case logs::Kind::camera: (void)epuck2::calibrate::camera_model_from_json(j, ext); break;
          default: break;
        }
      }());

  const std::vector<std::string> reading = c.kind == logs::Kind::camera ? std::vector<std::string>{"px", "py"}
                                                                        : std::vector<std::string>{"value"};
  const Csv check = parse(join(log, 1));
  const std::vector<double> measured = values(check, reading);
  const std::string sim_ext = (dir_ / "sim_ext.csv").string(), sim_plugin = (dir_ / "sim_plugin.csv").string(),
                    sim_noisy = (dir_ / "sim_noisy.csv").string();
  ASSERT_EQ(run("simulate " + kind + " --like \"" + check_half + "\" --coefficients \"" + ext + "\" -o \"" + sim_ext + "\"").exit_code, 0);
  ASSERT_EQ(run("simulate " + kind + " --like \"" + check_half + "\" -o \"" + sim_plugin + "\"").exit_code, 0);
  ASSERT_EQ(run("simulate " + kind + " --like \"" + check_half + "\" --coefficients \"" + ext + "\" --noise --seed 11 -o \"" +
                sim_noisy + "\"").exit_code, 0);
  const std::vector<double> plugin = values(parse(slurp(sim_plugin)), reading);
  const std::vector<double> ext_values = values(parse(slurp(sim_ext)), reading);
  const std::vector<double> noisy = values(parse(slurp(sim_noisy)), reading);
  ASSERT_EQ(ext_values.size(), measured.size());
  // A generated reading is rounded to a whole count (pixel): its noise variance is the drawn
  // noise's plus the rounding's 1/12.
  const double variance = c.noise_sd * c.noise_sd + 1.0 / 12.0;
  EXPECT_LE(mse(measured, ext_values), kMseBound * variance) << c;
  EXPECT_GT(mse(measured, plugin), kMseBound * variance) << c << ": the plug-in's model already reproduces the log";
  // The simulated noise against the measured noise on the same rows: noisy minus noiseless, and
  // measured minus noiseless, over readings away from the rails (which clip the noise).
  const double top = c.kind == logs::Kind::ground ? 1023 : 4095;
  std::vector<double> simulated_noise, measured_noise;
  for (std::size_t i = 0; i < noisy.size(); ++i)
    if (ext_values[i] > 4 * c.noise_sd && ext_values[i] < top - 4 * c.noise_sd) {
      simulated_noise.push_back(noisy[i] - ext_values[i]);
      measured_noise.push_back(measured[i] - ext_values[i]);
    }
  ASSERT_GT(simulated_noise.size(), 50u);
  auto sd = [](const std::vector<double>& x) {
    double m = 0, v = 0;
    for (double e : x) m += e / static_cast<double>(x.size());
    for (double e : x) v += (e - m) * (e - m) / static_cast<double>(x.size() - 1);
    return std::sqrt(v);
  };
  // Within 10 %, or within 3 standard errors of the ratio of two sd estimates from n readings
  // each (sqrt(1/(2n) + 1/(2n)) = 1/sqrt(n)) where n is too small for 10 % to be a test of the
  // model rather than of the draw (a half log of 150 readings: 24 %).
  const double n = static_cast<double>(simulated_noise.size());
  const double tolerance = std::max(kNoiseTolerance, 3.0 / std::sqrt(n));
  EXPECT_NEAR(sd(simulated_noise), sd(measured_noise), tolerance * sd(measured_noise))
      << c << "; the extended model's noise: " << nlohmann::json::parse(slurp(ext)).at("noise").dump();
}

// Noise: ground 5 counts, light 15 counts, proximity 10 counts, camera 0.5 px
// (diagnose_generators.hpp). One seed per effect, the first whose drawn effect matters.
INSTANTIATE_TEST_SUITE_P(
    EveryStaticKind, ModelLoop,
    ::testing::Values(Case{logs::Kind::ground, "black_offset", 3, 5.0}, Case{logs::Kind::ground, "white_level", 3, 5.0},
                      Case{logs::Kind::ground, "nonlinear_response", 3, 5.0}, Case{logs::Kind::ground, "sensor_gain", 3, 5.0},
                      Case{logs::Kind::light, "ambient_offset", 3, 15.0}, Case{logs::Kind::light, "falloff_exponent", 3, 15.0},
                      Case{logs::Kind::light, "sensor_gain", 3, 15.0}, Case{logs::Kind::proximity, "ambient_offset", 3, 10.0},
                      Case{logs::Kind::proximity, "long_tail", 3, 10.0}, Case{logs::Kind::proximity, "saturation", 3, 10.0},
                      Case{logs::Kind::proximity, "sensor_gain", 3, 10.0}, Case{logs::Kind::camera, "principal_offset", 3, 0.5},
                      Case{logs::Kind::camera, "radial_distortion", 3, 0.5}));

// ----- round trips --------------------------------------------------------------------------

TEST(ModelFile, JsonModelJsonRoundTripsEveryKind) {
  s::ProximityModel p;
  p.base = {190.0, -29.0, 1.02, 0.05};
  p.effects.ambient.offset_raw = 12.5;
  p.effects.gains.gain = {1, 1.1, 0.9, 1, 1, 1.05, 1, 1};
  p.effects.tail = {80.0, 0.03};
  p.effects.saturation.level_raw = 3900;
  p.noise_sd_raw = {10, 11, 12, 10, 10, 10, 10, 9};
  const auto p2 = epuck2::calibrate::proximity_model_from_json(epuck2::calibrate::model_to_json(p), "p.json");
  EXPECT_EQ(p2.base.a_per_m2, 190.0);
  EXPECT_EQ(p2.effects.ambient.offset_raw, 12.5);
  EXPECT_EQ(p2.effects.gains.gain[2], 0.9);
  EXPECT_EQ(p2.effects.tail.length_m, 0.03);
  EXPECT_EQ(p2.effects.saturation.level_raw, 3900);
  EXPECT_EQ(p2.effects.incidence.k, 0.0);
  EXPECT_EQ(p2.noise_sd_raw[7], 9.0);
  EXPECT_EQ(epuck2::calibrate::model_to_json(p2), epuck2::calibrate::model_to_json(p));

  s::GroundModel g;
  g.sensors = {{{900, 60}, {950, 50}, {880, 70}}};
  g.effects.exponent = 1.2;
  g.noise_sd_raw = {5, 5, 5};
  const auto gj = epuck2::calibrate::model_to_json(g);
  EXPECT_EQ(epuck2::calibrate::model_to_json(epuck2::calibrate::ground_model_from_json(gj, "g.json")), gj);
  EXPECT_FALSE(gj.at("noise").at("ground").contains("per_sensor_sd"));  // equal sensors: one sd

  s::DriveModel dm;
  dm.steps_per_m = 7700;
  dm.effects.slip.tau_s = 0.2;
  dm.effects.latency.delay_s = 0.05;
  dm.effects.speed_limit.max_cm_s = 12;
  dm.tof_noise_sd_mm = 3;
  const auto dj = epuck2::calibrate::model_to_json(dm);
  EXPECT_EQ(epuck2::calibrate::model_to_json(epuck2::calibrate::drive_model_from_json(dj, "d.json")), dj);
  EXPECT_EQ(dj.at("effects").at("latency").at("delay_s"), 0.05);
  EXPECT_FALSE(dj.at("effects").contains("accel_limit"));  // neutral effects are not written

  s::CameraModel cm;
  cm.base.horizontal_fov_rad = s::deg_to_rad(31.0);
  cm.base.cx_px = 82;
  cm.distortion.k1 = -0.2;
  const auto cj = epuck2::calibrate::model_to_json(cm);
  EXPECT_NEAR(cj.at("parameters").at("fov_deg").get<double>(), 31.0, 1e-12);
  EXPECT_EQ(epuck2::calibrate::model_to_json(epuck2::calibrate::camera_model_from_json(cj, "c.json")), cj);
}

TEST(ModelFile, BadFilesNameTheKey) {
  nlohmann::json j = {{"kind", "light"}, {"parameters", {{"gamma", "x"}}}};
  try {
    (void)epuck2::calibrate::light_model_from_json(j, "bad.json");
    FAIL() << "accepted a text gamma";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.json: parameters.gamma"), std::string::npos) << e.what();
  }
  nlohmann::json wrong = {{"kind", "ground"}, {"parameters", {{"gamma", 0.07}}}};
  EXPECT_THROW((void)epuck2::calibrate::light_model_from_json(wrong, "g.json"), std::runtime_error);
}

/// The shipped calibration files are models: base from `parameters`, noise from `noise` (when the
/// file has it).
TEST(ModelFile, ShippedCoefficientFilesReadAsModels) {
  const std::string dir = std::string(EPUCK2_SOURCE_DIR) + "/data/fitted/";
  auto read = [&](const std::string& k) { return nlohmann::json::parse(slurp(dir + k + ".json")); };
  const auto p = epuck2::calibrate::proximity_model_from_json(read("proximity"), "proximity.json");
  EXPECT_EQ(p.base.a_per_m2, read("proximity").at("parameters").at("a").get<double>());
  const auto g = epuck2::calibrate::ground_model_from_json(read("ground"), "ground.json");
  EXPECT_GT(g.sensors[0].offset_raw, 0.0);
  EXPECT_NO_THROW((void)epuck2::calibrate::light_model_from_json(read("light"), "light.json"));
  EXPECT_NO_THROW((void)epuck2::calibrate::camera_model_from_json(read("camera"), "camera.json"));
  EXPECT_NO_THROW((void)epuck2::calibrate::drive_model_from_json(read("drive"), "drive.json"));
}

}  // namespace

// Model -> generated header -> the same readings: the committed header (regenerated by
// scripts/regenerate.sh, checked byte for byte against codegen by test_safe_cli) returns the
// models the committed coefficient files hold.
#include "epuck2/fitted/coefficients.hpp"

namespace {

TEST(ModelFile, GeneratedHeaderGivesTheFilesReadings) {
  const std::string dir = std::string(EPUCK2_SOURCE_DIR) + "/data/fitted/";
  auto read = [&](const std::string& k) { return nlohmann::json::parse(slurp(dir + k + ".json")); };
  const auto pj = epuck2::calibrate::proximity_model_from_json(read("proximity"), "proximity.json");
  const auto ph = epuck2::fitted::proximity_model();
  for (double d : {0.0, 0.005, 0.02, 0.049, 0.06})
    for (int sensor : {0, 3, 7}) EXPECT_EQ(s::mean_raw(ph, sensor, d), s::mean_raw(pj, sensor, d)) << d;
  EXPECT_EQ(ph.noise_sd_raw, pj.noise_sd_raw);
  const auto lj = epuck2::calibrate::light_model_from_json(read("light"), "light.json");
  const auto lh = epuck2::fitted::light_model();
  for (double d : {0.02, 0.1, 0.3}) EXPECT_EQ(s::mean_raw(lh, 2, 1.0, d), s::mean_raw(lj, 2, 1.0, d));
  const auto gj = epuck2::calibrate::ground_model_from_json(read("ground"), "ground.json");
  const auto gh = epuck2::fitted::ground_model();
  for (double g : {0.0, 0.3, 1.0})
    for (int sensor : {0, 1, 2}) EXPECT_EQ(s::mean_raw(gh, sensor, g), s::mean_raw(gj, sensor, g));
  const auto cj = epuck2::calibrate::camera_model_from_json(read("camera"), "camera.json");
  const auto ch = epuck2::fitted::camera_model();
  EXPECT_EQ(s::mean_px(ch, 0.3, 0.05, -0.02), s::mean_px(cj, 0.3, 0.05, -0.02));
  const auto dj = epuck2::calibrate::drive_model_from_json(read("drive"), "drive.json");
  const auto dh = epuck2::fitted::drive_model();
  s::DriveSimulation a(dj, 1.0), b(dh, 1.0);
  s::StandardNormal na(5), nb(5);
  for (int i = 0; i < 50; ++i) {
    const auto ra = a.sample(0.1 * i, 5.0, 5.0, na), rb = b.sample(0.1 * i, 5.0, 5.0, nb);
    EXPECT_EQ(ra.tof_mm, rb.tof_mm);
    EXPECT_EQ(ra.left_steps, rb.left_steps);
  }
}

}  // namespace
