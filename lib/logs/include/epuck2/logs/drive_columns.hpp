// A drive log's columns as the calibration (lib/calibrate drive_fit.cpp) and the diagnosis
// (lib/diagnose kind_drive.cpp) read them: one reader, so that the two cannot read the log apart.
#pragma once

#include <vector>

#include "epuck2/logs/log.hpp"

namespace epuck2::logs {

/// The columns of a drive log (docs/logs.md, "drive"), as the reader validated them; the step
/// registers as logged (int16, wrapping: lib/models' unwrap_steps unwraps them).
struct DriveColumns {
  const std::vector<double>& time_s;
  const std::vector<double>& left_cm_s;   ///< left_speed_cm_s, the command
  const std::vector<double>& right_cm_s;  ///< right_speed_cm_s
  const std::vector<double>& left_steps;
  const std::vector<double>& right_steps;
  const std::vector<double>& tof_mm;
  double obstacle_m;  ///< the metadata's obstacle_distance_m
};

/// The drive columns of `log` (a drive log read by read_log).
inline DriveColumns drive_columns(const Log& log) {
  return {log.col("time_s"),     log.col("left_speed_cm_s"), log.col("right_speed_cm_s"),
          log.col("left_steps"), log.col("right_steps"),     log.col("tof_mm"),
          log.metadata_number("obstacle_distance_m")};
}

}  // namespace epuck2::logs
