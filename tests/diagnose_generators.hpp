// Seeded logs with one effect hidden in them, for the diagnosis tests (tests/test_diagnose.cpp)
// and the sweep (bench/diagnose_sweep.cpp): an effect of the catalogue (docs/diagnose.md)
// drawn with a random size, none, or an effect outside the catalogue (a reading that depends
// quadratically on an extra temperature_c column). Every log has a temperature_c column, so that
// `covariate:temperature_c` is always a candidate. Noise is Gaussian (Box-Muller from
// std::mt19937_64 bits, virtual_robot::Gaussian), readings are rounded and clamped as the robot's.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/battery.hpp"
#include "epuck2/models/sensors.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"
#include "epuck2/virtual_robot/sensor_truth.hpp"

namespace epuck2::testing::diagnose {

namespace s = models::sensors;

struct Hidden {
  std::string cause;                      ///< "none", a catalogue cause, or "quadratic:temperature_c"
  std::map<std::string, double> truth;    ///< the effect's parameters as drawn
  std::string expected_verdict;           ///< "none", the cause, or "unexplained"
  std::string expected_covariate;         ///< for "unexplained": the covariate that must come first
  /// The effect is large enough for its parameters to matter (and to be checked): false when the
  /// drawn size leaves it within a few noise standard deviations where only it acts.
  bool parameters_matter = true;
  /// The reading noise's sd where the generator draws it per log (battery: 0.01..0.03 of a
  /// charge); 0 where it is the kind's constant (see each generator).
  double noise_sd = 0;
};

/// The effects the generators can hide, per kind.
inline std::vector<std::string> hidden_effects(logs::Kind kind) {
  switch (kind) {
    case logs::Kind::ground:
      return {"none", "black_offset", "white_level", "sensor_gain", "nonlinear_response", "sensor_offset", "covariate:temperature_c",
              "quadratic:temperature_c"};
    case logs::Kind::light:
      return {"none", "ambient_offset", "falloff_exponent", "sensor_gain", "covariate:temperature_c", "quadratic:temperature_c"};
    case logs::Kind::camera:
      return {"none", "principal_offset", "radial_distortion", "distortion_k2", "distortion_k3", "covariate:temperature_c",
              "quadratic:temperature_c"};
    case logs::Kind::proximity:
      return {"none", "ambient_offset", "sensor_gain", "long_tail", "saturation", "incidence_angle", "covariate:temperature_c",
              "quadratic:temperature_c"};
    case logs::Kind::drive:
      return {"none",    "speed_limit", "accel_limit", "wheel_slip", "speed_scale", "latency", "tof_offset",
              "tof_scale", "covariate:temperature_c", "quadratic:temperature_c"};
    case logs::Kind::battery: return {"none", "capacity_scale", "covariate:temperature_c", "quadratic:temperature_c"};
  }
  return {};
}

class Draw {
 public:
  explicit Draw(std::uint64_t seed) : g_(seed) {}
  double uniform(double a, double b) { return a + (b - a) * g_.uniform(); }
  int integer(int a, int b) { return a + static_cast<int>(std::floor(g_.uniform() * (b - a + 1))); }
  double normal() { return g_(); }
  /// A size in [a, b] with a random sign.
  double signed_size(double a, double b) { return (g_.uniform() < 0.5 ? -1.0 : 1.0) * uniform(a, b); }

 private:
  virtual_robot::Gaussian g_;
};

inline Hidden hidden(const std::string& cause) {
  Hidden h;
  h.cause = cause;
  if (cause == "none") h.expected_verdict = "none";
  else if (cause.rfind("quadratic:", 0) == 0) {
    h.expected_verdict = "unexplained";
    h.expected_covariate = cause.substr(10);
  } else h.expected_verdict = cause;
  return h;
}

/// Temperature effect shared by every kind: linear (catalogue) or quadratic (outside it), in the
/// reading's units per degree.
struct Temperature {
  double linear = 0, quadratic = 0;
  static constexpr double kMean_c = 30.0;  ///< temperatures are drawn uniformly in 20..40 C
  double effect(double t) const { return linear * (t - kMean_c) + quadratic * ((t - kMean_c) * (t - kMean_c) - 100.0 / 3.0); }
};

inline Temperature temperature_effect(Hidden& h, Draw& d, double linear_lo, double linear_hi, double quad_lo, double quad_hi) {
  Temperature t;
  if (h.cause == "covariate:temperature_c") {
    t.linear = d.signed_size(linear_lo, linear_hi);
    h.truth["slope"] = t.linear;
  } else if (h.cause == "quadratic:temperature_c") {
    t.quadratic = d.signed_size(quad_lo, quad_hi);
  }
  return t;
}

/// A `covariate:` slope matters (its parameter is checked) when the log pins it down: its expected
/// relative standard error, noise / (|slope| sd(T) sqrt(observations)), at most 4 %, so that the
/// 10 % tolerance is 2.5 standard errors. Temperatures are uniform on 20..40 C: sd 20 / sqrt(12).
inline void covariate_precision(Hidden& h, const Temperature& t, double noise_sd, double observations) {
  if (h.cause != "covariate:temperature_c") return;
  constexpr double kTemperatureSd_c = 5.7735;
  constexpr double kMaxRelativeSe = 0.04;
  h.parameters_matter = noise_sd / (std::abs(t.linear) * kTemperatureSd_c * std::sqrt(observations)) <= kMaxRelativeSe;
}

inline std::string fmt(double v) {
  std::ostringstream o;
  o.precision(10);
  o << v;
  return o.str();
}

// ----- ground: readings N(0, 5 counts) around 1023 grey with the effect ------------------------
inline std::string ground_log(std::uint64_t seed, Hidden& h) {
  Draw d(seed);
  const int n = d.integer(300, 900);
  double offset = 0, level = s::kGroundFullScale_raw, p = 1;
  std::array<double, 3> gain{1, 1, 1}, own_offset{0, 0, 0};
  if (h.cause == "sensor_offset")  // relative to sensor 0 (the first seen)
    for (int k = 1; k < 3; ++k) h.truth["offsets[" + std::to_string(k) + "]"] = own_offset[static_cast<std::size_t>(k)] = d.signed_size(20, 60);
  if (h.cause == "black_offset") h.truth["offset"] = offset = d.uniform(30, 90);
  if (h.cause == "white_level") h.truth["level"] = level = d.uniform(850, 980);
  if (h.cause == "nonlinear_response") h.truth["exponent"] = p = d.uniform(0, 1) < 0.5 ? d.uniform(0.7, 0.87) : d.uniform(1.15, 1.5);
  if (h.cause == "sensor_gain")
    for (int k = 0; k < 3; ++k) h.truth["gains[" + std::to_string(k) + "]"] = gain[static_cast<std::size_t>(k)] = 1.0 + d.signed_size(0.04, 0.12);
  const Temperature temp = temperature_effect(h, d, 1.5, 4.0, 0.3, 0.6);
  constexpr double kNoise = 5.0;  // counts, as the virtual robot's ground sensors (sensor_truth.hpp)
  covariate_precision(h, temp, kNoise, n);
  std::string out = "# generated by tests/diagnose_generators.hpp\ngrey,sensor,value,temperature_c\n";
  for (int i = 0; i < n; ++i) {
    const double grey = d.integer(0, 10) / 10.0;
    const int sensor = d.integer(0, 2);
    const double t = d.uniform(20, 40);
    const double black = offset + own_offset[static_cast<std::size_t>(sensor)];
    const double v = black + (level - black) * gain[static_cast<std::size_t>(sensor)] * std::pow(grey, p) + temp.effect(t) + kNoise * d.normal();
    out += fmt(grey) + "," + std::to_string(sensor) + "," + fmt(std::clamp(std::round(v), 0.0, s::kGroundFullScale_raw)) + "," + fmt(std::round(t * 10) / 10) + "\n";
  }
  return out;
}

// ----- light: two to four sensors, Eq. 2 with gamma near 0.075, noise N(0, 15 counts) -----------
inline std::string light_log(std::uint64_t seed, Hidden& h) {
  Draw d(seed);
  const int n = d.integer(400, 1000);
  const double gamma = d.uniform(0.07, 0.08);
  double offset = 0, p = 2;
  std::array<double, 8> gain{1, 1, 1, 1, 1, 1, 1, 1};
  const int sensors = d.integer(2, 4);
  if (h.cause == "ambient_offset") h.truth["offset"] = offset = d.uniform(25, 80);
  if (h.cause == "falloff_exponent") h.truth["exponent"] = p = d.uniform(0, 1) < 0.5 ? d.uniform(1.6, 1.85) : d.uniform(2.15, 2.5);
  if (h.cause == "sensor_gain")
    for (int k = 1; k < sensors; ++k) h.truth["gains[" + std::to_string(k) + "]"] = gain[static_cast<std::size_t>(k)] = 1.0 + d.signed_size(0.06, 0.15);
  const Temperature temp = temperature_effect(h, d, 3.0, 8.0, 0.8, 1.5);
  constexpr double kNoise = 15.0;  // counts, as the virtual robot's light sensors (sensor_truth.hpp)
  covariate_precision(h, temp, kNoise, n);
  std::string out = "distance_m,intensity,sensor,value,temperature_c\n";
  for (int i = 0; i < n; ++i) {
    const double dist = d.integer(2, 10) * 0.05;
    const double intensity = d.integer(1, 4) * 0.5;
    const int sensor = d.integer(0, sensors - 1);
    const double t = d.uniform(20, 40);
    const double v = 4095.0 * (1.0 - gain[static_cast<std::size_t>(sensor)] * std::pow(gamma * intensity / dist, p)) - offset + temp.effect(t) +
                     kNoise * d.normal();
    out += fmt(dist) + "," + fmt(intensity) + "," + std::to_string(sensor) + "," + fmt(std::clamp(std::round(v), 0.0, 4095.0)) + "," +
           fmt(std::round(t * 10) / 10) + "\n";
  }
  return out;
}

// ----- camera: pinhole, fov 28..33 deg, centroid jitter N(0, 0.5 px), whole pixels --------------
inline std::string camera_log(std::uint64_t seed, Hidden& h) {
  Draw d(seed);
  const int n = d.integer(150, 500);
  const double fov = d.uniform(28, 33);
  double dx = 0, dy = 0, k1 = 0, k2 = 0, k3 = 0;
  if (h.cause == "principal_offset") {
    h.truth["dx_px"] = dx = d.signed_size(1.0, 3.0);
    h.truth["dy_px"] = dy = d.signed_size(1.0, 3.0);
  }
  if (h.cause == "radial_distortion") h.truth["k1"] = k1 = d.signed_size(0.5, 1.2);
  // OpenCV's fourth-order term alone: r^2 reaches 0.09 in these logs, so k2 8..20 moves the
  // image's corners by 4..10 px (the jitter is 0.5 px).
  if (h.cause == "distortion_k2") h.truth["k2"] = k2 = d.signed_size(8.0, 20.0);
  // The sixth-order term alone (k2 = 0). On the grid below (0.9 of the image's half-extents) it
  // is not told apart from k2: at fov 28 deg, 150 LEDs and k3 = 80 the best k2 alone leaves 2.4
  // jitter variances (0.5 px and the rounding's 1/12 px^2) more than k3, against a BIC tie. A k3
  // log therefore puts half its LEDs near the image's corners (0.75..0.95 of the half-extents,
  // r^2 up to 0.088..0.124 for fov 28..33 deg) and draws k3 in 100..200, which moves a corner of
  // the 0.9 grid by 5..11 px at fov 30 deg: k2 alone then leaves 12..14 such variances more than
  // k3 at fov 28, 150 LEDs and k3 = 100 (fov 30: 19..38; fov 33: 37..126), and more with more LEDs.
  // An LED whose image falls off the image is not seen (as in ARGoS): another is drawn.
  const bool corners = h.cause == "distortion_k3";
  if (corners) h.truth["k3"] = k3 = d.signed_size(100.0, 200.0);
  const Temperature temp = temperature_effect(h, d, 0.06, 0.15, 0.02, 0.04);
  constexpr double kJitter = 0.5;  // px, as the virtual robot's camera (sensor_truth.hpp)
  covariate_precision(h, temp, kJitter, 2.0 * n);  // px and py both drift
  const double f = 80.0 / std::tan(fov * s::kPi / 360.0);
  std::string out = "forward_m,lateral_m,vertical_m,px,py,temperature_c\n";
  for (int i = 0; i < n; ++i) {
    const double fw = d.uniform(0.2, 0.9);
    const bool corner = corners && d.uniform(0, 1) < 0.5;
    const double x = (corner ? d.signed_size(0.75, 0.95) : d.uniform(-0.9, 0.9)) * 80.0 / f;
    const double z = (corner ? d.signed_size(0.75, 0.95) : d.uniform(-0.9, 0.9)) * 60.0 / f;
    const double t = d.uniform(20, 40);
    const double r2 = x * x + z * z;
    const double sc = 1.0 + k1 * r2 + k2 * r2 * r2 + k3 * r2 * r2 * r2;
    const double px0 = 80 + dx - f * x * sc + temp.effect(t), py0 = 60 + dy - f * z * sc + temp.effect(t);
    // Chosen on the noiseless image (4 jitter sd inside the edge pixels), so that no draw of the
    // jitter decides which LEDs stay: a choice on the noisy one would keep the edge's LEDs whose
    // jitter pulled them inward, and bias k3 towards 0. Every cause's log: an LED pushed off the
    // image (k2 = 20 moves a 0.9 corner by 11 px, past the edge) is not seen, as a camera reports
    // it, rather than logged clamped to the edge pixel (which biased k2 towards 0 by up to 9 of
    // its standard errors: bench/fresh-slips.md, "Round 10").
    if (px0 < 2 || px0 > 157 || py0 < 2 || py0 > 117) {
      --i;  // not seen
      continue;
    }
    const double px = px0 + kJitter * d.normal();
    const double py = py0 + kJitter * d.normal();
    out += fmt(fw) + "," + fmt(x * fw) + "," + fmt(z * fw) + "," + fmt(std::clamp(std::round(px), 0.0, 159.0)) + "," +
           fmt(std::clamp(std::round(py), 0.0, 119.0)) + "," + fmt(std::round(t * 10) / 10) + "\n";
  }
  return out;
}

// ----- proximity: Eq. 1 with the plug-in's coefficients, one to four sensors, angles 0..60 deg,
// N(0, 10 counts) -----
inline std::string proximity_log(std::uint64_t seed, Hidden& h) {
  Draw d(seed);
  const int n = d.integer(500, 1200);
  const int sensors = d.integer(2, 4);
  double offset = 0, amplitude = 0, length = 0.02, level = 1e9;
  std::array<double, 8> gain{1, 1, 1, 1, 1, 1, 1, 1};
  if (h.cause == "ambient_offset") h.truth["offset"] = offset = d.uniform(40, 120);
  if (h.cause == "sensor_gain")
    for (int k = 1; k < sensors; ++k) h.truth["gains[" + std::to_string(k) + "]"] = gain[static_cast<std::size_t>(k)] = 1.0 + d.signed_size(0.08, 0.2);
  if (h.cause == "long_tail") {
    h.truth["amplitude"] = amplitude = d.uniform(150, 600);
    h.truth["length_m"] = length = d.uniform(0.015, 0.045);
    // Inside the cut-off the tail trades off against a, b and c: only the readings beyond it
    // (0.055 m and further) pin it down. There it must reach 5 noise sd (50 counts) to matter.
    constexpr double kFirstBeyond_m = 0.055;
    h.parameters_matter = amplitude * std::exp(-kFirstBeyond_m / length) >= 50.0;
  }
  if (h.cause == "saturation") h.truth["level"] = level = d.uniform(2500, 3500);
  double k_angle = 0;  // the plug-in ignores the angle: cos^0
  if (h.cause == "incidence_angle") h.truth["k"] = k_angle = d.uniform(0.8, 2.5);
  const Temperature temp = temperature_effect(h, d, 4.0, 10.0, 1.0, 2.0);
  constexpr double kNoise = 10.0;  // counts
  covariate_precision(h, temp, kNoise, n);
  std::string out = "distance_m,sensor,value,temperature_c,angle_deg\n";
  for (int i = 0; i < n; ++i) {
    const double dist = d.integer(0, 16) * 0.005;
    const int sensor = d.integer(0, sensors - 1);
    const double t = d.uniform(20, 40);
    const double angle_deg = 10.0 * d.integer(0, 6);
    double base = 0;
    const double abc[3] = {s::kPluginProximity.a_per_m2, s::kPluginProximity.b_per_m, s::kPluginProximity.c};
    if (dist <= s::kPluginProximity.range_m)
      base = 4095.0 * std::pow(std::cos(angle_deg * s::kPi / 180.0), k_angle) * std::clamp(s::proximity_polynomial(abc, dist), 0.0, 1.0);
    double v = std::min(gain[static_cast<std::size_t>(sensor)] * base + offset + amplitude * std::exp(-dist / length), level);
    v += temp.effect(t) + kNoise * d.normal();
    out += fmt(dist) + "," + std::to_string(sensor) + "," + fmt(std::clamp(std::round(v), 0.0, 4095.0)) + "," +
           fmt(std::round(t * 10) / 10) + "," + fmt(angle_deg) + "\n";
  }
  return out;
}


// ----- drive: runs to and fro before an obstacle, ~10 Hz sampling with jitter, ToF noise
// 2 mm + 3 mm per metre of range (as the virtual robot's, data/raw/drive/README.md) --------------
// The robot is simulated at 1 ms steps (wheels limited in speed and acceleration, the body's lag
// behind the wheels integrated exactly over each step), independently of the diagnosis's
// closed-form model. `rows` > 0 forces the log's length (the speed benchmark).
inline std::string drive_log(std::uint64_t seed, Hidden& h, int rows = 0) {
  Draw d(seed);
  const int n = rows > 0 ? rows : d.integer(600, 2400);
  const double obstacle_m = d.uniform(0.4, 0.8);
  double max_cm_s = 1e9, accel = 1e9, tau = 0, speed_k = 1, delay = 0, offset = 0, tof_k = 1;
  if (h.cause == "speed_limit") h.truth["max_cm_s"] = max_cm_s = d.uniform(6, 11);
  if (h.cause == "accel_limit") h.truth["accel_cm_s2"] = accel = d.uniform(8, 30);
  if (h.cause == "wheel_slip") h.truth["tau_s"] = tau = d.uniform(0.1, 0.3);
  if (h.cause == "speed_scale") h.truth["k"] = speed_k = 1.0 + d.signed_size(0.04, 0.10);
  if (h.cause == "latency") h.truth["delay_s"] = delay = d.uniform(0.1, 0.3);
  if (h.cause == "tof_offset") h.truth["offset_mm"] = offset = d.signed_size(8, 25);
  if (h.cause == "tof_scale") h.truth["k"] = tof_k = 1.0 + d.signed_size(0.02, 0.05);
  const Temperature temp = temperature_effect(h, d, 0.4, 1.0, 0.1, 0.2);
  // ToF noise 2 mm + 3 mm/m at a typical 0.6 m range.
  covariate_precision(h, temp, 3.8, n);
  constexpr double kStep = 0.001, kPeriod = 0.1, kJitter = 0.02;
  const double steps_per_m = s::kPluginStepsPerMetre;
  // Physics state; x_g's history for the ToF latency.
  double t = 0, v_w = 0, x_w = 0, v_g = 0, x_g = 0;
  std::vector<double> history{0.0};
  double command = 0, next_sample = 0;
  // Host: pause, then a run of a random speed and length towards or away from the obstacle
  // (keeping the range within 0.1..1.2 m), then pause again.
  bool moving = false;
  double phase_end = d.uniform(0.5, 1.5), run_start_steps = 0, run_steps = 0, run_speed = 0;
  std::string out = "# generated by tests/diagnose_generators.hpp\n# obstacle_distance_m: " + fmt(obstacle_m) +
                    "\ntime_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm,temperature_c\n";
  int written = 0;
  while (written < n) {
    if (t >= next_sample - 1e-9) {
      const double steps = std::floor(x_w * steps_per_m);
      if (moving && std::abs(steps - run_start_steps) >= run_steps) {
        moving = false;
        phase_end = t + d.uniform(0.5, 1.5);
      } else if (!moving && t >= phase_end) {
        moving = true;
        run_speed = d.uniform(2, 15);
        const double range = obstacle_m - x_g;
        const double dir = range < 0.3 ? -1.0 : range > 1.0 ? 1.0 : (d.uniform(0, 1) < 0.5 ? -1.0 : 1.0);
        run_speed *= dir;
        run_steps = d.uniform(0.08, 0.2) * steps_per_m;
        run_start_steps = steps;
      }
      command = moving ? run_speed : 0.0;
      // ToF: the body's travel `delay` ago.
      const std::size_t back = static_cast<std::size_t>(std::llround(delay / kStep));
      const double seen = history.size() > back ? history[history.size() - 1 - back] : 0.0;
      const double range_m = obstacle_m - seen;
      const double tc = d.uniform(20, 40);
      const double tof = tof_k * 1000.0 * range_m + offset + temp.effect(tc) + (2.0 + 3.0 * range_m) * d.normal();
      const double wrapped = steps - 65536.0 * std::floor((steps + 32768.0) / 65536.0);
      out += fmt(std::round(t * 1e4) / 1e4) + "," + fmt(command) + "," + fmt(command) + "," + fmt(wrapped) + "," + fmt(wrapped) + "," +
             fmt(std::clamp(std::round(tof), 20.0, 2000.0)) + "," + fmt(std::round(tc * 10) / 10) + "\n";
      ++written;
      next_sample = std::round((t + kPeriod + kJitter * (2.0 * d.uniform(0, 1) - 1.0)) / kStep) * kStep;
    }
    // Wheels: the command clamped to the speed limit, reached at the acceleration limit (the
    // ramp's end inside the step is integrated exactly).
    const double target = std::clamp(command, -max_cm_s, max_cm_s) / 100.0;
    const double a = accel / 100.0;
    const double ramp = std::min(kStep, std::abs(target - v_w) / a);
    const double a_signed = target > v_w ? a : -a;
    const double x_before = x_w;
    if (ramp > 0) {
      x_w += v_w * ramp + 0.5 * a_signed * ramp * ramp;
      v_w = ramp < kStep ? target : v_w + a_signed * ramp;
    }
    x_w += v_w * (kStep - ramp);
    // Body: first-order lag behind k times the wheels' mean speed over the step (exact for it).
    const double u = speed_k * (x_w - x_before) / kStep;
    if (tau > 0) {
      const double e = std::exp(-kStep / tau);
      x_g += u * kStep + (v_g - u) * tau * (1.0 - e);
      v_g = u + (v_g - u) * e;
    } else {
      x_g += u * kStep;
      v_g = u;
    }
    history.push_back(x_g);
    t += kStep;
  }
  return out;
}

// ----- battery: one discharge run at a constant speed, the Cubic (corrected, the plug-in's
// tables) with time running 1/k as fast, a reading every 5..30 s, noise N(0, 0.01..0.03) -------
inline std::string battery_log(std::uint64_t seed, Hidden& h) {
  namespace mb = models::battery;
  Draw d(seed);
  const mb::Tables tables = mb::plugin_tables();  // the diagnosis's default base model
  double k = 1;
  if (h.cause == "capacity_scale") h.truth["k"] = k = 1.0 + d.signed_size(0.04, 0.12);
  const Temperature temp = temperature_effect(h, d, 0.0015, 0.004, 0.0004, 0.0008);
  const double speed = d.integer(0, 15);
  const double period = d.uniform(5, 30);
  const double noise = d.uniform(0.01, 0.03);
  h.noise_sd = noise;
  // Rows: one per period over the lifetime.
  covariate_precision(h, temp, noise, tables.lifetime_s[static_cast<std::size_t>(speed)] * k / period);
  constexpr double kTick = 1.0;  // s
  std::string out = "# generated by tests/diagnose_generators.hpp\ntime_s,speed_cm_s,charge,temperature_c\n";
  double charge = 1.0, t = 0, next = 0;
  // The robot stops when the model's charge reaches 0 or the table's lifetime ends.
  const double end = tables.lifetime_s[static_cast<std::size_t>(speed)] * k;
  while (true) {
    const bool last = charge <= 0.0 || t >= end;
    if (t >= next - 1e-9 || last) {
      const double tc = d.uniform(20, 40);
      // The reading as logged: the log format bounds a normalised charge to [-1, 1.05].
      const double reading = std::clamp(charge + temp.effect(tc) + noise * d.normal(), -1.0, 1.05);
      out += fmt(std::round(t * 10) / 10) + "," + fmt(speed) + "," + fmt(reading) + "," +
             fmt(std::round(tc * 10) / 10) + "\n";
      next = t + period;
    }
    if (last) break;
    charge = mb::corrected::step(mb::Model::cubic, tables, charge, speed / 100.0 * kTick / k, kTick / k);
    t += kTick;
  }
  return out;
}

/// How a diagnosis of a hidden effect came out.
struct Outcome {
  bool verdict_right = false;
  bool parameters_checked = false;  ///< the effect has parameters to compare
  bool parameters_right = false;    ///< every parameter within kParameterTolerance of the truth
  std::string verdict, first_covariate;
  double worst_relative_error = 0;
};

/// Parameters must come within 10 % of the truth (the brief's target).
inline constexpr double kParameterTolerance = 0.10;

inline Outcome judge(const Hidden& h, const epuck2::diagnose::Report& r) {
  Outcome o;
  o.verdict = r.verdict_name();
  o.first_covariate = r.structure_after.empty() ? "" : r.structure_after.front().covariate;
  o.verdict_right = r.verdict_name() == h.expected_verdict;
  if (h.expected_verdict == "unexplained") o.verdict_right = o.verdict_right && o.first_covariate == h.expected_covariate;
  if (!h.truth.empty() && o.verdict_right && h.parameters_matter) {
    o.parameters_checked = true;
    o.parameters_right = true;
    for (const auto& f : r.findings) {
      if (f.cause != h.cause) continue;
      for (const auto& [name, truth] : h.truth) {
        double got = std::nan("");
        for (const auto& v : f.parameters)
          if (v.name == name) got = v.value;
        // Gains are relative to the first sensor seen (sensor 0 in these logs, gain 1).
        const double err = std::abs(got - truth) / std::max(1e-12, std::abs(name.rfind("gains", 0) == 0 ? truth - 1.0 : truth));
        const double rel = name.rfind("gains", 0) == 0 ? std::abs(got - truth) / std::abs(truth - 1.0) : err;
        o.worst_relative_error = std::max(o.worst_relative_error, std::isfinite(rel) ? rel : 1e9);
      }
    }
    o.parameters_right = o.worst_relative_error <= kParameterTolerance;
  }
  return o;
}

inline std::string make_log(logs::Kind kind, std::uint64_t seed, Hidden& h) {
  switch (kind) {
    case logs::Kind::ground: return ground_log(seed, h);
    case logs::Kind::light: return light_log(seed, h);
    case logs::Kind::camera: return camera_log(seed, h);
    case logs::Kind::proximity: return proximity_log(seed, h);
    case logs::Kind::drive: return drive_log(seed, h);
    case logs::Kind::battery: return battery_log(seed, h);
  }
  return {};
}

}  // namespace epuck2::testing::diagnose
