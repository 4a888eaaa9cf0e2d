// The loop the runtime library closes: a generated log hides an effect; `diagnose` on half of its
// rows writes the extended model (its report doubles as a coefficient file); `simulate KIND
// --like` with that file reproduces the other half's readings to within their noise, where the
// plug-in's published model does not; and the noise it draws has the generator's standard
// deviation. The generators (diagnose_generators.hpp) draw their readings with their own
// arithmetic (std::pow, their own clamps), not lib/models'.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "cli_harness.hpp"
#include "diagnose_generators.hpp"
#include "epuck2/calibrate/battery_json.hpp"
#include "epuck2/coefficients/model_file.hpp"

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

Csv parse_loop(const std::string& text) {
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

double sample_sd(const std::vector<double>& x) {
  double m = 0, v = 0;
  for (double e : x) m += e / static_cast<double>(x.size());
  for (double e : x) v += (e - m) * (e - m) / static_cast<double>(x.size() - 1);
  return std::sqrt(v);
}

/// The log with the rows `keep` (indices into c.rows, ascending).
std::string join_rows(const Csv& c, const std::vector<std::size_t>& keep) {
  std::string out;
  for (const auto& p : c.preamble) out += p + "\n";
  for (std::size_t i : keep) out += c.rows[i] + "\n";
  return out;
}

/// A time series split in two logs that both still describe the run: a command (drive: the two
/// wheel speeds; battery: the speed) holds from its row to the next, so a row where it changes
/// (and the first row, time 0 of the run) goes into both halves, or a half's zero-order hold
/// would move the robot at the wrong time; the other rows are dealt by parity. `compared` are
/// the check half's rows that the fit half does not have (positions within the check half).
struct Halves {
  std::vector<std::size_t> fit, check, compared;
};
Halves split_run(const Csv& c, const std::vector<std::string>& command_columns) {
  std::vector<std::size_t> at;
  for (const auto& name : command_columns)
    for (std::size_t k = 0; k < c.header.size(); ++k)
      if (c.header[k] == name) at.push_back(k);
  Halves h;
  std::vector<std::string> previous;
  for (std::size_t i = 0; i < c.rows.size(); ++i) {
    const auto cells = split(c.rows[i]);
    std::vector<std::string> command;
    for (std::size_t k : at) command.push_back(cells.at(k));
    const bool changes = i == 0 || command != previous;
    previous = command;
    if (changes || i % 2 == 0) h.fit.push_back(i);
    if (changes || i % 2 == 1) {
      if (!changes) h.compared.push_back(h.check.size());
      h.check.push_back(i);
    }
  }
  return h;
}

template <class T>
std::vector<T> pick(const std::vector<T>& v, const std::vector<std::size_t>& at) {
  std::vector<T> out;
  for (std::size_t i : at) out.push_back(v.at(i));
  return out;
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
  const Csv log = parse_loop(gen::make_log(c.kind, c.seed, h));
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
        ASSERT_FALSE(j.contains("effects_not_in_model")) << j.dump();
        switch (c.kind) {
          case logs::Kind::proximity: (void)epuck2::coefficients::proximity_model_from_json(j, ext); break;
          case logs::Kind::light: (void)epuck2::coefficients::light_model_from_json(j, ext); break;
          case logs::Kind::ground: (void)epuck2::coefficients::ground_model_from_json(j, ext); break;
          case logs::Kind::camera: (void)epuck2::coefficients::camera_model_from_json(j, ext); break;
          default: break;
        }
      }());

  const std::vector<std::string> reading = c.kind == logs::Kind::camera ? std::vector<std::string>{"px", "py"}
                                                                        : std::vector<std::string>{"value"};
  const Csv check = parse_loop(join(log, 1));
  const std::vector<double> measured = values(check, reading);
  const std::string sim_ext = (dir_ / "sim_ext.csv").string(), sim_plugin = (dir_ / "sim_plugin.csv").string(),
                    sim_noisy = (dir_ / "sim_noisy.csv").string();
  ASSERT_EQ(run("simulate " + kind + " --like \"" + check_half + "\" --coefficients \"" + ext + "\" -o \"" + sim_ext + "\"").exit_code, 0);
  ASSERT_EQ(run("simulate " + kind + " --like \"" + check_half + "\" -o \"" + sim_plugin + "\"").exit_code, 0);
  ASSERT_EQ(run("simulate " + kind + " --like \"" + check_half + "\" --coefficients \"" + ext + "\" --noise --seed 11 -o \"" +
                sim_noisy + "\"").exit_code, 0);
  const std::vector<double> plugin = values(parse_loop(slurp(sim_plugin)), reading);
  const std::vector<double> ext_values = values(parse_loop(slurp(sim_ext)), reading);
  const std::vector<double> noisy = values(parse_loop(slurp(sim_noisy)), reading);
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
  const auto sd = sample_sd;
  // Within 10 %, or within 3 standard errors of the ratio of two sd estimates from n readings
  // each (sqrt(1/(2n) + 1/(2n)) = 1/sqrt(n)) where n is too small for 10 % to be a test of the
  // model rather than of the draw (a half log of 150 readings: 24 %).
  const double n = static_cast<double>(simulated_noise.size());
  const double tolerance = std::max(kNoiseTolerance, 3.0 / std::sqrt(n));
  EXPECT_NEAR(sd(simulated_noise), sd(measured_noise), tolerance * sd(measured_noise))
      << c << "; the extended model's noise: " << nlohmann::json::parse(slurp(ext)).at("noise").dump();
  std::printf("[loop] %s/%s: MSE/variance %.3f (plug-in %.3g), noise sd ratio %.3f over %zu readings\n",
              kind.c_str(), c.cause.c_str(), mse(measured, ext_values) / variance, mse(measured, plugin) / variance,
              sd(simulated_noise) / sd(measured_noise), simulated_noise.size());
}

// Noise: ground 5 counts, light 15 counts, proximity 10 counts, camera 0.5 px
// (diagnose_generators.hpp). One seed per effect, the first whose drawn effect matters.
// incidence_angle: the generator's angle_deg column (0..60 degrees), which simulate --like reads.
// covariate:temperature_c: the generator's temperature_c column, which the model's covariate
// effect reads (slope and centre from the diagnosis).
INSTANTIATE_TEST_SUITE_P(
    EveryStaticKind, ModelLoop,
    ::testing::Values(Case{logs::Kind::ground, "black_offset", 3, 5.0}, Case{logs::Kind::ground, "white_level", 3, 5.0},
                      Case{logs::Kind::ground, "nonlinear_response", 3, 5.0}, Case{logs::Kind::ground, "sensor_gain", 3, 5.0},
                      Case{logs::Kind::ground, "sensor_offset", 3, 5.0},
                      Case{logs::Kind::light, "ambient_offset", 3, 15.0}, Case{logs::Kind::light, "falloff_exponent", 3, 15.0},
                      Case{logs::Kind::light, "sensor_gain", 3, 15.0}, Case{logs::Kind::proximity, "ambient_offset", 3, 10.0},
                      Case{logs::Kind::proximity, "long_tail", 3, 10.0}, Case{logs::Kind::proximity, "saturation", 3, 10.0},
                      Case{logs::Kind::proximity, "sensor_gain", 3, 10.0}, Case{logs::Kind::camera, "principal_offset", 3, 0.5},
                      Case{logs::Kind::camera, "radial_distortion", 3, 0.5},
                      Case{logs::Kind::proximity, "incidence_angle", 3, 10.0},
                      Case{logs::Kind::ground, "covariate:temperature_c", 3, 5.0}));

// ----- drive: three channels ----------------------------------------------------------------

struct DriveCase {
  std::string cause;
  std::uint64_t seed;
};
std::ostream& operator<<(std::ostream& os, const DriveCase& c) { return os << "drive/" << c.cause; }

class DriveLoop : public CliTest, public ::testing::WithParamInterface<DriveCase> {};

/// Rows of a generated drive log (the generator draws 600..2400): about 760 compared rows in the
/// check half, so that the noise sd ratio is tested at max(10 %, 3/sqrt(n)) = 11 %, and the ToF's
/// MSE, an average of n squared N(0, sd_i) draws, has a relative sd of sqrt(2/n) = 5 %: the 1.2
/// bound sits 4 of them above the noise alone.
constexpr int kDriveRows = 1600;

/// The drive's readings are three registers. ToF: the generator's noise is N(0, 2 mm + 3 mm per
/// metre of range) before rounding to whole mm, so each row's variance is (2 + 3 range)^2 + 1/12
/// with the range of that row (from the measured reading and the ToF's own true scale and offset:
/// the reading's noise moves the sd by 3/1000 of itself, nothing); the bound is 1.2 x the mean of
/// these. Encoders: the generator draws no encoder noise, the register is floor(steps per metre x
/// the wheel's travel). A model whose wheel travel is within a fraction of a step of the
/// generator's gives the same register or one step off, with a probability of that fraction; two
/// registers that were each rounded independently would differ with a variance of 1/6 step^2.
/// The encoders are asserted within 1.2 x 1/6 = 0.2 step^2: the model's wheels follow the
/// generator's to within a fraction of a step on almost every row. For speed_limit and
/// accel_limit, the effects the encoders see, the plug-in's model must exceed it.
constexpr double kEncoderBound = 1.2 / 6.0;

TEST_P(DriveLoop, DiagnoseOnHalfSimulatesTheOtherHalfWithinEachChannelsNoise) {
  const DriveCase c = GetParam();
  gen::Hidden h = gen::hidden(c.cause);
  const Csv log = parse_loop(gen::drive_log(c.seed, h, kDriveRows));
  const Halves halves = split_run(log, {"left_speed_cm_s", "right_speed_cm_s"});
  const std::string fit_half = write("fit.csv", join_rows(log, halves.fit));
  const std::string check_text = join_rows(log, halves.check);
  const std::string check_half = write("check.csv", check_text);
  const std::string ext = (dir_ / "ext.json").string();
  const CliRun d = run("diagnose --kind drive --json \"" + ext + "\" \"" + fit_half + "\"");
  ASSERT_EQ(d.exit_code, 0) << d.err;
  ASSERT_NE(d.out.find(c.cause), std::string::npos) << "the diagnosis did not name " << c.cause << ":\n" << d.out;
  const auto model_json = nlohmann::json::parse(slurp(ext));
  ASSERT_FALSE(model_json.contains("effects_not_in_model")) << model_json.dump();
  ASSERT_NO_THROW((void)epuck2::coefficients::drive_model_from_json(model_json, ext));

  const std::string sim_ext = (dir_ / "sim_ext.csv").string(), sim_plugin = (dir_ / "sim_plugin.csv").string(),
                    sim_noisy = (dir_ / "sim_noisy.csv").string();
  ASSERT_EQ(run("simulate drive --like \"" + check_half + "\" --coefficients \"" + ext + "\" -o \"" + sim_ext + "\"").exit_code, 0);
  ASSERT_EQ(run("simulate drive --like \"" + check_half + "\" -o \"" + sim_plugin + "\"").exit_code, 0);
  ASSERT_EQ(run("simulate drive --like \"" + check_half + "\" --coefficients \"" + ext + "\" --noise --seed 11 -o \"" + sim_noisy +
                "\"").exit_code, 0);
  const Csv check = parse_loop(check_text), ext_log = parse_loop(slurp(sim_ext)), plugin_log = parse_loop(slurp(sim_plugin)),
            noisy_log = parse_loop(slurp(sim_noisy));
  auto channel = [&](const Csv& l, const std::vector<std::string>& columns) { return values(l, columns); };
  // Only the rows the fit half did not see.
  auto compared = [&](const std::vector<double>& v, std::size_t per_row) {
    std::vector<double> out;
    for (std::size_t r : halves.compared)
      for (std::size_t k = 0; k < per_row; ++k) out.push_back(v.at(r * per_row + k));
    return out;
  };
  const auto tof = compared(channel(check, {"tof_mm"}), 1), tof_ext = compared(channel(ext_log, {"tof_mm"}), 1),
             tof_plugin = compared(channel(plugin_log, {"tof_mm"}), 1), tof_noisy = compared(channel(noisy_log, {"tof_mm"}), 1);
  const std::vector<std::string> encoders{"left_steps", "right_steps"};
  const auto steps = compared(channel(check, encoders), 2), steps_ext = compared(channel(ext_log, encoders), 2),
             steps_plugin = compared(channel(plugin_log, encoders), 2);
  ASSERT_EQ(tof_ext.size(), tof.size());
  ASSERT_GT(tof.size(), 500u);

  // ToF: the generator's variance, row by row (see kEncoderBound's comment).
  const double tof_k = c.cause == "tof_scale" ? h.truth.at("k") : 1.0;
  const double tof_offset = c.cause == "tof_offset" ? h.truth.at("offset_mm") : 0.0;
  double variance = 0;
  for (double reading : tof) {
    const double range_m = (reading - tof_offset) / (1000.0 * tof_k);
    variance += ((2.0 + 3.0 * range_m) * (2.0 + 3.0 * range_m) + 1.0 / 12.0) / static_cast<double>(tof.size());
  }
  EXPECT_LE(mse(tof, tof_ext), kMseBound * variance) << c << ": ToF";
  EXPECT_GT(mse(tof, tof_plugin), kMseBound * variance) << c << ": the plug-in's model already reproduces the ToF";
  // Encoders: register differences (the int16 wrap taken out).
  auto wrapped_mse = [](const std::vector<double>& a, const std::vector<double>& b) {
    std::vector<double> e(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) e[i] = std::remainder(a[i] - b[i], 65536.0);
    return mse(e, std::vector<double>(e.size(), 0.0));
  };
  EXPECT_LE(wrapped_mse(steps, steps_ext), kEncoderBound) << c << ": encoders";
  if (c.cause == "speed_limit" || c.cause == "accel_limit")
    EXPECT_GT(wrapped_mse(steps, steps_plugin), kEncoderBound) << c << ": the plug-in's model already reproduces the encoders";
  // The ToF's noise: simulated (noisy - noiseless) against measured (measured - noiseless).
  std::vector<double> simulated_noise, measured_noise;
  for (std::size_t i = 0; i < tof.size(); ++i) {
    simulated_noise.push_back(tof_noisy[i] - tof_ext[i]);
    measured_noise.push_back(tof[i] - tof_ext[i]);
  }
  const double n = static_cast<double>(simulated_noise.size());
  const double tolerance = std::max(kNoiseTolerance, 3.0 / std::sqrt(n));
  EXPECT_NEAR(sample_sd(simulated_noise), sample_sd(measured_noise), tolerance * sample_sd(measured_noise))
      << c << "; the extended model's noise: " << model_json.at("noise").dump();
  std::printf("[loop] drive/%s: ToF MSE/variance %.3f (plug-in %.3g), encoders MSE %.3f step^2 (plug-in %.3g), ToF noise sd ratio "
              "%.3f over %zu readings\n",
              c.cause.c_str(), mse(tof, tof_ext) / variance, mse(tof, tof_plugin) / variance, wrapped_mse(steps, steps_ext),
              wrapped_mse(steps, steps_plugin), sample_sd(simulated_noise) / sample_sd(measured_noise), simulated_noise.size());
}

INSTANTIATE_TEST_SUITE_P(EveryDriveEffect, DriveLoop,
                         ::testing::Values(DriveCase{"speed_limit", 3}, DriveCase{"accel_limit", 3}, DriveCase{"wheel_slip", 3},
                                           DriveCase{"speed_scale", 3}, DriveCase{"latency", 3}, DriveCase{"tof_offset", 3},
                                           DriveCase{"tof_scale", 3}));

// ----- battery: the charge of a discharge run ------------------------------------------------

class BatteryLoop : public CliTest, public ::testing::WithParamInterface<std::uint64_t> {};

/// The generator (diagnose_generators.hpp) runs the corrected Cubic with the plug-in's tables and
/// time running 1/k as fast, a reading every 5..30 s with noise N(0, sd), sd drawn in 0.01..0.03
/// per log (Hidden::noise_sd), not rounded. The log's last row is the moment the robot stopped: as
/// the diagnosis, it is simulated, not compared.
TEST_P(BatteryLoop, CapacityScaleOnHalfSimulatesTheOtherHalfWithinItsNoise) {
  gen::Hidden h = gen::hidden("capacity_scale");
  const Csv log = parse_loop(gen::battery_log(GetParam(), h));
  ASSERT_GT(h.noise_sd, 0.0);
  const Halves halves = split_run(log, {"speed_cm_s"});
  const std::string fit_half = write("fit.csv", join_rows(log, halves.fit));
  const std::string check_text = join_rows(log, halves.check);
  const std::string check_half = write("check.csv", check_text);
  const std::string ext = (dir_ / "ext.json").string();
  const CliRun d = run("diagnose --kind battery --coefficients plugin --json \"" + ext + "\" \"" + fit_half + "\"");
  ASSERT_EQ(d.exit_code, 0) << d.err;
  ASSERT_NE(d.out.find("capacity_scale"), std::string::npos) << d.out;
  const auto model_json = nlohmann::json::parse(slurp(ext));
  ASSERT_FALSE(model_json.contains("effects_not_in_model")) << model_json.dump();
  const auto model = epuck2::coefficients::battery_model_from_json(model_json, ext);
  EXPECT_EQ(model.model, epuck2::models::battery::Model::cubic);

  const std::string sim_ext = (dir_ / "sim_ext.csv").string(), sim_plugin = (dir_ / "sim_plugin.csv").string(),
                    sim_noisy = (dir_ / "sim_noisy.csv").string();
  ASSERT_EQ(run("simulate battery --like \"" + check_half + "\" --coefficients \"" + ext + "\" -o \"" + sim_ext + "\"").exit_code, 0);
  const CliRun p = run("simulate battery --like \"" + check_half + "\" -o \"" + sim_plugin + "\"");
  ASSERT_EQ(p.exit_code, 0) << p.err;
  ASSERT_EQ(run("simulate battery --like \"" + check_half + "\" --coefficients \"" + ext + "\" --noise --seed 11 -o \"" + sim_noisy +
                "\"").exit_code, 0);
  std::vector<std::size_t> rows = halves.compared;
  if (!rows.empty() && halves.check.at(rows.back()) + 1 == log.rows.size()) rows.pop_back();  // the stop
  const auto charge = pick(values(parse_loop(check_text), {"charge"}), rows);
  const auto ext_values = pick(values(parse_loop(slurp(sim_ext)), {"charge"}), rows);
  const auto plugin = pick(values(parse_loop(slurp(sim_plugin)), {"charge"}), rows);
  const auto noisy = pick(values(parse_loop(slurp(sim_noisy)), {"charge"}), rows);
  ASSERT_GT(charge.size(), 100u);
  const double variance = h.noise_sd * h.noise_sd;
  EXPECT_LE(mse(charge, ext_values), kMseBound * variance);
  EXPECT_GT(mse(charge, plugin), kMseBound * variance) << "the plug-in's model already reproduces the log";
  std::vector<double> simulated_noise, measured_noise;
  for (std::size_t i = 0; i < charge.size(); ++i) {
    simulated_noise.push_back(noisy[i] - ext_values[i]);
    measured_noise.push_back(charge[i] - ext_values[i]);
  }
  const double n = static_cast<double>(simulated_noise.size());
  const double tolerance = std::max(kNoiseTolerance, 3.0 / std::sqrt(n));
  EXPECT_NEAR(sample_sd(simulated_noise), sample_sd(measured_noise), tolerance * sample_sd(measured_noise));
  std::printf("[loop] battery/capacity_scale (k %.4f, noise %.4f): MSE/variance %.3f (plug-in %.3g), noise sd ratio %.3f over %zu "
              "readings\n",
              h.truth.at("k"), h.noise_sd, mse(charge, ext_values) / variance, mse(charge, plugin) / variance,
              sample_sd(simulated_noise) / sample_sd(measured_noise), simulated_noise.size());
}

INSTANTIATE_TEST_SUITE_P(CapacityScale, BatteryLoop, ::testing::Values(3));

// ----- simulate --like: what the loop relies on ----------------------------------------------

class SimulateLike : public CliTest {};

/// A diagnosis against its own extended model (diagnose --coefficients ext.json) finds nothing
/// more on the same logs: the base model of every kind comes from the file, the battery's with
/// its capacity scale.
TEST_F(SimulateLike, ADiagnosisAgainstItsOwnExtendedModelFindsNothingMore) {
  for (const std::string kind : {"battery", "ground"}) {
    const std::string logs = shipped(kind, kind == "battery" ? "robot-a" : "ground_virtual-epuck2-1");
    const std::string ext = (dir_ / (kind + "_ext.json")).string(), again = (dir_ / (kind + "_again.json")).string();
    const CliRun first = run("diagnose" + logs + " -o \"" + ext + "\"");
    ASSERT_EQ(first.exit_code, 0) << first.err;
    ASSERT_FALSE(nlohmann::json::parse(slurp(ext)).at("findings").empty()) << kind;
    const CliRun second = run("diagnose" + logs + " --coefficients \"" + ext + "\" -o \"" + again + "\"");
    ASSERT_EQ(second.exit_code, 0) << second.err;
    const nlohmann::json j = nlohmann::json::parse(slurp(again));
    EXPECT_TRUE(j.at("findings").empty()) << kind << ": " << j.at("findings").dump().substr(0, 300);
    EXPECT_EQ(j.at("verdict"), "none") << kind;
  }
}

TEST_F(SimulateLike, DiagnoseTakesABaseModelOfTheLogsKindOnly) {
  const CliRun wrong = run("diagnose" + shipped("ground", "ground_virtual-epuck2-1") + " --coefficients \"" +
                           std::string(EPUCK2_SOURCE_DIR) + "/data/fitted/light.json\"");
  EXPECT_EQ(wrong.exit_code, 2);
  EXPECT_NE(wrong.err.find("ground"), std::string::npos) << wrong.err;
  const CliRun effects = run("diagnose" + shipped("ground", "ground_virtual-epuck2-1") + " --effects black_offset,black_offset,nope");
  EXPECT_EQ(effects.exit_code, 2);
  EXPECT_NE(effects.err.find("'nope'"), std::string::npos) << effects.err;
}

/// codegen of a battery diagnosis writes the model it found: epuck2::fitted::battery_model() with
/// the capacity scale of the report's extended model (the shipped robot-a logs: a capacity_scale
/// finding, k above 1: the virtual robot's robot a holds 0.5 % more and draws its current through
/// 10 % less resistance, docs in data/raw/battery/README.md).
TEST_F(SimulateLike, CodegenOfABatteryDiagnosisCarriesItsCapacityScale) {
  const std::string logs = shipped("battery", "robot-a");
  const std::string ext = (dir_ / "battery_ext.json").string(), header = (dir_ / "battery_ext.hpp").string();
  ASSERT_EQ(run("diagnose" + logs + " -o \"" + ext + "\"").exit_code, 0);
  const nlohmann::json j = nlohmann::json::parse(slurp(ext));
  const double k = j.at("effects").at("capacity_scale").at("k").get<double>();
  EXPECT_GT(k, 1.0);
  EXPECT_LT(k, 1.05);
  const CliRun cg = run("codegen \"" + ext + "\" -o \"" + header + "\"");
  ASSERT_EQ(cg.exit_code, 0) << cg.err;
  const std::string text = slurp(header);
  EXPECT_NE(text.find("inline models::sensors::BatteryModel battery_model()"), std::string::npos);
  // The header's literal, read back, is the report's k (codegen writes round-trip digits).
  const std::size_t at = text.find("m.capacity.k = ");
  ASSERT_NE(at, std::string::npos);
  EXPECT_EQ(std::stod(text.substr(at + 15)), k);
}

/// A covariate effect reads its column from the log: none, no simulation (exit 2, the column
/// named); with it, the reading moves by slope x (column - centre).
TEST_F(SimulateLike, ACovariateEffectReadsItsColumn) {
  s::GroundModel g;
  g.covariates = {{"temperature_c", 2.0, 30.0}};
  const std::string model = write("g.json", epuck2::coefficients::model_to_json(g).dump());
  const std::string with = write("with.csv", "grey,sensor,value,temperature_c\n0.5,0,500,35\n0.5,1,500,25\n");
  const std::string without = write("without.csv", "grey,sensor,value\n0.5,0,500\n");
  const CliRun bad = run("simulate ground --like \"" + without + "\" --coefficients \"" + model + "\"");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("covariate:temperature_c"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("'temperature_c'"), std::string::npos) << bad.err;
  const CliRun good = run("simulate ground --like \"" + with + "\" --coefficients \"" + model + "\"");
  ASSERT_EQ(good.exit_code, 0) << good.err;
  // 1023 x 0.5 + 2 x (35 - 30), and 2 x (25 - 30).
  EXPECT_EQ(values(parse_loop(good.out), {"value"}), (std::vector<double>{521.5, 501.5}));
}

TEST_F(SimulateLike, BatteryLikeRunsTheLogsSpeedsAndTimesAndLeavesItsVoltageOut) {
  const std::string log = write("b.csv", "time_s,speed_cm_s,charge,voltage_v\n0,5,0.99,4.2\n100,5,0.95,4.1\n200,5,0.9,4.0\n");
  const CliRun r = run("simulate battery --like \"" + log + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Csv out = parse_loop(r.out);
  EXPECT_EQ(out.header, (std::vector<std::string>{"time_s", "speed_cm_s", "charge"}));
  // A first reading >= 0.9 is the run's full charge; then the plug-in's Cubic at 5 cm/s, whose
  // curve (d + c t + b t^2 + a t^3, the plug-in's published row) it follows from the moment the
  // firmware filter's start x' = -x/tau + c (from 1 - d above the curve) reaches it, t* = tau
  // ln(1 + (1 - d)/(-c tau)) (docs/battery-models.md), whatever the log's row spacing.
  const auto charge = values(out, {"charge"});
  ASSERT_EQ(charge.size(), 3u);
  EXPECT_EQ(charge[0], 1.0);
  const double q[4] = {0.9603929712, -1.9429015609e-04, 3.4602913169e-08, -2.5372952124e-12};
  const double tau = 2.2407, t_star = tau * std::log(1 + (1 - q[0]) / (-q[1] * tau)), t = 200 - t_star;
  EXPECT_NEAR(t_star, 10.13, 0.01);
  EXPECT_NEAR(charge[2], q[0] + q[1] * t + q[2] * t * t + q[3] * t * t * t, 1e-6);
  // The two modes' options do not mix.
  const std::string profile = write("p.csv", "time_s,speed_cm_s\n0,5\n10,0\n");
  EXPECT_EQ(run("simulate battery --like \"" + log + "\" --profile \"" + profile + "\"").exit_code, 2);
  EXPECT_EQ(run("simulate battery --model cubic --noise --profile \"" + profile + "\"").exit_code, 2);
  const CliRun none = run("simulate battery --model cubic");
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find("--profile is required"), std::string::npos) << none.err;
  const CliRun bad_model = run("simulate battery --like \"" + log + "\" --battery-model cubik");
  EXPECT_EQ(bad_model.exit_code, 2);
  EXPECT_NE(bad_model.err.find("did you mean 'cubic'?"), std::string::npos) << bad_model.err;
}

/// `--coefficients fitted` is the compiled-in header's battery tables, which codegen wrote from
/// data/fitted/battery.json: the same charges as that file (the Cubic, no effect; without noise),
/// and not the plug-in's. Another kind has no compiled-in model: exit 2 naming its file. A battery
/// log without a charge column (voltage_v only) cannot be simulated: exit 2 naming the column.
TEST_F(SimulateLike, FittedIsTheCompiledInBatteryTablesOnly) {
  const std::string log = write("b.csv", "time_s,speed_cm_s,charge\n0,5,0.99\n1000,5,0.8\n3000,5,0.5\n");
  const CliRun fitted = run("simulate battery --like \"" + log + "\" --coefficients fitted");
  ASSERT_EQ(fitted.exit_code, 0) << fitted.err;
  const CliRun file = run("simulate battery --like \"" + log + "\" --coefficients \"" + std::string(EPUCK2_SOURCE_DIR) +
                          "/data/fitted/battery.json\"");
  ASSERT_EQ(file.exit_code, 0) << file.err;
  const CliRun plugin = run("simulate battery --like \"" + log + "\" --coefficients plugin");
  ASSERT_EQ(plugin.exit_code, 0) << plugin.err;
  const auto f = values(parse_loop(fitted.out), {"charge"}), j = values(parse_loop(file.out), {"charge"}), p = values(parse_loop(plugin.out), {"charge"});
  ASSERT_EQ(f.size(), 3u);
  EXPECT_EQ(f, j);
  EXPECT_NE(f[2], p[2]);
  const CliRun ground = run("diagnose" + shipped("ground", "ground_virtual-epuck2-1") + " --coefficients fitted");
  EXPECT_EQ(ground.exit_code, 2);
  EXPECT_NE(ground.err.find("data/fitted/ground.json"), std::string::npos) << ground.err;
  const std::string volts = write("v.csv", "time_s,speed_cm_s,voltage_v\n0,5,4.2\n100,5,4.1\n");
  const CliRun no_charge = run("simulate battery --like \"" + volts + "\"");
  EXPECT_EQ(no_charge.exit_code, 2);
  EXPECT_NE(no_charge.err.find("'charge'"), std::string::npos) << no_charge.err;
}

/// codegen keeps a model's covariate effects (a diagnose -o report is a coefficient file for it).
TEST_F(SimulateLike, CodegenEmitsTheCovariates) {
  s::GroundModel g;
  g.covariates = {{"temperature_c", 2.0, 30.5}};
  const std::string model = write("g.json", epuck2::coefficients::model_to_json(g).dump());
  const std::string header = (dir_ / "g.hpp").string();
  ASSERT_EQ(run("codegen \"" + model + "\" -o \"" + header + "\"").exit_code, 0);
  EXPECT_NE(slurp(header).find("  m.covariates = {{\"temperature_c\", 2, 30.5}};\n"), std::string::npos) << slurp(header);
}

// ----- round trips --------------------------------------------------------------------------

TEST(ModelFile, JsonModelJsonRoundTripsEveryKind) {
  s::ProximityModel p;
  p.base = {190.0, -29.0, 1.02, 0.05};
  p.effects.ambient.offset_raw = 12.5;
  p.effects.gains.gain = {1, 1.1, 0.9, 1, 1, 1.05, 1, 1};
  p.effects.tail = {80.0, 0.03};
  p.effects.saturation.level_raw = 3900;
  p.noise_sd_raw = {10, 11, 12, 10, 10, 10, 10, 9};
  const auto p2 = epuck2::coefficients::proximity_model_from_json(epuck2::coefficients::model_to_json(p), "p.json");
  EXPECT_EQ(p2.base.a_per_m2, 190.0);
  EXPECT_EQ(p2.effects.ambient.offset_raw, 12.5);
  EXPECT_EQ(p2.effects.gains.gain[2], 0.9);
  EXPECT_EQ(p2.effects.tail.length_m, 0.03);
  EXPECT_EQ(p2.effects.saturation.level_raw, 3900);
  EXPECT_EQ(p2.effects.incidence.k, 0.0);
  EXPECT_EQ(p2.noise_sd_raw[7], 9.0);
  EXPECT_EQ(epuck2::coefficients::model_to_json(p2), epuck2::coefficients::model_to_json(p));

  s::GroundModel g;
  g.sensors = {{{900, 60}, {950, 50}, {880, 70}}};
  g.effects.exponent = 1.2;
  g.noise_sd_raw = {5, 5, 5};
  const auto gj = epuck2::coefficients::model_to_json(g);
  EXPECT_EQ(epuck2::coefficients::model_to_json(epuck2::coefficients::ground_model_from_json(gj, "g.json")), gj);
  EXPECT_FALSE(gj.at("noise").at("ground").contains("per_sensor_sd"));  // equal sensors: one sd

  s::DriveModel dm;
  dm.steps_per_m = 7700;
  dm.effects.slip.tau_s = 0.2;
  dm.effects.latency.delay_s = 0.05;
  dm.effects.speed_limit.max_cm_s = 12;
  dm.tof_noise_sd_mm = 3;
  const auto dj = epuck2::coefficients::model_to_json(dm);
  EXPECT_EQ(epuck2::coefficients::model_to_json(epuck2::coefficients::drive_model_from_json(dj, "d.json")), dj);
  EXPECT_EQ(dj.at("effects").at("latency").at("delay_s"), 0.05);
  EXPECT_FALSE(dj.at("effects").contains("accel_limit"));  // neutral effects are not written

  // covariate:NAME, any kind: slope and centre under the catalogue's name.
  g.covariates = {{"temperature_c", 2.5, 30.1}};
  const auto gcj = epuck2::coefficients::model_to_json(g);
  EXPECT_EQ(gcj.at("effects").at("covariate:temperature_c").at("centre"), 30.1);
  const auto g2 = epuck2::coefficients::ground_model_from_json(gcj, "g.json");
  ASSERT_EQ(g2.covariates.size(), 1u);
  EXPECT_EQ(g2.covariates[0].column, "temperature_c");
  EXPECT_EQ(g2.covariates[0].slope, 2.5);
  EXPECT_EQ(epuck2::coefficients::model_to_json(g2), gcj);

  s::CameraModel cm;
  cm.base.horizontal_fov_rad = s::deg_to_rad(31.0);
  cm.base.cx_px = 82;
  cm.distortion.k1 = -0.2;
  const auto cj = epuck2::coefficients::model_to_json(cm);
  EXPECT_NEAR(cj.at("parameters").at("fov_deg").get<double>(), 31.0, 1e-12);
  EXPECT_EQ(epuck2::coefficients::model_to_json(epuck2::coefficients::camera_model_from_json(cj, "c.json")), cj);

  namespace mb = epuck2::models::battery;
  s::BatteryModel bm;
  bm.model = mb::Model::approximated;
  bm.capacity.k = 1.07;
  bm.noise_sd = 0.02;
  bm.covariates = {{"temperature_c", 0.002, 29.5}};
  const auto bj = epuck2::coefficients::model_to_json(bm);
  EXPECT_EQ(bj.at("battery_model"), "approximated");
  EXPECT_EQ(bj.at("effects").at("capacity_scale").at("k"), 1.07);
  const auto bm2 = epuck2::coefficients::battery_model_from_json(bj, "b.json");
  EXPECT_EQ(epuck2::coefficients::model_to_json(bm2), bj);
  EXPECT_EQ(bm2.model, mb::Model::approximated);
  EXPECT_EQ(bm2.noise_sd, 0.02);
  ASSERT_EQ(bm2.covariates.size(), 1u);
  EXPECT_EQ(bm2.covariates[0].centre, 29.5);
  // The tables bit for bit (what the simulation runs).
  const mb::Tables& plugin = mb::plugin_tables();
  for (int k = 0; k < mb::kSpeedCount; ++k) {
    EXPECT_EQ(bm2.tables.cubic[k].a, plugin.cubic[k].a);
    EXPECT_EQ(bm2.tables.cubic[k].d, plugin.cubic[k].d);
    EXPECT_EQ(bm2.tables.cubic[k].end_s, plugin.cubic[k].end_s);
    EXPECT_EQ(bm2.tables.segments[k][2].m, plugin.segments[k][2].m);
    EXPECT_EQ(bm2.tables.linear_slope_per_s[k], plugin.linear_slope_per_s[k]);
  }
  EXPECT_EQ(bm2.tables.simple_moving_slope_per_s, plugin.simple_moving_slope_per_s);
  // Neutral: no capacity_scale written, the Cubic when the file names no discharge model.
  nlohmann::json neutral = epuck2::coefficients::model_to_json(s::BatteryModel{});
  EXPECT_FALSE(neutral.at("effects").contains("capacity_scale"));
  neutral.erase("battery_model");
  EXPECT_EQ(epuck2::coefficients::battery_model_from_json(neutral, "n.json").model, mb::Model::cubic);
}

TEST(ModelFile, BadFilesNameTheKey) {
  nlohmann::json j = {{"kind", "light"}, {"parameters", {{"gamma", "x"}}}};
  try {
    (void)epuck2::coefficients::light_model_from_json(j, "bad.json");
    FAIL() << "accepted a text gamma";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.json: parameters.gamma"), std::string::npos) << e.what();
  }
  nlohmann::json wrong = {{"kind", "ground"}, {"parameters", {{"gamma", 0.07}}}};
  EXPECT_THROW((void)epuck2::coefficients::light_model_from_json(wrong, "g.json"), std::runtime_error);
  nlohmann::json no_centre = epuck2::coefficients::model_to_json(s::GroundModel{});
  no_centre["effects"]["covariate:temperature_c"] = {{"slope", 2.0}};
  try {
    (void)epuck2::coefficients::ground_model_from_json(no_centre, "c.json");
    FAIL() << "accepted a covariate without its centre";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("c.json: missing effects.covariate:temperature_c.centre"), std::string::npos) << e.what();
  }
  nlohmann::json bad_model = epuck2::coefficients::model_to_json(s::BatteryModel{});
  bad_model["battery_model"] = "quartic";
  EXPECT_THROW((void)epuck2::coefficients::battery_model_from_json(bad_model, "b.json"), std::runtime_error);
}

/// The shipped calibration files are models: base from `parameters`, noise from `noise` (when the
/// file has it).
TEST(ModelFile, ShippedCoefficientFilesReadAsModels) {
  const std::string dir = std::string(EPUCK2_SOURCE_DIR) + "/data/fitted/";
  auto read = [&](const std::string& k) { return nlohmann::json::parse(slurp(dir + k + ".json")); };
  const auto p = epuck2::coefficients::proximity_model_from_json(read("proximity"), "proximity.json");
  EXPECT_EQ(p.base.a_per_m2, read("proximity").at("parameters").at("a").get<double>());
  const auto g = epuck2::coefficients::ground_model_from_json(read("ground"), "ground.json");
  EXPECT_GT(g.sensors[0].offset_raw, 0.0);
  EXPECT_NO_THROW((void)epuck2::coefficients::light_model_from_json(read("light"), "light.json"));
  EXPECT_NO_THROW((void)epuck2::coefficients::camera_model_from_json(read("camera"), "camera.json"));
  EXPECT_NO_THROW((void)epuck2::coefficients::drive_model_from_json(read("drive"), "drive.json"));
  // The battery file: its tables, the Cubic, and its speeds' residual sd as the charge noise.
  const auto b = epuck2::coefficients::battery_model_from_json(read("battery"), "battery.json");
  const auto tables = epuck2::coefficients::battery_tables_from_json(read("battery"), "battery.json");
  EXPECT_EQ(b.tables.cubic[7].b, tables.cubic[7].b);
  EXPECT_EQ(b.model, epuck2::models::battery::Model::cubic);
  double sum = 0;
  const auto battery = read("battery");
  for (const auto& speed : battery.at("speeds")) sum += std::pow(speed.at("noise_sd").get<double>(), 2);
  EXPECT_NEAR(b.noise_sd, std::sqrt(sum / 16.0), 1e-15);
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
  const auto pj = epuck2::coefficients::proximity_model_from_json(read("proximity"), "proximity.json");
  const auto ph = epuck2::fitted::proximity_model();
  for (double d : {0.0, 0.005, 0.02, 0.049, 0.06})
    for (int sensor : {0, 3, 7}) EXPECT_EQ(s::mean_raw(ph, sensor, d), s::mean_raw(pj, sensor, d)) << d;
  EXPECT_EQ(ph.noise_sd_raw, pj.noise_sd_raw);
  const auto lj = epuck2::coefficients::light_model_from_json(read("light"), "light.json");
  const auto lh = epuck2::fitted::light_model();
  for (double d : {0.02, 0.1, 0.3}) EXPECT_EQ(s::mean_raw(lh, 2, 1.0, d), s::mean_raw(lj, 2, 1.0, d));
  const auto gj = epuck2::coefficients::ground_model_from_json(read("ground"), "ground.json");
  const auto gh = epuck2::fitted::ground_model();
  for (double g : {0.0, 0.3, 1.0})
    for (int sensor : {0, 1, 2}) EXPECT_EQ(s::mean_raw(gh, sensor, g), s::mean_raw(gj, sensor, g));
  const auto cj = epuck2::coefficients::camera_model_from_json(read("camera"), "camera.json");
  const auto ch = epuck2::fitted::camera_model();
  EXPECT_EQ(s::mean_px(ch, 0.3, 0.05, -0.02), s::mean_px(cj, 0.3, 0.05, -0.02));
  const auto dj = epuck2::coefficients::drive_model_from_json(read("drive"), "drive.json");
  const auto dh = epuck2::fitted::drive_model();
  s::DriveSimulation a(dj, 1.0), b(dh, 1.0);
  s::StandardNormal na(5), nb(5);
  for (int i = 0; i < 50; ++i) {
    const auto ra = a.sample(0.1 * i, 5.0, 5.0, na), rb = b.sample(0.1 * i, 5.0, 5.0, nb);
    EXPECT_EQ(ra.tof_mm, rb.tof_mm);
    EXPECT_EQ(ra.left_steps, rb.left_steps);
  }
  // The battery as a model: discharge model, tables, capacity scale and noise, the same charge
  // over a two-hour run at 5 cm/s.
  const auto bj = epuck2::coefficients::battery_model_from_json(read("battery"), "battery.json");
  const auto bh = epuck2::fitted::battery_model();
  EXPECT_TRUE(bh.model == bj.model);
  EXPECT_EQ(bh.capacity.k, bj.capacity.k);
  EXPECT_EQ(bh.noise_sd, bj.noise_sd);
  std::vector<double> t, v;
  for (int i = 0; i <= 720; ++i) {
    t.push_back(10.0 * i);
    v.push_back(5.0);
  }
  EXPECT_EQ(s::battery_mean_charge(bh, t, v, 1.0), s::battery_mean_charge(bj, t, v, 1.0));
}

}  // namespace
