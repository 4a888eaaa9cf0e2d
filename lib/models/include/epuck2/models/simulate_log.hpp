// A kind's model run on a measured log's conditions (`epuck2-fit simulate KIND --like LOG`,
// docs/cli.md): per row, the readings the model gives where the log's conditions are (distances
// and sensors, intensities, grey levels, LED positions, commands and the obstacle's distance, a
// discharge run's speeds and times), in the order of the kind's reading columns
// (kind_facts.hpp: KindFacts::readings). One overload per model type (kinds.hpp): a caller that
// serves every kind holds the model in a variant and visits it, never switching on the kind.
//
// A row whose reading the sensor does not report (a camera LED off the image) gets an empty vector.
//
// `log` is any table with has(column), col(column) (the column's values, one a row), rows() and
// metadata_number(key) (a logs::Log); the columns the kind's conditions need are there (the log
// reader's checks). `covariate[i]`: the model's covariate effects' sum on row i
// (covariate_offset), added to the mean as the diagnosis fits it. Without noise the expected
// reading: the mean clamped to the sensor's rails and not rounded (comparable with a measured
// reading to within that reading's own noise); with it the register, noisy (drawn from `normal`),
// rounded and clamped, as the sensor reports it.
//
// Header-only, standard library only (epuck2::models).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "epuck2/models/geometry.hpp"
#include "epuck2/models/kinds.hpp"

namespace epuck2::models::sensors {

namespace simulate_detail {
/// One reading a row from the row's sensor (the column `sensor`): without noise the mean
/// `mean(i, sensor)` plus the row's covariate offset, clamped to the register [0, full_scale];
/// with it the register `noisy(i, sensor, normal)`.
template <class Log, class Normal, class Noisy, class Mean>
std::vector<std::vector<double>> per_sensor_rows(const Log& log, const std::vector<double>& covariate, double full_scale,
                                                 bool noise, Normal& normal, const Noisy& noisy, const Mean& mean) {
  const std::size_t n = log.rows();
  std::vector<std::vector<double>> out(n);
  const auto& sn = log.col("sensor");
  for (std::size_t i = 0; i < n; ++i) {
    const int sensor = static_cast<int>(sn[i]);
    out[i] = {noise ? static_cast<double>(noisy(i, sensor, normal))
                    : std::clamp(mean(i, sensor) + covariate[i], 0.0, full_scale)};
  }
  return out;
}
}  // namespace simulate_detail

/// proximity: the row's sensor at distance_m, at the incidence angle_deg where the log has one.
template <class Log, class Normal>
std::vector<std::vector<double>> simulated_readings(const ProximityModel& m, const Log& log, const std::vector<double>& covariate,
                                                    bool noise, Normal& normal) {
  const auto& d = log.col("distance_m");
  const bool angle = log.has("angle_deg");
  const auto cos_incidence = [&](std::size_t i) { return angle ? std::cos(deg_to_rad(log.col("angle_deg")[i])) : 1.0; };
  return simulate_detail::per_sensor_rows(
      log, covariate, kProximityFullScale_raw, noise, normal,
      [&](std::size_t i, int sensor, Normal& g) { return reading(m, sensor, d[i], cos_incidence(i), g, covariate[i]); },
      [&](std::size_t i, int sensor) { return mean_raw(m, sensor, d[i], cos_incidence(i)); });
}

/// light: the row's sensor, one light of the row's intensity at distance_m.
template <class Log, class Normal>
std::vector<std::vector<double>> simulated_readings(const LightModel& m, const Log& log, const std::vector<double>& covariate,
                                                    bool noise, Normal& normal) {
  const auto& d = log.col("distance_m");
  const auto& in = log.col("intensity");
  return simulate_detail::per_sensor_rows(
      log, covariate, kProximityFullScale_raw, noise, normal,
      [&](std::size_t i, int sensor, Normal& g) { return reading(m, sensor, in[i], d[i], g, covariate[i]); },
      [&](std::size_t i, int sensor) { return mean_raw(m, sensor, in[i], d[i]); });
}

/// ground: the row's sensor over the row's grey level.
template <class Log, class Normal>
std::vector<std::vector<double>> simulated_readings(const GroundModel& m, const Log& log, const std::vector<double>& covariate,
                                                    bool noise, Normal& normal) {
  const auto& grey = log.col("grey");
  return simulate_detail::per_sensor_rows(
      log, covariate, kGroundFullScale_raw, noise, normal,
      [&](std::size_t i, int sensor, Normal& g) { return reading(m, sensor, grey[i], g, covariate[i]); },
      [&](std::size_t i, int sensor) { return mean_raw(m, sensor, grey[i]); });
}

/// camera: the image position (px, py) of the LED at the row's position in the camera frame; the
/// covariate effects move both axes. An LED whose image falls off the image (camera_image_holds:
/// rounded, outside 0..W-1 x 0..H-1) is not seen, as in ARGoS: its row gets no reading (an empty
/// vector; a camera log lists only the LEDs seen). Without noise a position seen is clamped to the
/// image's edge pixels (-0.4 or 159.3 is reported as 0 or 159, as the rounding does). A log whose
/// px or py hold decimals (a blob's centroid, docs/logs.md) is simulated in sub-pixels: its noise
/// is drawn without the register's rounding, which its measured sd does not hold.
template <class Log, class Normal>
std::vector<std::vector<double>> simulated_readings(const CameraModel& m, const Log& log, const std::vector<double>& covariate,
                                                    bool noise, Normal& normal) {
  const std::size_t n = log.rows();
  std::vector<std::vector<double>> out(n);
  const auto& f = log.col("forward_m");
  const auto& l = log.col("lateral_m");
  const auto& v = log.col("vertical_m");
  bool subpixel = false;
  for (const char* axis : {"px", "py"})
    if (log.has(axis))
      for (const double x : log.col(axis)) subpixel = subpixel || (std::isfinite(x) && x != std::floor(x));
  for (std::size_t i = 0; i < n; ++i) {
    if (noise && subpixel) {
      const auto p = mean_px(m, f[i], l[i], v[i]);
      const double dx = m.noise_sd_px > 0 ? m.noise_sd_px * normal() : 0.0;
      const double dy = m.noise_sd_px > 0 ? m.noise_sd_px * normal() : 0.0;
      out[i] = {p[0] + covariate[i] + dx, p[1] + covariate[i] + dy};
    } else if (noise) {
      const auto p = reading(m, f[i], l[i], v[i], normal, covariate[i]);
      out[i] = {static_cast<double>(p[0]), static_cast<double>(p[1])};
    } else {
      const auto p = mean_px(m, f[i], l[i], v[i]);
      out[i] = {p[0] + covariate[i], p[1] + covariate[i]};
    }
    if (!camera_image_holds(out[i][0], out[i][1], m.base.width_px, m.base.height_px)) {
      out[i].clear();
    } else if (!noise && std::isfinite(out[i][0]) && std::isfinite(out[i][1])) {
      out[i][0] = std::clamp(out[i][0], 0.0, m.base.width_px - 1.0);
      out[i][1] = std::clamp(out[i][1], 0.0, m.base.height_px - 1.0);
    }
  }
  return out;
}

/// drive: the run's commands row by row towards the obstacle at obstacle_distance_m (metadata):
/// the encoders and the ToF. Its registers are integers either way (the encoders' floor is the
/// model's); without noise none is drawn.
template <class Log, class Normal>
std::vector<std::vector<double>> simulated_readings(const DriveModel& m, const Log& log, const std::vector<double>& covariate,
                                                    bool noise, Normal& normal) {
  const std::size_t n = log.rows();
  std::vector<std::vector<double>> out(n);
  DriveSimulation sim(m, log.metadata_number("obstacle_distance_m"));
  const auto& t = log.col("time_s");
  const auto& cl = log.col("left_speed_cm_s");
  const auto& cr = log.col("right_speed_cm_s");
  struct Silent {
    double operator()() const { return 0.0; }
  } silent;
  for (std::size_t i = 0; i < n; ++i) {
    const auto r = noise ? sim.sample(t[i], cl[i], cr[i], normal, covariate[i]) : sim.sample(t[i], cl[i], cr[i], silent, covariate[i]);
    out[i] = {static_cast<double>(r.left_steps), static_cast<double>(r.right_steps), static_cast<double>(r.tof_mm)};
  }
  return out;
}

/// battery: the discharge at the run's speeds and times, from its first charge reading (the log
/// needs its charge column). Without noise the mean charge, bounded as the log format bounds a
/// charge; with it the reading's Gaussian noise added (not rounded: a charge is no register).
template <class Log, class Normal>
std::vector<std::vector<double>> simulated_readings(const BatteryModel& m, const Log& log, const std::vector<double>& covariate,
                                                    bool noise, Normal& normal) {
  const std::size_t n = log.rows();
  std::vector<std::vector<double>> out(n);
  const auto mean = battery_mean_charge(m, log.col("time_s"), log.col("speed_cm_s"), n ? log.col("charge").front() : 1.0);
  for (std::size_t i = 0; i < n; ++i)
    out[i] = {noise ? charge_reading(m, mean[i], normal, covariate[i]) : std::clamp(mean[i] + covariate[i], -1.0, 1.05)};
  return out;
}

}  // namespace epuck2::models::sensors
