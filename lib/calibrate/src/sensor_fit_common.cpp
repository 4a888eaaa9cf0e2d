// The helpers the sensor fits share (sensor_fit_common.hpp).
#include "sensor_fit_common.hpp"

#include <sstream>
#include "epuck2/logs/output.hpp"

namespace epuck2::calibrate::sensor_fit_detail {

using namespace epuck2::fit;  // the engine (lib/fit)

double mse_of(const std::vector<double>& residuals) {
  if (residuals.empty()) return 0.0;
  double sum = 0;
  for (double r : residuals) sum += r * r;
  return sum / static_cast<double>(residuals.size());
}

std::string where(const logs::Log& log, std::size_t row) {
  return log.path + ":" + std::to_string(log.line_of_row.at(row));
}

std::string fmt(double v, int digits) { return logs::format_number(v, digits); }

void collect(std::vector<std::string>& into, const std::string& prefix, const std::vector<std::string>& from) {
  for (const std::string& w : from) into.push_back(prefix + w);
}

RobustOptions robust_options(const SensorFitOptions& o, double noise_floor) {
  RobustOptions r;
  r.robust = o.robust;
  r.reject_sd = o.reject_sd;
  r.noise_floor = noise_floor;
  return r;
}

/// A sensor index from a log's `sensor` column (0 when the log has none).
int sensor_of(const logs::Log& log, std::size_t row) {
  return log.has("sensor") ? static_cast<int>(log.col("sensor")[row]) : 0;
}

int robot_index(std::vector<std::string>& names, const std::string& robot) {
  const auto named = std::find(names.begin(), names.end(), robot);
  if (named != names.end()) return static_cast<int>(named - names.begin());
  names.push_back(robot);
  return static_cast<int>(names.size()) - 1;
}

}  // namespace epuck2::calibrate::sensor_fit_detail
