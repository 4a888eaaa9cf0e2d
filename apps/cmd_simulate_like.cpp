// epuck2-fit simulate {proximity,light,ground,camera,drive} --like LOG [--coefficients FILE]
//                     [--noise] [--seed N] [-o FILE]
// Runs the runtime model library (lib/models kinds.hpp) on the conditions of a measured log
// (distances and sensors, intensities, grey levels, LED positions, commands and the obstacle's
// distance) and writes a log in the same format with the simulated readings in place of the
// measured ones: comparable row by row. Without --coefficients, the plug-in's published model.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "app_support.hpp"
#include "commands.hpp"
#include "epuck2/calibrate/model_file.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/logs/output.hpp"
#include "epuck2/models/kinds.hpp"

namespace epuck2::app {
namespace {

namespace s = models::sensors;

struct LikeOptions {
  logs::Kind kind = logs::Kind::proximity;
  std::string like;
  std::string coefficients;
  bool noise = false;
  std::uint64_t seed = 1;
  std::string output;
  bool skip_bad_rows = false;
};

/// The columns the kind's readings are in (replaced by the simulation).
std::vector<std::string> reading_columns(logs::Kind kind) {
  switch (kind) {
    case logs::Kind::camera: return {"px", "py"};
    case logs::Kind::drive: return {"left_steps", "right_steps", "tof_mm"};
    default: return {"value"};
  }
}

template <class Model>
Model load(const LikeOptions& o, Model (*from_json)(const nlohmann::json&, const std::string&)) {
  if (o.coefficients.empty()) return Model{};
  try {
    return from_json(read_json(o.coefficients), o.coefficients);
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
      const auto m = load<s::ProximityModel>(o, calibrate::proximity_model_from_json);
      const auto& d = log.col("distance_m");
      const auto& sn = log.col("sensor");
      const bool angle = log.has("angle_deg");
      for (std::size_t i = 0; i < n; ++i) {
        const double c = angle ? std::cos(s::deg_to_rad(log.col("angle_deg")[i])) : 1.0;
        out[i] = {draw([&](auto& g) { return double(s::reading(m, static_cast<int>(sn[i]), d[i], c, g)); },
                       [&] { return std::clamp(s::mean_raw(m, static_cast<int>(sn[i]), d[i], c), 0.0, s::kProximityFullScale_raw); })};
      }
      break;
    }
    case logs::Kind::light: {
      const auto m = load<s::LightModel>(o, calibrate::light_model_from_json);
      const auto& d = log.col("distance_m");
      const auto& in = log.col("intensity");
      const auto& sn = log.col("sensor");
      for (std::size_t i = 0; i < n; ++i)
        out[i] = {draw([&](auto& g) { return double(s::reading(m, static_cast<int>(sn[i]), in[i], d[i], g)); },
                       [&] { return std::clamp(s::mean_raw(m, static_cast<int>(sn[i]), in[i], d[i]), 0.0, s::kProximityFullScale_raw); })};
      break;
    }
    case logs::Kind::ground: {
      const auto m = load<s::GroundModel>(o, calibrate::ground_model_from_json);
      const auto& grey = log.col("grey");
      const auto& sn = log.col("sensor");
      for (std::size_t i = 0; i < n; ++i)
        out[i] = {draw([&](auto& g) { return double(s::reading(m, static_cast<int>(sn[i]), grey[i], g)); },
                       [&] { return std::clamp(s::mean_raw(m, static_cast<int>(sn[i]), grey[i]), 0.0, s::kGroundFullScale_raw); })};
      break;
    }
    case logs::Kind::camera: {
      const auto m = load<s::CameraModel>(o, calibrate::camera_model_from_json);
      const auto& f = log.col("forward_m");
      const auto& l = log.col("lateral_m");
      const auto& v = log.col("vertical_m");
      for (std::size_t i = 0; i < n; ++i) {
        if (o.noise) {
          const auto p = s::reading(m, f[i], l[i], v[i], normal);
          out[i] = {static_cast<double>(p[0]), static_cast<double>(p[1])};
        } else {
          const auto p = s::mean_px(m, f[i], l[i], v[i]);
          out[i] = {p[0], p[1]};
        }
      }
      break;
    }
    case logs::Kind::drive: {
      const auto m = load<s::DriveModel>(o, calibrate::drive_model_from_json);
      s::DriveSimulation sim(m, log.metadata_number("obstacle_distance_m"));
      const auto& t = log.col("time_s");
      const auto& cl = log.col("left_speed_cm_s");
      const auto& cr = log.col("right_speed_cm_s");
      for (std::size_t i = 0; i < n; ++i) {
        // The drive's registers are integers either way (the encoders' floor is the model's).
        struct Silent {
          double operator()() const { return 0.0; }
        } silent;
        const auto r = o.noise ? sim.sample(t[i], cl[i], cr[i], normal) : sim.sample(t[i], cl[i], cr[i], silent);
        out[i] = {static_cast<double>(r.left_steps), static_cast<double>(r.right_steps), static_cast<double>(r.tof_mm)};
      }
      break;
    }
    default:
      throw UsageError("simulate --like does not support the kind '" + std::string(logs::to_string(log.kind)) + "'");
  }
  return out;
}

int run_like(const LikeOptions& o) {
  const auto logs = read_logs_reporting("simulate", {o.like}, o.kind, o.skip_bad_rows);
  const logs::Log& log = logs.front();
  s::StandardNormal normal(o.seed);
  const auto simulated = simulate(o, log, normal);
  const std::vector<std::string> replaced = reading_columns(log.kind);
  std::vector<std::string> columns;
  for (const auto& c : log.columns)
    if (log.has(c)) columns.push_back(c);
  if (columns.size() < log.columns.size())
    std::fprintf(stderr, "simulate: text columns of %s are not copied (only numeric columns are)\n", o.like.c_str());
  logs::LogWriter w(columns);
  w.comment("Simulated by epuck2-fit simulate " + std::string(logs::to_string(log.kind)) + " --like " + o.like +
            (o.coefficients.empty() ? std::string(" with the plug-in's published model") : " with " + o.coefficients) +
            (o.noise ? " and reading noise, seed " + std::to_string(o.seed) : std::string(", without noise")));
  for (const auto& [k, v] : log.metadata) w.metadata(k, v);
  for (std::size_t i = 0; i < log.rows(); ++i) {
    std::vector<double> row;
    for (const auto& c : columns) {
      const auto at = std::find(replaced.begin(), replaced.end(), c);
      row.push_back(at == replaced.end() ? log.col(c)[i] : simulated[i][static_cast<std::size_t>(at - replaced.begin())]);
    }
    w.row(row);
  }
  write_output(w.str(), o.output);
  return 0;
}

}  // namespace

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
    sub->add_option("-o,--output", o->output, "Write the log to this file (atomically) instead of standard output");
    add_skip_bad_rows(sub, o->skip_bad_rows);
    sub->callback([o, &action] { action = [o] { return run_like(*o); }; });
  }
}

}  // namespace epuck2::app
