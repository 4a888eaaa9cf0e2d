// The virtual E-Puck2 battery: calibration to the published figures, the discharge simulator and
// the Table 5 checks. See battery.hpp for the model and data/raw/battery/README.md for the story.
#include "epuck2/virtual_robot/battery.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "epuck2/fit/problem.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"

namespace epuck2::virtual_robot::battery {

namespace {

/// Paper Table 5, "analytic" row, Cubic column: the average MSE of the per-speed cubic against the
/// logs. The scatter of the virtual logs is sized to it.
constexpr double kTable5CubicMse = 0.0020;

constexpr double kChargeSpan_v = kFullVoltage_v - kEmptyVoltage_v;

/// Samples per published curve in the calibration (u = t / end from 0 to 1).
constexpr int kCalibrationSamples = 41;

/// Weight of the prior LiPo OCV chart against the published curves (charge units per volt /
/// 0.8): small, it only pins the knots that the published curves do not reach and the one-
/// parameter stretch between the OCV curve and the depths of discharge.
constexpr double kPriorWeight = 0.15;
/// Weight of the curvature penalty (second differences departing from the prior's).
constexpr double kSmoothnessWeight = 0.5;

using fit::value_of;

double cubic_at(const mb::CubicRow& q, double t_s) {
  const double p[4] = {q.d, q.c, q.b, q.a};
  return mb::cubic_charge(p, t_s);
}

// Residual of the noise-free firmware reading against one published cubic, in charge units, at
// u_j = j / (n - 1) of the published lifetime end:
//   r_j = (OCV(1 - x u_j) - I R - 3.4) / 0.8 - Q(u_j end),  I = x C / end,
// x = depth of discharge reached at end (fraction of the nominal capacity C in A s), R = the path
// resistance. The filter's lag (2.5 s time constant) is negligible against hours.
class PublishedCurveResidual {
 public:
  PublishedCurveResidual(const mb::CubicRow& published, double capacity_As)
      : published_(published), capacity_As_(capacity_As) {}

  template <typename T>
  bool operator()(const T* ocv_knots_v, const T* resistance_ohm, const T* depth, T* residual) const {
    const T current_a = depth[0] * (capacity_As_ / published_.end_s);
    for (int j = 0; j < kCalibrationSamples; ++j) {
      const double u = static_cast<double>(j) / (kCalibrationSamples - 1);
      const T z = T(1.0) - depth[0] * u;
      const T reading_v = ocv_at(ocv_knots_v, z, value_of(z)) - current_a * resistance_ohm[0];
      residual[j] = (reading_v - T(kEmptyVoltage_v)) / T(kChargeSpan_v) - T(cubic_at(published_, u * published_.end_s));
    }
    return true;
  }

  static fit::ResidualBlock block(const mb::CubicRow& published, double capacity_As) {
    return fit::autodiff<kCalibrationSamples, kOcvKnotCount, 1, 1>(PublishedCurveResidual(published, capacity_As));
  }

 private:
  const mb::CubicRow published_;
  const double capacity_As_;
};

// Keeps the OCV knots near the LiPo chart where the data are silent:
//   r_k = w_p (g_k - prior_k) / 0.8                               (k = 0..20)
//   r_(21+k) = w_s (Δ²g_k - Δ²prior_k) / 0.8                       (k = 1..19)
class OcvPriorResidual {
 public:
  static constexpr int kResiduals = kOcvKnotCount + (kOcvKnotCount - 2);
  template <typename T>
  bool operator()(const T* g, T* r) const {
    for (int k = 0; k < kOcvKnotCount; ++k) r[k] = T(kPriorWeight / kChargeSpan_v) * (g[k] - T(kLipoOcvPrior_v[k]));
    for (int k = 1; k + 1 < kOcvKnotCount; ++k) {
      const double prior_curv = kLipoOcvPrior_v[k - 1] - 2 * kLipoOcvPrior_v[k] + kLipoOcvPrior_v[k + 1];
      r[kOcvKnotCount + k - 1] = T(kSmoothnessWeight / kChargeSpan_v) * (g[k - 1] - T(2.0) * g[k] + g[k + 1] - T(prior_curv));
    }
    return true;
  }
  static fit::ResidualBlock block() { return fit::autodiff<kResiduals, kOcvKnotCount>(OcvPriorResidual{}); }
};

/// SplitMix64 (Steele, Lea, Flood 2014): decorrelates nearby seeds.
std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

/// Portable random numbers: uniform from the top 53 bits of mt19937_64, normal by Box-Muller.
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = uniform();
    while (u1 <= 0.0) u1 = uniform();
    const double u2 = uniform();
    const double radius = std::sqrt(-2.0 * std::log(u1));
    const double angle = 2.0 * M_PI * u2;
    spare_ = radius * std::sin(angle);
    has_spare_ = true;
    return radius * std::cos(angle);
  }

 private:
  std::mt19937_64 engine_;
  double spare_ = 0;
  bool has_spare_ = false;
};

double interpolate_speed(const std::array<double, mb::kSpeedCount>& table, double speed_cm_s) {
  const double s = std::clamp(speed_cm_s, 0.0, static_cast<double>(mb::kSpeedCount - 1));
  const int lo = std::min(static_cast<int>(std::floor(s)), mb::kSpeedCount - 2);
  const double w = s - lo;
  return table[lo] + (table[lo + 1] - table[lo]) * w;
}

double ocv(const Calibration& cal, double z) {
  return ocv_at(cal.ocv_v.data(), z, z);
}

double charge_of(double voltage_v) { return (voltage_v - kEmptyVoltage_v) / kChargeSpan_v; }

/// Least-squares cubic of y against t, returning the mean squared residual.
double cubic_fit_mse(const std::vector<double>& t_s, const std::vector<double>& y) {
  const Eigen::Index n = static_cast<Eigen::Index>(t_s.size());
  if (n < 4) return std::numeric_limits<double>::quiet_NaN();
  constexpr double kTimeScale_s = 1e4;  // conditioning: t in units of 10^4 s
  Eigen::MatrixXd a(n, 4);
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double tau = t_s[i] / kTimeScale_s;
    a(i, 0) = 1;
    a(i, 1) = tau;
    a(i, 2) = tau * tau;
    a(i, 3) = tau * tau * tau;
    b(i) = y[i];
  }
  const Eigen::VectorXd coef = a.colPivHouseholderQr().solve(b);
  return (a * coef - b).squaredNorm() / static_cast<double>(n);
}

}  // namespace

double current_draw_a(const Calibration& cal, double speed_cm_s) { return interpolate_speed(cal.current_a, speed_cm_s); }
double stop_voltage_v(const Calibration& cal, double speed_cm_s) { return interpolate_speed(cal.stop_voltage_v, speed_cm_s); }

RobotParameters robot_a() {
  RobotParameters r;
  r.name = "virtual-e-puck2-a";
  r.capacity_scale = 1.005;
  r.resistance_scale = 0.9;
  return r;
}

RobotParameters robot_b() {
  RobotParameters r;
  r.name = "virtual-e-puck2-b";
  r.capacity_scale = 0.995;
  r.resistance_scale = 1.1;
  return r;
}

std::uint64_t reference_run_seed(std::uint64_t seed, int robot_index, int speed_cm_s) {
  return splitmix64(splitmix64(seed) ^ (static_cast<std::uint64_t>(robot_index) * 1000u + static_cast<std::uint64_t>(speed_cm_s)));
}

Run simulate(const std::vector<mb::ProfilePoint>& profile, const RobotParameters& robot, std::uint64_t seed,
             const SimulationOptions& options, const Calibration& cal) {
  constexpr double dt_s = kFilterUpdatePeriod_s;
  const double steps_real = options.log_interval_s / dt_s;
  const long steps_per_log = std::lround(steps_real);
  if (!(steps_per_log >= 1) || std::abs(steps_real - static_cast<double>(steps_per_log)) > 1e-9)
    throw std::invalid_argument("battery simulation: the log interval must be a positive multiple of 0.5 s");
  if (!(robot.capacity_scale > 0) || !(robot.current_scale >= 0) || !(robot.resistance_scale >= 0) || !(robot.pulse_scale >= 0))
    throw std::invalid_argument("battery simulation: robot scales must be positive (capacity) or non-negative");

  const double capacity_As = cal.capacity_Ah * robot.capacity_scale * kSecondsPerHour;
  const double resistance_ohm = cal.path_resistance_ohm * robot.resistance_scale;
  const double dip_v = cal.pulse_dip_v * robot.pulse_scale;
  const double mean_dip_v = dip_v * kPulseCatchProbability;
  const double adc_sd_counts = kAdcNoise_counts;
  Random rng(seed);

  // One firmware update: a burst of 32 conversions, all inside or all outside a load pulse. Each
  // conversion adds adc_sd_counts of noise and rounds to a whole count; with about a count of
  // noise the rounding error is uniform and independent of the input (dithered), so the burst's
  // mean is the input plus one normal of variance (sd^2 + 1/12) / 32 counts^2: drawn as such.
  const double burst_sd_counts = std::sqrt((adc_sd_counts * adc_sd_counts + 1.0 / 12.0) / kAdcSamplesPerReading);
  auto measure = [&](double terminal_v) {
    if (!options.noise) return terminal_v - mean_dip_v;
    const double input_v = terminal_v - (rng.uniform() < kPulseCatchProbability ? dip_v : 0.0);
    return (input_v * kAdcCountsPerVolt + burst_sd_counts * rng.normal()) / kAdcCountsPerVolt;
  };

  // The profile is walked forward once (points sorted by time, as commanded_speed_cm_s assumes).
  std::size_t next_point = 0;
  double speed_cm_s = 0;
  auto speed_at = [&](double t_s) {
    constexpr double kTimeSlack_s = 1e-9;
    while (next_point < profile.size() && profile[next_point].time_s <= t_s + kTimeSlack_s) speed_cm_s = profile[next_point++].speed_cm_s;
    return speed_cm_s;
  };

  Run run;
  double z = robot.initial_soc;
  double speed = speed_at(0.0);
  double current_a = current_draw_a(cal, speed) * robot.current_scale;
  double terminal_v = ocv(cal, z) - current_a * resistance_ohm;
  // The filter has settled before logging starts: its state is the mean reading at t = 0.
  double filtered_v = terminal_v - mean_dip_v;
  auto push = [&](double t_s, double v_cm_s) { run.rows.push_back(Row{t_s, v_cm_s, charge_of(filtered_v), filtered_v, z}); };
  push(0.0, speed);
  if (terminal_v <= stop_voltage_v(cal, speed)) {
    run.stopped = true;
    return run;
  }
  for (long k = 1;; ++k) {
    const double t_prev_s = static_cast<double>(k - 1) * dt_s;
    const double t_s = static_cast<double>(k) * dt_s;
    if (t_prev_s >= options.max_time_s) break;
    speed = speed_at(t_prev_s);
    current_a = current_draw_a(cal, speed) * robot.current_scale;
    const double stop_v = stop_voltage_v(cal, speed);
    const double v_prev = ocv(cal, z) - current_a * resistance_ohm;
    if (v_prev <= stop_v) {  // a change of speed asked for more than the cell can give
      run.stopped = true;
      run.stop_time_s = t_prev_s;
      if ((k - 1) % steps_per_log != 0) push(t_prev_s, speed);
      return run;
    }
    z -= current_a * dt_s / capacity_As;
    terminal_v = ocv(cal, z) - current_a * resistance_ohm;
    if (terminal_v <= stop_v) {
      const double fraction = (v_prev - stop_v) / (v_prev - terminal_v);
      run.stopped = true;
      run.stop_time_s = t_prev_s + fraction * dt_s;
      push(run.stop_time_s, speed);
      return run;
    }
    filtered_v = kFilterKeep * filtered_v + (1.0 - kFilterKeep) * measure(terminal_v);
    if (k % steps_per_log == 0) push(t_s, speed_at(t_s));  // the command in force at the row
  }
  return run;
}

Run simulate_protocol(double speed_cm_s, const RobotParameters& robot, std::uint64_t seed,
                      const SimulationOptions& options, const Calibration& calibration) {
  return simulate({mb::ProfilePoint{0.0, speed_cm_s}}, robot, seed, options, calibration);
}

double rms_against_cubic(const Run& run, const mb::CubicRow& published) {
  double sum = 0;
  std::size_t n = 0;
  for (const Row& r : run.rows) {
    if (r.time_s > published.end_s) break;
    const double e = r.charge - cubic_at(published, r.time_s);
    sum += e * e;
    ++n;
  }
  return n ? std::sqrt(sum / static_cast<double>(n)) : std::numeric_limits<double>::quiet_NaN();
}

Table5Check table5_check(const std::vector<std::vector<Run>>& runs) {
  if (runs.empty()) throw std::invalid_argument("table5_check: no runs");
  const std::size_t speeds = runs.front().size();
  for (const auto& r : runs)
    if (r.size() != speeds || speeds < 2) throw std::invalid_argument("table5_check: every robot needs the same speeds (at least 2)");
  std::vector<double> lifetime_s(speeds, 0.0);
  for (std::size_t s = 0; s < speeds; ++s) {
    for (const auto& robot : runs) lifetime_s[s] += robot[s].rows.back().time_s;
    lifetime_s[s] /= static_cast<double>(runs.size());
  }
  double moving_sum_s = 0;
  for (std::size_t s = 1; s < speeds; ++s) moving_sum_s += lifetime_s[s];
  const double m0 = -1.0 / lifetime_s[0];
  const double m1 = -1.0 / (moving_sum_s / static_cast<double>(speeds - 1));

  Table5Check out;
  for (std::size_t s = 0; s < speeds; ++s) {
    std::vector<double> t, y;
    double linear = 0, simple = 0;
    const double m = s == 0 ? m0 : m1;
    for (const auto& robot : runs) {
      for (const Row& row : robot[s].rows) {
        t.push_back(row.time_s);
        y.push_back(row.charge);
        // The models' predictions never go below an empty battery (the plug-in stops at 0).
        const double el = row.charge - std::max(0.0, 1.0 - row.time_s / lifetime_s[s]);
        const double es = row.charge - std::max(0.0, 1.0 + m * row.time_s);
        linear += el * el;
        simple += es * es;
      }
    }
    const double n = static_cast<double>(t.size());
    out.cubic += cubic_fit_mse(t, y);
    out.linear += linear / n;
    out.simple += simple / n;
  }
  out.cubic /= static_cast<double>(speeds);
  out.linear /= static_cast<double>(speeds);
  out.simple /= static_cast<double>(speeds);
  return out;
}

Calibration calibrate(const mb::Tables& published) {
  Calibration cal;
  const double capacity_As = cal.capacity_Ah * kSecondsPerHour;

  // 1. OCV knots, path resistance and per-speed depth of discharge against the published cubics.
  std::array<double, kOcvKnotCount> g = kLipoOcvPrior_v;
  double resistance_ohm = 0.15;  // start: a small LiPo cell with its protection and contacts
  std::array<double, mb::kSpeedCount> depth{};
  depth.fill(0.9);
  fit::Problem problem;
  for (int s = 0; s < mb::kSpeedCount; ++s) {
    problem.add(PublishedCurveResidual::block(published.cubic[s], capacity_As), {g.data(), &resistance_ohm, &depth[s]});
    problem.set_lower_bound(&depth[s], 0, 0.3);
    problem.set_upper_bound(&depth[s], 0, 1.0);
  }
  problem.add(OcvPriorResidual::block(), {g.data()});
  // Bounds on R: plausible for an 1800 mAh LiPo path (milliohms of the cell up to half an ohm).
  problem.set_lower_bound(&resistance_ohm, 0, 0.02);
  problem.set_upper_bound(&resistance_ohm, 0, 0.5);
  // The solver's stock tolerances (Ceres 2.1's defaults), with which the shipped virtual cell was
  // calibrated: the engine's own (1e-15) would move the logs in data/raw.
  fit::FitOptions opts = fit::FitOptions::stock();
  opts.compute_covariance = false;
  const fit::SolveSummary summary = problem.solve(opts);
  if (!summary.usable) throw std::runtime_error("virtual battery calibration failed: " + summary.brief);

  cal.path_resistance_ohm = resistance_ohm;
  cal.ocv_v = g;  // for now: the mean reading's curve (the mean pulse dip is added below)
  double sq = 0;
  for (int s = 0; s < mb::kSpeedCount; ++s) {
    const double end_s = published.cubic[s].end_s;
    cal.current_a[s] = depth[s] * capacity_As / end_s;
    cal.stop_voltage_v[s] = ocv(cal, 1.0 - depth[s]) - cal.current_a[s] * resistance_ohm;
  }
  {
    // RMS of the fit over all samples (the residual blocks' own definition).
    std::vector<double> r(kCalibrationSamples);
    for (int s = 0; s < mb::kSpeedCount; ++s) {
      PublishedCurveResidual f(published.cubic[s], capacity_As);
      f(g.data(), &resistance_ohm, &depth[s], r.data());
      for (double e : r) sq += e * e;
    }
    cal.fit_rms_charge = std::sqrt(sq / (mb::kSpeedCount * kCalibrationSamples));
  }

  // 2. Scatter: what the noise-free curves of robots a and b already leave around a pooled
  //    cubic, then the pulse dip that brings the logs' scatter to Table 5's cubic MSE.
  std::vector<std::vector<Run>> clean(2);
  SimulationOptions quiet;
  quiet.noise = false;
  const RobotParameters robots[2] = {robot_a(), robot_b()};
  for (int r = 0; r < 2; ++r)
    for (int s = 0; s < mb::kSpeedCount; ++s) clean[r].push_back(simulate_protocol(s, robots[r], 0, quiet, cal));
  cal.clean_pooled_cubic_mse = table5_check(clean).cubic;
  // Floor: a tenth of the target, should the clean curves already scatter as much as the logs.
  cal.target_reading_variance = std::max(kTable5CubicMse - cal.clean_pooled_cubic_mse, 0.1 * kTable5CubicMse);
  // The EMA y <- 0.8 y + 0.2 x passes (0.2^2 / (1 - 0.8^2)) = 1/9 of a white input's variance;
  // the 10 s rows are 20 updates apart (correlation 0.8^20 = 0.01): independent.
  const double filter_gain = (1 - kFilterKeep) * (1 - kFilterKeep) / (1 - kFilterKeep * kFilterKeep);
  const double input_var_v2 = cal.target_reading_variance * kChargeSpan_v * kChargeSpan_v / filter_gain;
  // ADC noise and rounding (1/12 count^2) of a 32-sample mean.
  const double adc_var_v2 = (kAdcNoise_counts * kAdcNoise_counts + 1.0 / 12.0) / kAdcSamplesPerReading / (kAdcCountsPerVolt * kAdcCountsPerVolt);
  const double p = kPulseCatchProbability;
  cal.pulse_dip_v = std::sqrt(std::max(input_var_v2 - adc_var_v2, 0.0) / (p * (1 - p)));

  // 3. True cell voltages: the fitted curve is the mean reading, which the pulses pull down by
  //    p * dip on average; the cell and the stop levels sit that much higher.
  const double mean_dip_v = p * cal.pulse_dip_v;
  for (double& v : cal.ocv_v) v += mean_dip_v;
  for (double& v : cal.stop_voltage_v) v += mean_dip_v;
  return cal;
}

const Calibration& reference_calibration() {
  static const Calibration cal = calibrate(mb::plugin_tables());
  return cal;
}

}  // namespace epuck2::virtual_robot::battery
