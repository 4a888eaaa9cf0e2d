// epuck2-fit simulate {proximity,light,ground,camera,drive} --like LOG [--coefficients FILE]
//                     [--noise] [--seed N] [-o FILE]
// epuck2-fit simulate battery --like LOG [--coefficients FILE] [--battery-model M] ... (the
//                     battery subcommand is cmd_simulate.cpp's; its --like runs here)
// Runs the runtime model library (lib/models kinds.hpp) on the conditions of a measured log
// (distances and sensors, intensities, grey levels, LED positions, commands and the obstacle's
// distance, a discharge run's speeds and times) and writes a log in the same format with the
// simulated readings in place of the measured ones: comparable row by row. Without
// --coefficients, the plug-in's published model. A model's `covariate:NAME` effects read the
// log's column NAME.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "app_support.hpp"
#include "commands.hpp"
#include "epuck2/models/kind_facts.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/logs/output.hpp"
#include "epuck2/models/kinds.hpp"
#if __has_include("epuck2/fitted/coefficients.hpp")
#include "epuck2/fitted/coefficients.hpp"  // --coefficients fitted (battery)
#endif

namespace epuck2::app {
namespace {

namespace s = models::sensors;

/// The columns the kind's readings are in (replaced by the simulation): its facts' (kind_facts).
std::vector<std::string> reading_columns(logs::Kind kind) {
  const auto& readings = models::kind_facts(std::string(logs::to_string(kind)))->readings;
  return {readings.begin(), readings.end()};
}

/// The model's covariate effects' sum on each row, from the log's columns (a usage error naming
/// the column when the log lacks one).
std::vector<double> covariate_offsets(const std::vector<s::CovariateEffect>& covariates, const logs::Log& log,
                                      const LikeOptions& o) {
  for (const auto& c : covariates)
    if (!log.has(c.column))
      throw UsageError("--like " + o.like + ": the model's covariate:" + c.column + " effect reads the column '" + c.column +
                       "', which this log does not have as a numeric column");
  std::vector<double> out(log.rows(), 0.0);
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = s::covariate_offset(covariates, [&](const std::string& column) { return log.col(column)[i]; });
  return out;
}

/// The battery model: the plug-in's published tables and the Cubic without --coefficients (or
/// with `plugin`), the compiled-in fitted tables with `fitted`, else the file's tables, discharge
/// model, effects and noise; --battery-model, when given, names the discharge model.
s::BatteryModel load_battery(const LikeOptions& o) {
  s::BatteryModel m;
  if (o.coefficients == "fitted") {
#ifdef EPUCK2_FITTED_HAS_BATTERY
    m.tables = fitted::battery_tables();
#else
    throw UsageError("this build has no compiled-in fitted battery tables; give --coefficients FILE");
#endif
  } else if (!o.coefficients.empty() && o.coefficients != "plugin") {
    const std::string& file = coefficient_file(o.coefficients);
    try {
      m = coefficients::battery_model_from_json(read_json(file), file);
    } catch (const logs::InputError&) {
      throw;
    } catch (const std::runtime_error& e) {
      throw UsageError(std::string("--coefficients: ") + e.what());
    }
  }
  if (!o.battery_model.empty() && !models::battery::parse_model(o.battery_model, m.model))
    throw UsageError("--battery-model: " + unknown_name("discharge model", o.battery_model, {"simple", "linear", "cubic", "approximated"}));
  return m;
}

template <class Model>
Model load(const LikeOptions& o, Model (*from_json)(const nlohmann::json&, const std::string&, const std::string&)) {
  if (o.coefficients.empty()) return Model{};
  try {
    return from_json(read_json(o.coefficients), o.coefficients, "");
  } catch (const logs::InputError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw UsageError(std::string("--coefficients: ") + e.what());
  }
}

/// Per row, the simulated readings of the kind's reading columns (in reading_columns' order).
std::vector<std::vector<double>> simulate(const LikeOptions& o, const logs::Log& log, s::StandardNormal& normal) {
  const std::size_t n = log.rows();
  std::vector<std::vector<double>> out(n);
  // Without --noise: the expected reading, the model's mean clamped to the sensor's rails and not
  // rounded (comparable with a measured reading to within that reading's own noise); with it: the
  // register, noisy, rounded and clamped.
  auto draw = [&](auto&& noisy, auto&& mean) { return o.noise ? noisy(normal) : mean(); };
  switch (log.kind) {
    case logs::Kind::proximity: {
      const auto m = load<s::ProximityModel>(o, coefficients::proximity_model_from_json);
      const auto& d = log.col("distance_m");
      const auto& sn = log.col("sensor");
      const bool angle = log.has("angle_deg");
      const auto cov = covariate_offsets(m.covariates, log, o);
      for (std::size_t i = 0; i < n; ++i) {
        const double c = angle ? std::cos(s::deg_to_rad(log.col("angle_deg")[i])) : 1.0;
        out[i] = {draw([&](auto& g) { return double(s::reading(m, static_cast<int>(sn[i]), d[i], c, g, cov[i])); },
                       [&] {
                         return std::clamp(s::mean_raw(m, static_cast<int>(sn[i]), d[i], c) + cov[i], 0.0, s::kProximityFullScale_raw);
                       })};
      }
      break;
    }
    case logs::Kind::light: {
      const auto m = load<s::LightModel>(o, coefficients::light_model_from_json);
      const auto& d = log.col("distance_m");
      const auto& in = log.col("intensity");
      const auto& sn = log.col("sensor");
      const auto cov = covariate_offsets(m.covariates, log, o);
      for (std::size_t i = 0; i < n; ++i)
        out[i] = {draw([&](auto& g) { return double(s::reading(m, static_cast<int>(sn[i]), in[i], d[i], g, cov[i])); },
                       [&] {
                         return std::clamp(s::mean_raw(m, static_cast<int>(sn[i]), in[i], d[i]) + cov[i], 0.0,
                                           s::kProximityFullScale_raw);
                       })};
      break;
    }
    case logs::Kind::ground: {
      const auto m = load<s::GroundModel>(o, coefficients::ground_model_from_json);
      const auto& grey = log.col("grey");
      const auto& sn = log.col("sensor");
      const auto cov = covariate_offsets(m.covariates, log, o);
      for (std::size_t i = 0; i < n; ++i)
        out[i] = {draw([&](auto& g) { return double(s::reading(m, static_cast<int>(sn[i]), grey[i], g, cov[i])); },
                       [&] {
                         return std::clamp(s::mean_raw(m, static_cast<int>(sn[i]), grey[i]) + cov[i], 0.0, s::kGroundFullScale_raw);
                       })};
      break;
    }
    case logs::Kind::camera: {
      const auto m = load<s::CameraModel>(o, coefficients::camera_model_from_json);
      const auto& f = log.col("forward_m");
      const auto& l = log.col("lateral_m");
      const auto& v = log.col("vertical_m");
      const auto cov = covariate_offsets(m.covariates, log, o);
      for (std::size_t i = 0; i < n; ++i) {
        if (o.noise) {
          const auto p = s::reading(m, f[i], l[i], v[i], normal, cov[i]);
          out[i] = {static_cast<double>(p[0]), static_cast<double>(p[1])};
        } else {
          const auto p = s::mean_px(m, f[i], l[i], v[i]);
          out[i] = {p[0] + cov[i], p[1] + cov[i]};
        }
      }
      break;
    }
    case logs::Kind::drive: {
      const auto m = load<s::DriveModel>(o, coefficients::drive_model_from_json);
      s::DriveSimulation sim(m, log.metadata_number("obstacle_distance_m"));
      const auto& t = log.col("time_s");
      const auto& cl = log.col("left_speed_cm_s");
      const auto& cr = log.col("right_speed_cm_s");
      const auto cov = covariate_offsets(m.covariates, log, o);
      for (std::size_t i = 0; i < n; ++i) {
        // The drive's registers are integers either way (the encoders' floor is the model's).
        struct Silent {
          double operator()() const { return 0.0; }
        } silent;
        const auto r = o.noise ? sim.sample(t[i], cl[i], cr[i], normal, cov[i]) : sim.sample(t[i], cl[i], cr[i], silent, cov[i]);
        out[i] = {static_cast<double>(r.left_steps), static_cast<double>(r.right_steps), static_cast<double>(r.tof_mm)};
      }
      break;
    }
    case logs::Kind::battery: {
      const s::BatteryModel m = load_battery(o);
      if (!log.has("charge"))
        throw UsageError("--like " + o.like + ": a battery log with a 'charge' column is needed (this one has voltage_v only); "
                         "the run starts from its first charge");
      const auto& t = log.col("time_s");
      const auto mean = s::battery_mean_charge(m, t, log.col("speed_cm_s"), n ? log.col("charge").front() : 1.0);
      const auto cov = covariate_offsets(m.covariates, log, o);
      // Without --noise the mean charge, bounded as the log format bounds a charge; with it, the
      // reading's Gaussian noise added (not rounded: a charge is no register).
      for (std::size_t i = 0; i < n; ++i)
        out[i] = {o.noise ? s::charge_reading(m, mean[i], normal, cov[i]) : std::clamp(mean[i] + cov[i], -1.0, 1.05)};
      break;
    }
    default:
      throw UsageError("simulate --like does not support the kind '" + std::string(logs::to_string(log.kind)) + "'");
  }
  return out;
}

}  // namespace

int run_like(const LikeOptions& o) {
  const auto logs = read_logs_reporting("simulate", {o.like}, o.kind, o.skip_bad_rows);
  const logs::Log& log = logs.front();
  s::StandardNormal normal(o.seed);
  const auto simulated = simulate(o, log, normal);
  const std::vector<std::string> replaced = reading_columns(log.kind);
  // A NaN or infinite reading is never written: the row's conditions (which the log reader's ranges
  // should have refused) or the model's coefficients overflow the model there.
  for (std::size_t i = 0; i < simulated.size(); ++i)
    for (std::size_t c = 0; c < simulated[i].size(); ++c)
      if (!std::isfinite(simulated[i][c]))
        throw logs::InputError(o.like, log.line_of_row[i], 0,
                               "the simulated " + replaced[c] + " is " + logs::format_number(simulated[i][c]) +
                                   " (the model overflows on this row's conditions" +
                                   (o.coefficients.empty() ? std::string() : " with " + o.coefficients) + "); nothing was written");
  std::vector<std::string> columns;
  std::size_t text_columns = 0;
  for (const auto& c : log.columns) {
    // A battery log's voltage_v is a reading the model does not simulate: beside a simulated
    // charge it would contradict it.
    if (log.kind == logs::Kind::battery && c == "voltage_v") continue;
    if (log.has(c)) columns.push_back(c);
    else ++text_columns;
  }
  if (text_columns > 0)
    std::fprintf(stderr, "simulate: text columns of %s are not copied (only numeric columns are)\n", o.like.c_str());
  logs::LogWriter w(columns);
  const std::string model = o.coefficients.empty() || o.coefficients == "plugin" ? std::string(" with the plug-in's published model")
                                                                                 : " with " + o.coefficients;
  w.comment("Simulated by epuck2-fit simulate " + std::string(logs::to_string(log.kind)) + " --like " + o.like + model +
            (o.noise ? " and reading noise, seed " + std::to_string(o.seed) : std::string(", without noise")));
  // The log's conditions are the simulation's too (robot, obstacle distance), but its seed is the
  // recording's: the simulation's own replaces it (with --noise), or none is written.
  for (const auto& [k, v] : log.metadata)
    if (k != "seed") w.metadata(k, v);
  if (o.noise) w.metadata("seed", std::to_string(o.seed));
  for (std::size_t i = 0; i < log.rows(); ++i) {
    std::vector<double> row;
    for (const auto& c : columns) {
      const auto at = std::find(replaced.begin(), replaced.end(), c);
      row.push_back(at == replaced.end() ? log.col(c)[i] : simulated[i][static_cast<std::size_t>(at - replaced.begin())]);
    }
    w.row(row);
  }
  write_output(w.str(), o.output);
  if (!o.output.empty()) std::cerr << "simulate: wrote " << o.output << '\n';
  return 0;
}


void setup_simulate_like(CLI::App& sim, Action& action) {
  for (logs::Kind kind : {logs::Kind::proximity, logs::Kind::light, logs::Kind::ground, logs::Kind::camera, logs::Kind::drive}) {
    auto o = std::make_shared<LikeOptions>();
    o->kind = kind;
    const std::string name(logs::to_string(kind));
    CLI::App* sub = sim.add_subcommand(
        name, "Run the " + name + " model on a measured log's conditions and write the same log with simulated readings");
    sub->add_option("--like", o->like, "The measured " + name + " log (docs/logs.md) whose conditions are simulated")
        ->required()
        ->check(CLI::ExistingFile);
    sub->add_option("--coefficients", o->coefficients,
                    "Coefficient file (`epuck2-fit " + name + " -o` or `diagnose -o`: base, effects, noise); "
                    "default: the plug-in's published model")
        ->check(CLI::ExistingFile);
    sub->add_flag("--noise", o->noise, "Add the file's reading noise (Gaussian, its `noise` section)");
    sub->add_option("--seed", o->seed, "Seed of the noise")->capture_default_str();
    sub->add_option("-o,--output", o->output, "Write the log to this file (atomically) instead of standard output")
        ->type_name("FILE")
        ->check(output_file());
    add_skip_bad_rows(sub, o->skip_bad_rows);
    sub->callback([o, &action] { action = [o] { return run_like(*o); }; });
  }
}

}  // namespace epuck2::app
