// The camera fit (see epuck2/calibrate/sensors.hpp; the shared conventions: proximity_fit.cpp).
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
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/models/saturation.hpp"
#include "epuck2/logs/json_location.hpp"
#include "sensor_fit_common.hpp"

namespace epuck2::calibrate {

using namespace epuck2::fit;  // the engine (lib/fit)
using namespace sensor_fit_detail;  // the sensor fits' shared helpers

namespace s = models::sensors;

namespace {
// px and py of every observation (2 per LED sighting), p = {fov_deg, cx_px, cy_px}:
// px = cx - f y / x, py = cy - f z / x, f = (W/2) / tan(fov/2).
struct CameraModel {
  std::vector<CameraObservation> obs;
  template <typename T>
  bool operator()(const T* p, T* out) const {
    for (std::size_t i = 0; i < obs.size(); ++i)
      s::camera_projection(T(s::deg_to_rad(1.0)) * p[0], p[1], p[2], s::kCameraWidth_px, obs[i].forward_m, obs[i].lateral_m,
                           obs[i].vertical_m, &out[2 * i], &out[2 * i + 1]);
    return true;
  }
};
}  // namespace

CameraFit fit_camera(const std::vector<logs::Log>& logs, const SensorFitOptions& options) {
  CameraFit out;
  std::vector<Observation> obs;
  std::map<std::tuple<double, double, double>, int> groups;
  for (const logs::Log& log : logs) {
    const auto& x = log.col("forward_m");
    const auto& y = log.col("lateral_m");
    const auto& z = log.col("vertical_m");
    const auto& px = log.col("px");
    const auto& py = log.col("py");
    const int robot = robot_index(out.robot_names, log.robot);
    for (std::size_t i = 0; i < log.rows(); ++i) {
      out.observations.push_back({x[i], y[i], z[i], px[i], py[i], where(log, i), robot});
      const int g = groups.emplace(std::make_tuple(x[i], y[i], z[i]), static_cast<int>(groups.size())).first->second;
      obs.push_back({px[i], Censoring::none, where(log, i), 2 * g, robot});
      obs.push_back({py[i], Censoring::none, where(log, i), 2 * g + 1, robot});
    }
  }
  const s::CameraCoefficients plugin = s::plugin_camera();
  if (out.observations.size() < 2) {
    out.result.message = "too few camera observations (" + std::to_string(out.observations.size()) +
                         ") for 3 parameters and their noise";
    return out;
  }
  const double fov = s::rad_to_deg(plugin.horizontal_fov_rad);
  const double inf = std::numeric_limits<double>::infinity();
  // The field of view lies within (0, 180) degrees.
  out.result = fit_robust(CameraModel{out.observations}, obs,
                          {{"fov_deg", fov, fov, 1e-3, 179.9},
                           {"cx_px", plugin.cx_px, plugin.cx_px, -inf, inf},
                           {"cy_px", plugin.cy_px, plugin.cy_px, -inf, inf}},
                          robust_options(options, kQuantisationSd));
  collect(out.warnings, "", out.result.warnings);

  // The plug-in's MSE on the readings the fit's MSE is over: those not left out as wild (px and
  // py each a reading, as the fit has them).
  std::vector<bool> left_out(obs.size(), false);
  for (std::size_t i : out.result.outliers)
    if (i < left_out.size()) left_out[i] = true;
  std::vector<double> r, alphas;
  for (std::size_t i = 0; i < out.observations.size(); ++i) {
    const auto& o = out.observations[i];
    double mx, my;
    s::camera_projection(plugin.horizontal_fov_rad, plugin.cx_px, plugin.cy_px, s::kCameraWidth_px, o.forward_m,
                         o.lateral_m, o.vertical_m, &mx, &my);
    if (!left_out[2 * i]) r.push_back(o.px - mx);
    if (!left_out[2 * i + 1]) r.push_back(o.py - my);
    const double offset = o.px - s::kCameraWidth_px / 2.0;
    if (std::abs(offset) > s::kCameraWidth_px / 4.0 && o.lateral_m != 0.0)
      alphas.push_back(s::rad_to_deg(s::alpha_from_pixel_offset_rad(o.forward_m, o.lateral_m, offset)));
  }
  out.plugin_mse = mse_of(r);
  out.plugin_readings = r.size();
  out.table4_points = alphas.size();
  if (!alphas.empty()) {
    const double mean = std::accumulate(alphas.begin(), alphas.end(), 0.0) / static_cast<double>(alphas.size());
    double ss = 0;
    for (double a : alphas) ss += (a - mean) * (a - mean);
    out.table4_alpha_mean_deg = mean;
    out.table4_alpha_sd_deg = alphas.size() > 1 ? std::sqrt(ss / static_cast<double>(alphas.size() - 1)) : 0.0;
  }

  // The reading noise: the frames of each LED position, px and py each their own group, pooled.
  // Blobs have no rail (a blob off the image is not seen). The plug-in's camera draws no noise:
  // no ARGoS scale.
  std::vector<double> nv;
  std::vector<int> ng, ns;
  std::vector<bool> nr;
  Groups<std::tuple<std::size_t, double, double, double, int>> frames;
  for (std::size_t l = 0; l < logs.size(); ++l) {
    const auto& x = logs[l].col("forward_m");
    const auto& y = logs[l].col("lateral_m");
    const auto& z = logs[l].col("vertical_m");
    const auto& px = logs[l].col("px");
    const auto& py = logs[l].col("py");
    for (std::size_t i = 0; i < logs[l].rows(); ++i)
      for (int axis = 0; axis < 2; ++axis) {
        nv.push_back(axis == 0 ? px[i] : py[i]);
        ng.push_back(frames.of({l, x[i], y[i], z[i], axis}));
        ns.push_back(0);
        nr.push_back(false);
      }
  }
  out.noise = replicates_or_residuals(noise_from_replicates("camera", "px", 0.0, nv, ng, nr, ns, 0, kQuantisationSd),
                                      noise_from_residuals("camera", "px", 0.0, out.result));
  return out;
}

}  // namespace epuck2::calibrate
