// The helpers the sensor fits share (proximity_fit.cpp, light_fit.cpp, ground_fit.cpp,
// camera_fit.cpp, drive_fit.cpp): internal to lib/calibrate, not part of its interface.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/fit/robust.hpp"
#include "epuck2/logs/log.hpp"

namespace epuck2::calibrate::sensor_fit_detail {

double mse_of(const std::vector<double>& residuals);

std::string where(const logs::Log& log, std::size_t row);

std::string fmt(double v, int digits = 4);

void collect(std::vector<std::string>& into, const std::string& prefix, const std::vector<std::string>& from);

fit::RobustOptions robust_options(const SensorFitOptions& o, double noise_floor);

// Quantisation noise of an integer reading: 1/sqrt(12) of a count.
constexpr double kQuantisationSd = 0.28867513459481287;

/// Groups of readings under the same conditions: an id per distinct key.
template <class Key>
class Groups {
 public:
  int of(const Key& k) { return ids_.emplace(k, static_cast<int>(ids_.size())).first->second; }

 private:
  std::map<Key, int> ids_;
};

/// A sensor index from a log's `sensor` column (0 when the log has none).
int sensor_of(const logs::Log& log, std::size_t row);

/// `robot`'s index in `names` (the logs' robots in the order first met), added when new.
int robot_index(std::vector<std::string>& names, const std::string& robot);

}  // namespace epuck2::calibrate::sensor_fit_detail
