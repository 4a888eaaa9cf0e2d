// Sensor calibration fits (see epuck2/fit/sensors.hpp): proximity, light, ground, camera, drive,
// and the loaders of the coefficient files the CLI writes.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "epuck2/fit/sensors.hpp"
#include "epuck2/logs/json_location.hpp"

namespace epuck2::fit {

namespace s = models::sensors;

namespace {

double mse_of(const std::vector<double>& residuals) {
  if (residuals.empty()) return 0.0;
  double sum = 0;
  for (double r : residuals) sum += r * r;
  return sum / static_cast<double>(residuals.size());
}

// Eq. 1's quadratic, normalised response against the distance: y = a d^2 + b d + c.
struct ProximityModel {
  static constexpr int kParameters = 3;
  template <typename T>
  T operator()(const T* abc, double distance_m) const {
    return s::proximity_polynomial(abc, distance_m);
  }
};

// Eq. 2 for one light: y = 1 - (gamma x)^2 with x = intensity / distance (per metre), since the
// response depends on the two only through their ratio.
struct LightModel {
  static constexpr int kParameters = 1;
  template <typename T>
  T operator()(const T* gamma_m, double intensity_per_m) const {
    return s::light_response(gamma_m[0], intensity_per_m, 1.0);
  }
};

// Ground: y = offset + gain grey, p = {gain_raw, offset_raw}.
struct GroundModel {
  static constexpr int kParameters = 2;
  template <typename T>
  T operator()(const T* p, double grey) const {
    return s::ground_response(p[0], p[1], grey);
  }
};

// Encoder steps against the commanded distance: y = steps_per_m x.
struct StepsModel {
  static constexpr int kParameters = 1;
  template <typename T>
  T operator()(const T* steps_per_m, double distance_m) const {
    return steps_per_m[0] * distance_m;
  }
};

// Camera: residuals (px - px_model, py - py_model) in pixels, with
// px_model = cx - f y/x, py_model = cy - f z/x, f = (W/2)/tan(fov/2), fov in degrees.
class CameraResidual {
 public:
  explicit CameraResidual(const CameraObservation& o) : o_(o) {}
  template <typename T>
  bool operator()(const T* p, T* residual) const {
    T px, py;
    s::camera_projection(T(s::deg_to_rad(1.0)) * p[0], p[1], p[2], s::kCameraWidth_px, o_.forward_m, o_.lateral_m,
                         o_.vertical_m, &px, &py);
    residual[0] = T(o_.px) - px;
    residual[1] = T(o_.py) - py;
    return true;
  }
  static ceres::CostFunction* Create(const CameraObservation& o) {
    return new ceres::AutoDiffCostFunction<CameraResidual, 2, 3>(new CameraResidual(o));
  }

 private:
  const CameraObservation o_;
};

// ToF along one run: residual_k = tof_k - (scale 1000 (D - g_k) + offset), g = the encoders'
// wheel travel lagged by tau (lagged_travel_m), p = {tof_scale, tof_offset_mm, tau_s}. Rows at
// the sensor's clamps (20 and 2000 mm) are skipped.
class TofRunResidual {
 public:
  TofRunResidual(const DriveRun& run, double steps_per_m, std::vector<std::size_t> rows)
      : run_(run), steps_per_m_(steps_per_m), rows_(std::move(rows)) {}
  template <typename T>
  bool operator()(T const* const* params, T* residual) const {
    const T* p = params[0];
    const std::vector<T> travel = lagged_travel_m(run_, steps_per_m_, p[2]);
    for (std::size_t i = 0; i < rows_.size(); ++i) {
      const std::size_t k = rows_[i];
      residual[i] = T(run_.tof_mm[k]) - s::tof_response_mm(p[0], p[1], T(run_.obstacle_distance_m) - travel[k]);
    }
    return true;
  }
  static ceres::CostFunction* Create(const DriveRun& run, double steps_per_m, std::vector<std::size_t> rows) {
    const int n = static_cast<int>(rows.size());
    auto* f = new ceres::DynamicAutoDiffCostFunction<TofRunResidual, 4>(new TofRunResidual(run, steps_per_m, std::move(rows)));
    f->AddParameterBlock(3);
    f->SetNumResiduals(n);
    return f;
  }

 private:
  const DriveRun& run_;
  const double steps_per_m_;
  const std::vector<std::size_t> rows_;
};

FitResult unusable(const std::string& why) {
  FitResult r;
  r.message = why;
  return r;
}

}  // namespace

// ================================================================================================
// Proximity
// ================================================================================================

ProximityFit fit_proximity(const std::vector<logs::Log>& logs, const s::ProximityCoefficients& start) {
  ProximityFit out;
  std::map<double, std::vector<double>> by_distance;
  for (const logs::Log& log : logs) {
    const auto& d = log.col("distance_m");
    const auto& v = log.col("value");
    for (std::size_t i = 0; i < log.rows(); ++i) by_distance[d[i]].push_back(v[i] / s::kProximityFullScale_raw);
    out.readings += log.rows();
  }
  std::vector<double> x, ymax, ymean;
  for (const auto& [d, values] : by_distance) {
    ProximityPoint p;
    p.distance_m = d;
    p.readings = values.size();
    p.max = *std::max_element(values.begin(), values.end());
    p.min = *std::min_element(values.begin(), values.end());
    p.mean = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
    if (d > start.range_m) {
      p.excluded_why = "beyond the sensor's range";
    } else if (p.max >= 1.0) {
      p.excluded_why = "saturated (4095)";
    } else if (p.mean < kProximityUndetectedFraction) {
      p.excluded_why = "nothing detected";
    } else {
      p.used = true;
      x.push_back(d);
      ymax.push_back(p.max);
      ymean.push_back(p.mean);
    }
    out.points.push_back(p);
  }
  const std::vector<double> initial{start.a_per_m2, start.b_per_m, start.c};
  const std::vector<std::string> names{"a", "b", "c"};
  out.maxima = fit_curve(ProximityModel{}, x, ymax, initial, names);
  out.means = fit_curve(ProximityModel{}, x, ymean, initial, names);
  auto reference_mse = [&](const s::ProximityCoefficients& k, const std::vector<double>& y) {
    std::vector<double> r;
    const double abc[3] = {k.a_per_m2, k.b_per_m, k.c};
    for (std::size_t i = 0; i < x.size(); ++i) r.push_back(y[i] - s::proximity_polynomial(abc, x[i]));
    return mse_of(r);
  };
  out.plugin_mse_maxima = reference_mse(s::kPluginProximity, ymax);
  out.plugin_mse_means = reference_mse(s::kPluginProximity, ymean);
  out.epuck1_mse_maxima = reference_mse(s::kEpuck1Proximity, ymax);
  out.epuck1_mse_means = reference_mse(s::kEpuck1Proximity, ymean);
  return out;
}

// ================================================================================================
// Light
// ================================================================================================

LightFit fit_light(const std::vector<logs::Log>& logs) {
  LightFit out;
  std::map<int, std::pair<std::vector<double>, std::vector<double>>> per_sensor;
  std::vector<double> x, y;
  for (const logs::Log& log : logs) {
    const auto& d = log.col("distance_m");
    const auto& in = log.col("intensity");
    const auto& sen = log.col("sensor");
    const auto& v = log.col("value");
    out.readings += log.rows();
    for (std::size_t i = 0; i < log.rows(); ++i) {
      // Saturated (0), dark (4095), a light out of range or of no intensity: no information on gamma.
      if (v[i] <= 0.0 || v[i] >= s::kProximityFullScale_raw || !(d[i] > 0) || d[i] > s::kPluginLight.range_m ||
          !(in[i] > 0)) {
        ++out.censored;
        continue;
      }
      const int sensor = static_cast<int>(sen[i]);
      out.observations.push_back({d[i], in[i], sensor, v[i]});
      x.push_back(in[i] / d[i]);
      y.push_back(v[i] / s::kProximityFullScale_raw);
      per_sensor[sensor].first.push_back(x.back());
      per_sensor[sensor].second.push_back(y.back());
    }
  }
  const std::vector<double> initial{s::kPluginLight.gamma_m};
  out.gamma = fit_curve(LightModel{}, x, y, initial, {"gamma"});
  for (const auto& [sensor, xy] : per_sensor) {
    out.sensors.push_back(sensor);
    out.gamma_per_sensor.push_back(fit_curve(LightModel{}, xy.first, xy.second, initial, {"gamma"}));
  }
  std::vector<double> r;
  for (std::size_t i = 0; i < x.size(); ++i) r.push_back(y[i] - s::light_response(s::kPluginLight.gamma_m, x[i], 1.0));
  out.plugin_mse = mse_of(r);
  return out;
}

// ================================================================================================
// Ground
// ================================================================================================

GroundFit fit_ground(const std::vector<logs::Log>& logs) {
  GroundFit out;
  for (const logs::Log& log : logs) {
    const auto& g = log.col("grey");
    const auto& sen = log.col("sensor");
    const auto& v = log.col("value");
    out.readings += log.rows();
    for (std::size_t i = 0; i < log.rows(); ++i) {
      // A reading at 0 or 1023 is clamped: it bounds the response without measuring it.
      if (v[i] <= 0.0 || v[i] >= s::kGroundFullScale_raw) {
        ++out.censored;
        continue;
      }
      const auto k = static_cast<std::size_t>(sen[i]);
      out.grey[k].push_back(g[i]);
      out.value_raw[k].push_back(v[i]);
    }
  }
  double rss = 0;
  std::size_t n = 0;
  for (int k = 0; k < s::kGroundCount; ++k) {
    const auto kk = static_cast<std::size_t>(k);
    out.sensors[kk] = fit_curve(GroundModel{}, out.grey[kk], out.value_raw[kk],
                                {s::kPluginGround.gain_raw, s::kPluginGround.offset_raw}, {"gain", "offset"});
    if (out.sensors[kk].usable) {
      rss += out.sensors[kk].rss;
      n += out.sensors[kk].observations;
    }
    std::vector<double> r;
    for (std::size_t i = 0; i < out.grey[kk].size(); ++i)
      r.push_back(out.value_raw[kk][i] - s::ground_response(s::kPluginGround.gain_raw, s::kPluginGround.offset_raw, out.grey[kk][i]));
    out.plugin_mse[kk] = mse_of(r);
  }
  out.mse = n ? rss / static_cast<double>(n) : 0.0;
  return out;
}

// ================================================================================================
// Camera
// ================================================================================================

CameraFit fit_camera(const std::vector<logs::Log>& logs) {
  CameraFit out;
  for (const logs::Log& log : logs) {
    const auto& x = log.col("forward_m");
    const auto& y = log.col("lateral_m");
    const auto& z = log.col("vertical_m");
    const auto& px = log.col("px");
    const auto& py = log.col("py");
    for (std::size_t i = 0; i < log.rows(); ++i) out.observations.push_back({x[i], y[i], z[i], px[i], py[i]});
  }
  const s::CameraCoefficients plugin = s::plugin_camera();
  if (out.observations.size() < 3) {
    out.result = unusable("too few camera observations (" + std::to_string(out.observations.size()) + ") for 3 parameters");
    return out;
  }
  std::vector<double> p{s::rad_to_deg(plugin.horizontal_fov_rad), plugin.cx_px, plugin.cy_px};
  ceres::Problem problem;
  std::vector<double> observed;
  FitOptions options;
  for (const auto& o : out.observations) {
    problem.AddResidualBlock(CameraResidual::Create(o), options.make_loss(), p.data());
    observed.push_back(o.px);
    observed.push_back(o.py);
  }
  // The field of view stays within (0, 180) degrees.
  problem.SetParameterLowerBound(p.data(), 0, 1e-3);
  problem.SetParameterUpperBound(p.data(), 0, 179.0);
  ceres::Solver::Summary summary;
  ceres::Solve(options.solver_options(), &problem, &summary);
  out.result = summarize(problem, ParameterLayout{{p.data()}, {3}, {"fov_deg", "cx_px", "cy_px"}}, observed, summary, options);

  std::vector<double> r, alphas;
  for (const auto& o : out.observations) {
    double mx, my;
    s::camera_projection(plugin.horizontal_fov_rad, plugin.cx_px, plugin.cy_px, s::kCameraWidth_px, o.forward_m,
                         o.lateral_m, o.vertical_m, &mx, &my);
    r.push_back(o.px - mx);
    r.push_back(o.py - my);
    const double offset = o.px - s::kCameraWidth_px / 2.0;
    if (std::abs(offset) > s::kCameraWidth_px / 4.0 && o.lateral_m != 0.0)
      alphas.push_back(s::rad_to_deg(s::alpha_from_pixel_offset_rad(o.forward_m, o.lateral_m, offset)));
  }
  out.plugin_mse = mse_of(r);
  out.table4_points = alphas.size();
  if (!alphas.empty()) {
    const double mean = std::accumulate(alphas.begin(), alphas.end(), 0.0) / static_cast<double>(alphas.size());
    double ss = 0;
    for (double a : alphas) ss += (a - mean) * (a - mean);
    out.table4_alpha_mean_deg = mean;
    out.table4_alpha_sd_deg = alphas.size() > 1 ? std::sqrt(ss / static_cast<double>(alphas.size() - 1)) : 0.0;
  }
  return out;
}

// ================================================================================================
// Drive
// ================================================================================================

DriveRun drive_run_from_log(const logs::Log& log) {
  DriveRun run;
  run.path = log.path;
  run.obstacle_distance_m = log.metadata_number("obstacle_distance_m");
  const auto& t = log.col("time_s");
  const auto& vl = log.col("left_speed_cm_s");
  const auto& vr = log.col("right_speed_cm_s");
  const auto& sl = log.col("left_steps");
  const auto& sr = log.col("right_steps");
  const auto& tof = log.col("tof_mm");
  const std::vector<double> ul = s::unwrap_steps(sl), ur = s::unwrap_steps(sr);
  for (std::size_t i = 0; i < log.rows(); ++i) {
    run.time_s.push_back(t[i]);
    const double v = 0.5 * (vl[i] + vr[i]) / 100.0;
    run.command_m_s.push_back(v);
    if (std::abs(vl[i]) / 100.0 > kFirmwareSpeedLimit_m_s || std::abs(vr[i]) / 100.0 > kFirmwareSpeedLimit_m_s)
      run.over_speed_limit = true;
    run.steps.push_back(0.5 * (ul[i] + ur[i]));
    run.tof_mm.push_back(tof[i]);
  }
  return run;
}

DriveFit fit_drive(const std::vector<logs::Log>& logs) {
  DriveFit out;
  for (const logs::Log& log : logs) out.runs.push_back(drive_run_from_log(log));

  // 1. Steps per metre: encoder steps against the commanded distance (a command holds until the
  //    next row), over the runs whose commands the firmware could follow.
  std::vector<double> x, y;
  for (const DriveRun& run : out.runs) {
    if (run.over_speed_limit) {
      out.excluded_from_steps.push_back(run.path);
      continue;
    }
    double commanded_m = 0;
    for (std::size_t k = 0; k < run.time_s.size(); ++k) {
      x.push_back(commanded_m);
      y.push_back(run.steps[k]);
      if (k + 1 < run.time_s.size()) commanded_m += run.command_m_s[k] * (run.time_s[k + 1] - run.time_s[k]);
    }
  }
  out.steps_rows = x.size();
  out.steps = fit_curve(StepsModel{}, x, y, {s::kPluginStepsPerMetre}, {"steps_per_m"});
  const double steps_per_m = out.steps.usable ? out.steps.value("steps_per_m") : s::kPluginStepsPerMetre;

  // 2. ToF scale and offset, with the slip lag, from every run.
  std::vector<double> p{1.0, 0.0, 0.05};  // scale, offset_mm, tau_s
  ceres::Problem problem;
  std::vector<double> observed, plugin_r;
  FitOptions options;
  for (const DriveRun& run : out.runs) {
    std::vector<std::size_t> rows;
    const std::vector<double> enc_travel = lagged_travel_m(run, s::kPluginStepsPerMetre, 1e-9);
    for (std::size_t k = 0; k < run.time_s.size(); ++k) {
      if (run.tof_mm[k] <= s::kPluginTof.min_mm || run.tof_mm[k] >= s::kPluginTof.max_mm) {
        ++out.tof_censored;
        continue;
      }
      rows.push_back(k);
      observed.push_back(run.tof_mm[k]);
      plugin_r.push_back(run.tof_mm[k] - 1000.0 * (run.obstacle_distance_m - enc_travel[k]));
    }
    if (rows.empty()) continue;
    problem.AddResidualBlock(TofRunResidual::Create(run, steps_per_m, rows), options.make_loss(), p.data());
  }
  out.tof_rows = observed.size();
  out.plugin_tof_mse = mse_of(plugin_r);
  if (observed.size() < 4) {
    out.tof = unusable("too few ToF readings (" + std::to_string(observed.size()) + ") for 3 parameters");
    return out;
  }
  problem.SetParameterLowerBound(p.data(), 2, 1e-4);  // the lag's time constant stays positive
  ceres::Solver::Summary summary;
  ceres::Solve(options.solver_options(), &problem, &summary);
  out.tof = summarize(problem, ParameterLayout{{p.data()}, {3}, {"tof_scale", "tof_offset_mm", "slip_time_constant_s"}},
                      observed, summary, options);
  return out;
}

// ================================================================================================
// Coefficient files
// ================================================================================================

namespace {

// A coefficient file's text (kept to place errors at their line) and its "parameters" object.
struct CoefficientFile {
  std::string path;
  std::string text;
  nlohmann::json parameters;
};

CoefficientFile load_parameters(const std::string& path, const std::string& kind) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw logs::InputError(path, 0, 0, "cannot open the coefficient file");
  std::ostringstream ss;
  ss << in.rdbuf();
  CoefficientFile f{path, ss.str(), {}};
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(f.text);
  } catch (const nlohmann::json::parse_error& e) {
    const logs::SourcePos at = logs::position_of(f.text, e.byte > 0 ? e.byte - 1 : 0);
    throw logs::InputError(path, at.line, at.column, std::string("not JSON: ") + e.what());
  } catch (const nlohmann::json::exception& e) {
    const logs::SourcePos at = logs::locate_json_overflow(f.text);  // e.g. 1e999
    throw logs::InputError(path, at.line, at.column, std::string("not JSON: ") + e.what());
  }
  if (!j.is_object()) throw logs::json_error(path, f.text, "", "expected an object with 'kind' and 'parameters'");
  if (j.contains("kind")) {
    if (!j.at("kind").is_string()) throw logs::json_error(path, f.text, "/kind", "expected 'kind' as a string");
    if (j.at("kind").get<std::string>() != kind)
      throw logs::json_error(path, f.text, "/kind", "a " + j.at("kind").get<std::string>() + " file, expected " + kind);
  }
  if (!j.contains("parameters") || !j.at("parameters").is_object())
    throw logs::json_error(path, f.text, "/parameters", "expected a 'parameters' object");
  f.parameters = j.at("parameters");
  return f;
}

double number(const CoefficientFile& f, const std::string& key) {
  if (!f.parameters.contains(key) || !f.parameters.at(key).is_number())
    throw logs::json_error(f.path, f.text, "/parameters/" + key, "expected a number 'parameters." + key + "'");
  return f.parameters.at(key).get<double>();
}

double number(const CoefficientFile& f, const std::string& key, std::size_t index, std::size_t count) {
  const std::string what = "expected 'parameters." + key + "' as an array of " + std::to_string(count) + " numbers";
  if (!f.parameters.contains(key) || !f.parameters.at(key).is_array() || f.parameters.at(key).size() != count)
    throw logs::json_error(f.path, f.text, "/parameters/" + key, what);
  const nlohmann::json& v = f.parameters.at(key).at(index);
  if (!v.is_number()) throw logs::json_error(f.path, f.text, "/parameters/" + key + "/" + std::to_string(index), what);
  return v.get<double>();
}

}  // namespace

s::ProximityCoefficients load_proximity_coefficients(const std::string& path) {
  const CoefficientFile f = load_parameters(path, "proximity");
  s::ProximityCoefficients k;
  k.a_per_m2 = number(f, "a");
  k.b_per_m = number(f, "b");
  k.c = number(f, "c");
  return k;
}

s::LightCoefficients load_light_coefficients(const std::string& path) {
  const CoefficientFile f = load_parameters(path, "light");
  s::LightCoefficients k;
  k.gamma_m = number(f, "gamma");
  return k;
}

std::array<s::GroundCoefficients, s::kGroundCount> load_ground_coefficients(const std::string& path) {
  const CoefficientFile f = load_parameters(path, "ground");
  std::array<s::GroundCoefficients, s::kGroundCount> k;
  for (std::size_t i = 0; i < k.size(); ++i) {
    k[i].gain_raw = number(f, "gain", i, k.size());
    k[i].offset_raw = number(f, "offset", i, k.size());
  }
  return k;
}

s::CameraCoefficients load_camera_coefficients(const std::string& path) {
  const CoefficientFile f = load_parameters(path, "camera");
  s::CameraCoefficients k;
  k.horizontal_fov_rad = s::deg_to_rad(number(f, "fov_deg"));
  k.cx_px = number(f, "cx_px");
  k.cy_px = number(f, "cy_px");
  return k;
}

DriveCoefficients load_drive_coefficients(const std::string& path) {
  const CoefficientFile f = load_parameters(path, "drive");
  DriveCoefficients k;
  k.encoder.steps_per_m = number(f, "steps_per_m");
  k.tof.scale = number(f, "tof_scale");
  k.tof.offset_mm = number(f, "tof_offset_mm");
  if (f.parameters.contains("slip_time_constant_s")) k.slip_time_constant_s = number(f, "slip_time_constant_s");
  return k;
}

}  // namespace epuck2::fit
