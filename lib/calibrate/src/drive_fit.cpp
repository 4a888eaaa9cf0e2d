// The drive fit (see epuck2/calibrate/sensors.hpp; the shared conventions: proximity_fit.cpp).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "epuck2/fit/replicates.hpp"
#include "epuck2/models/kind_facts.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/models/saturation.hpp"
#include "epuck2/logs/drive_columns.hpp"
#include "epuck2/logs/json_location.hpp"
#include "sensor_fit_common.hpp"

namespace epuck2::calibrate {

using namespace epuck2::fit;  // the engine (lib/fit)
using namespace sensor_fit_detail;  // the sensor fits' shared helpers

namespace s = models::sensors;

void cap_commands(DriveRun& run, double cap) {
  const auto& vl = run.left_cm_s;
  const auto& vr = run.right_cm_s;
  run.command_m_s.assign(vl.size(), 0.0);
  run.over_speed_limit = false;
  run.capped_rows = 0;
  for (std::size_t i = 0; i < vl.size(); ++i) {
    // The firmware runs a wheel commanded above its limit at the limit.
    const double l = std::clamp(vl[i] / 100.0, -cap, cap), r = std::clamp(vr[i] / 100.0, -cap, cap);
    if (l != vl[i] / 100.0 || r != vr[i] / 100.0) {
      run.over_speed_limit = true;
      ++run.capped_rows;
    }
    run.command_m_s[i] = 0.5 * (l + r);
  }
}

DriveRun drive_run_from_log(const logs::Log& log) {
  DriveRun run;
  run.path = log.path;
  run.robot = log.robot;
  const logs::DriveColumns cols = logs::drive_columns(log);
  run.obstacle_distance_m = cols.obstacle_m;
  const auto& t = cols.time_s;
  const auto& vl = cols.left_cm_s;
  const auto& vr = cols.right_cm_s;
  const auto& tof = cols.tof_mm;
  const std::vector<double> ul = s::unwrap_steps(cols.left_steps), ur = s::unwrap_steps(cols.right_steps);
  for (std::size_t i = 0; i < log.rows(); ++i) {
    run.time_s.push_back(t[i]);
    run.line.push_back(log.line_of_row.at(i));
    run.left_cm_s.push_back(vl[i]);
    run.right_cm_s.push_back(vr[i]);
    run.command_uncapped_m_s.push_back(0.5 * (vl[i] + vr[i]) / 100.0);
    run.steps.push_back(0.5 * (ul[i] + ur[i]));
    run.tof_mm.push_back(tof[i]);
  }
  cap_commands(run, kFirmwareSpeedLimit_m_s);
  return run;
}

namespace {

// The autocorrelation correction of a fit to rows of runs: the AR(1) factor from the residuals of
// the readings inside the rails that the fit kept, in row order, NaN elsewhere (a censored or
// left-out reading breaks the chain), each run its own series; and the cluster-robust errors
// with each run a cluster (fit::apply_cluster_robust).
AutocorrelationCorrection run_autocorrelation(const RobustFit& f, const std::vector<Observation>& obs,
                                              const std::vector<int>& run_of) {
  std::vector<double> e(obs.size(), std::numeric_limits<double>::quiet_NaN());
  std::vector<bool> left_out(obs.size(), false);
  for (std::size_t i : f.outliers)
    if (i < left_out.size()) left_out[i] = true;
  for (std::size_t i = 0; i < obs.size() && i < f.predictions.size(); ++i)
    if (obs[i].censoring == Censoring::none && !left_out[i]) e[i] = obs[i].value - f.predictions[i];
  AutocorrelationCorrection a = autocorrelation_correction(e, run_of);
  // Runs as clusters: every kept reading's score (censored ones too), whatever its correlation
  // with its neighbours.
  std::vector<double> r(obs.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < obs.size() && i < f.scaled_residuals.size(); ++i)
    if (!left_out[i]) r[i] = f.scaled_residuals[i];
  apply_cluster_robust(a, f, f.jacobian, r, run_of);
  return a;
}

}  // namespace

namespace {
// Encoder steps against the commanded distance: the register's mean after that travel
// (lib/models encoder_mean_steps: steps_per_m x - 1/2, the mean of floor(steps_per_m x)).
// With the firmware's cap: distance_m the travel commanded below the cap, capped_steps the steps
// the wheels made at the cap (1100 steps/s whatever steps_per_m), so that the wheel's travel is
// distance_m + capped_steps / steps_per_m (no capped_steps: none at the cap).
struct StepsLine {
  std::vector<double> distance_m;
  std::vector<double> capped_steps;
  template <typename T>
  bool operator()(const T* p, T* out) const {
    for (std::size_t i = 0; i < distance_m.size(); ++i)
      out[i] = capped_steps.empty() ? s::encoder_mean_steps(p[0], distance_m[i])
                                    : s::encoder_mean_steps(p[0], T(distance_m[i]) + capped_steps[i] / p[0]);
    return true;
  }
};

// The steps fit's rows with every run's commands capped at `cap` m/s (the firmware's 1100 steps/s
// over the steps per metre the cap is reckoned with): the runs' command_m_s and capped rows set,
// and per row the travel commanded below the cap and the steps made at it (a command holds until
// the next row).
StepsLine capped_steps_line(std::vector<DriveRun>& runs, double cap) {
  StepsLine line;
  for (DriveRun& run : runs) {
    cap_commands(run, cap);
    double below_m = 0, at_cap_steps = 0;
    for (std::size_t k = 0; k < run.time_s.size(); ++k) {
      line.distance_m.push_back(below_m);
      line.capped_steps.push_back(at_cap_steps);
      if (k + 1 < run.time_s.size()) {
        const double dt = run.time_s[k + 1] - run.time_s[k];
        for (double v : {run.left_cm_s[k] / 100.0, run.right_cm_s[k] / 100.0}) {
          if (std::abs(v) > cap) at_cap_steps += 0.5 * std::copysign(s::kFirmwareSpeedLimit_steps_s, v) * dt;
          else below_m += 0.5 * v * dt;
        }
      }
    }
  }
  return line;
}

// Whether the caps `a` and `b` (m/s) cap the same wheel commands of the runs.
bool same_capping(const std::vector<DriveRun>& runs, double a, double b) {
  for (const DriveRun& run : runs)
    for (const auto* wheel : {&run.left_cm_s, &run.right_cm_s})
      for (double cm_s : *wheel)
        if ((std::abs(cm_s / 100.0) > a) != (std::abs(cm_s / 100.0) > b)) return false;
  return true;
}

// The ToF of every row of every run: latent = scale 1000 (D - g) + offset, g the encoders'
// wheel travel lagged by tau (lagged_travel_m); p = {tof_offset_mm, tof_scale, slip_time_constant_s}.
struct TofModel {
  const std::vector<DriveRun>* runs;
  double steps_per_m;
  template <typename T>
  bool operator()(const T* p, T* out) const {
    std::size_t i = 0;
    for (const DriveRun& run : *runs) {
      const std::vector<T> travel = lagged_travel_m(run, steps_per_m, p[2]);
      for (std::size_t k = 0; k < run.time_s.size(); ++k)
        out[i++] = s::tof_response_mm(p[1], p[0], T(run.obstacle_distance_m) - travel[k]);
    }
    return true;
  }
};

// The rows of a run while the robot stands still before it first moves (no command yet, the
// encoders unchanged), `commands` the run's commands as the steps fit took them: their ToF
// readings are replicates, the body has not moved (after a move it may still be settling, see the
// slip lag).
std::size_t still_rows(const DriveRun& run, const std::vector<double>& commands) {
  std::size_t k = 0;
  while (k < run.time_s.size() && commands[k] == 0.0 && run.steps[k] == run.steps[0]) ++k;
  return k;
}

ReadingNoise still_tof_noise(const std::vector<DriveRun>& runs, std::vector<double> DriveRun::*commands) {
  std::vector<double> nv;
  std::vector<int> ng, ns;
  std::vector<bool> nr;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const DriveRun& run = runs[r];
    const std::size_t still = still_rows(run, run.*commands);
    for (std::size_t k = 0; k < still; ++k) {
      nv.push_back(run.tof_mm[k]);
      ng.push_back(static_cast<int>(r));
      ns.push_back(0);
      nr.push_back(run.tof_mm[k] <= s::kPluginTof.min_mm || run.tof_mm[k] >= s::kPluginTof.max_mm);
    }
  }
  return noise_from_replicates("tof", "mm", kArgosNoiseScaleTof_mm, nv, ng, nr, ns, 0, kQuantisationSd);
}
}  // namespace

DriveFit fit_drive(const std::vector<logs::Log>& logs, const SensorFitOptions& options) {
  DriveFit out;
  for (const logs::Log& log : logs) out.runs.push_back(drive_run_from_log(log));
  const double nominal = s::kPluginStepsPerMetre;

  // 1. Steps per metre: encoder steps against the commanded distance (a command holds until the
  //    next row), commands above the firmware's limit taken as the limit -- unless the encoders
  //    say the wheels ran faster (the cap tested by the BIC, DriveFit::cap_kept). The limit is
  //    1100 steps/s, in m/s of command 1100 / steps_per_m: the fitted steps per metre, not the
  //    plug-in's; a wheel at the cap counts 1100 steps a second whatever steps_per_m is. Which
  //    commands exceed it depends on the fit: from the plug-in's steps per metre, refitted until
  //    the fitted value caps the same commands.
  std::vector<double> x_uncapped;
  std::vector<Observation> obs;
  std::vector<int> run_of;  // per row: its run (the residuals' series)
  for (const DriveRun& run : out.runs) {
    double uncapped_m = 0;
    for (std::size_t k = 0; k < run.time_s.size(); ++k) {
      run_of.push_back(static_cast<int>(&run - out.runs.data()));
      x_uncapped.push_back(uncapped_m);
      obs.push_back({run.steps[k], Censoring::none, run.path + ":" + std::to_string(run.line[k]), -1});
      if (k + 1 < run.time_s.size()) uncapped_m += run.command_uncapped_m_s[k] * (run.time_s[k + 1] - run.time_s[k]);
    }
  }
  out.steps_rows = obs.size();
  // Within +-20 % of the nominal 41 mm wheel; steps are whole numbers.
  const std::vector<fit::Parameter> steps_params{{"steps_per_m", nominal, nominal, 0.8 * nominal, 1.2 * nominal}};
  double cap_steps_per_m = nominal;  // the steps per metre the cap is reckoned with
  StepsLine capped_line;
  for (int pass = 0; pass < 10; ++pass) {
    const double cap = s::kFirmwareSpeedLimit_steps_s / cap_steps_per_m;
    capped_line = capped_steps_line(out.runs, cap);
    out.steps = fit_robust(capped_line, obs, steps_params, robust_options(options, kQuantisationSd));
    if (!out.steps.usable) break;
    const double fitted = out.steps.value("steps_per_m");
    const bool settled = same_capping(out.runs, cap, s::kFirmwareSpeedLimit_steps_s / fitted);
    cap_steps_per_m = fitted;
    if (settled) break;
  }
  out.cap_m_s = s::kFirmwareSpeedLimit_steps_s / cap_steps_per_m;
  for (DriveRun& run : out.runs) {
    cap_commands(run, out.cap_m_s);
    if (run.over_speed_limit) out.over_limit_runs.push_back(run.path);
    out.capped_rows += run.capped_rows;
  }
  if (out.capped_rows > 0) {
    RobustFit uncapped = fit_robust(StepsLine{x_uncapped, {}}, obs, steps_params, robust_options(options, kQuantisationSd));
    // Each model's BIC over every row (the same rows, one parameter each): n ln(RSS/n) + ln n.
    auto bic = [&](const RobustFit& f, const StepsLine& line) {
      if (!f.usable) return std::numeric_limits<double>::infinity();
      const double k = f.value("steps_per_m");
      std::vector<double> predicted(obs.size());
      line(&k, predicted.data());
      double rss = 0;
      for (std::size_t i = 0; i < obs.size(); ++i) {
        const double r = obs[i].value - predicted[i];
        rss += r * r;
      }
      const double n = static_cast<double>(obs.size());
      return n * std::log(std::max(rss, 1e-300) / n) + std::log(n);
    };
    out.cap_tested = true;
    out.bic_capped = bic(out.steps, capped_line);
    out.bic_uncapped = bic(uncapped, StepsLine{x_uncapped, {}});
    if (out.bic_uncapped <= out.bic_capped - kCapBicMargin) {
      out.cap_kept = false;
      out.steps = std::move(uncapped);
      for (DriveRun& run : out.runs) run.command_m_s = run.command_uncapped_m_s;
    }
  }
  collect(out.warnings, "steps per metre: ", out.steps.warnings);
  if (out.steps.usable) out.steps_autocorrelation = run_autocorrelation(out.steps, obs, run_of);
  const double steps_per_m = out.steps.usable ? out.steps.value("steps_per_m") : nominal;

  // 2. ToF offset and scale with the slip lag, from every row of every run: readings at the
  //    sensor's floor (20 mm) or ceiling (2000 mm, and the out-of-range codes >= 8190) censored.
  std::vector<Observation> tobs;
  std::vector<double> plugin_r;  // per row: the plug-in's residual (NaN on a rail)
  const models::Channel& tof_channel = models::kind_facts("drive")->channels.front();
  for (const DriveRun& run : out.runs) {
    const std::vector<double> enc_travel = lagged_travel_m(run, nominal, 0.0);
    for (std::size_t k = 0; k < run.time_s.size(); ++k) {
      const double mm = run.tof_mm[k];
      // As the diagnosis reads it (lib/models kind_facts.hpp: the ToF channel's rails).
      const Observation o{tof_channel.on_rails(mm), censoring_at(mm, tof_channel.low_rail, tof_channel.high_rail),
                          run.path + ":" + std::to_string(run.line[k]), -1};
      if (logs::is_tof_out_of_range(mm)) ++out.tof_out_of_range_codes;
      plugin_r.push_back(o.censoring == Censoring::none
                             ? mm - s::tof_response_mm(1.0, 0.0, run.obstacle_distance_m - enc_travel[k])  // the plug-in's
                             : std::numeric_limits<double>::quiet_NaN());
      if (o.censoring != Censoring::none) ++out.tof_censored;
      tobs.push_back(o);
    }
  }
  out.tof_rows = tobs.size();
  // Scale within a factor of two of a true range; the lag between none and 2 s. Declared order
  // decides what a log that cannot tell them apart keeps: the scale and the lag before the offset.
  out.tof = fit_robust(TofModel{&out.runs, steps_per_m}, tobs,
                       {{"tof_offset_mm", 0.0, s::kPluginTof.offset_mm, -500.0, 500.0},
                        {models::effects::file_key(models::effects::drive_catalogue(), models::effects::drive::tof_scale), 1.0, s::kPluginTof.scale, 0.5, 2.0},
                        {"slip_time_constant_s", 0.05, 0.0, 0.0, 2.0}},
                       robust_options(options, kQuantisationSd));
  collect(out.warnings, "ToF: ", out.tof.warnings);
  if (out.tof.usable) {
    const models::effects::Param& tau =
        models::effects::drive_catalogue()[models::effects::drive::wheel_slip].params.front();
    const double v = out.tof.value(tau.file_key);
    if (models::effects::between_neutral_and_range(tau, v))
      out.warnings.push_back(std::string("ToF: the slip lag fitted is ") + fmt(v, 3) + " s, under the " + fmt(tau.lower) +
                             " s a lag may be: no slip these logs resolve; written as " + fmt(tau.neutral) + " (no slip).");
  }
  // The plug-in's MSE on the rows the fit's MSE is over: inside the rails (no rail, no
  // out-of-range code) and not left out as wild.
  {
    std::vector<bool> left_out(tobs.size(), false);
    for (std::size_t i : out.tof.outliers)
      if (i < left_out.size()) left_out[i] = true;
    std::size_t row = 0;
    for (const DriveRun& run : out.runs)
      for (const double mm : run.tof_mm) out.tof_code_dropouts += (left_out[row++] && logs::is_tof_out_of_range(mm)) ? 1 : 0;
    std::vector<double> kept;
    for (std::size_t i = 0; i < plugin_r.size(); ++i)
      if (tobs[i].censoring == Censoring::none && !left_out[i]) kept.push_back(plugin_r[i]);
    out.plugin_tof_rows = kept.size();
    out.plugin_tof_mse = mse_of(kept);
  }
  if (out.tof.usable) out.tof_autocorrelation = run_autocorrelation(out.tof, tobs, run_of);
  const std::string limit = fmt(out.cap_m_s * 100, 5) + " cm/s, 1100 steps/s over " +
                            (out.steps.usable ? "the fitted " + fmt(cap_steps_per_m, 7) : "the plug-in's " + fmt(nominal, 7)) + " steps/m";
  if (!out.over_limit_runs.empty() && out.cap_kept)
    out.warnings.push_back(std::to_string(out.capped_rows) + " rows command more than the firmware's limit (" +
                           limit + "): taken as the limit, which is what the robot does (the " +
                           "encoders agree: BIC " + fmt(out.bic_capped) + " with the cap, " + fmt(out.bic_uncapped) + " without).");
  if (!out.cap_kept)
    out.warnings.push_back(std::to_string(out.capped_rows) + " rows command more than the firmware's limit (" +
                           limit + "), and the encoders say the wheels ran faster: BIC " +
                           fmt(out.bic_uncapped) + " as commanded against " + fmt(out.bic_capped) +
                           " with the cap; the wheels exceed the firmware's limit and are fitted as they run.");

  // 3. The reading noise. ToF: the readings of each run while the robot stands still before it
  //    first moves (still_tof_noise); with fewer than kMinStillReadings of them, the ToF fit's
  //    residuals. Encoders: the steps fit's residuals.
  out.tof_noise = still_tof_noise(out.runs, &DriveRun::command_m_s);
  if (!(out.tof_noise.n >= kMinStillReadings) || !std::isfinite(out.tof_noise.sd))
    out.tof_noise = noise_from_residuals("tof", "mm", kArgosNoiseScaleTof_mm, out.tof);
  out.encoder_noise = noise_from_residuals("encoder", "steps", kArgosNoiseScaleEncoder_steps, out.steps);
  return out;
}

ReadingNoise drive_tof_replicate_noise(const std::vector<logs::Log>& logs) {
  std::vector<DriveRun> runs;
  for (const logs::Log& log : logs) runs.push_back(drive_run_from_log(log));
  // The still rows end at the first command, capped or as logged (fit_drive's steps fit decides
  // which it keeps): where the two agree in every run, the fits cannot change the estimate.
  for (const DriveRun& run : runs)
    if (still_rows(run, run.command_m_s) != still_rows(run, run.command_uncapped_m_s)) {
      ReadingNoise noise = fit_drive(logs).tof_noise;
      return noise.from == "replicates" ? noise : ReadingNoise{};
    }
  ReadingNoise noise = still_tof_noise(runs, &DriveRun::command_m_s);
  if (!(noise.n >= kMinStillReadings) || !std::isfinite(noise.sd)) return ReadingNoise{};  // fit_drive's: from residuals
  return noise;
}

}  // namespace epuck2::calibrate
