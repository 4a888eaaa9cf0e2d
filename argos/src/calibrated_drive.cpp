#include "calibrated_drive.hpp"

#include <string>

namespace epuck2::argos_plugin {

namespace {

/// effects.<name>.<parameter>: a number (checked), or `fallback` when the file has no such effect.
double effect_number(const CoefficientFile& file, const std::string& name, const std::string& parameter,
                     double fallback) {
  const nlohmann::json& e = file.effects();
  if (!e.contains(name)) return fallback;
  const nlohmann::json& o = e.at(name);
  if (!o.is_object() || !o.contains(parameter) || !o.at(parameter).is_number())
    file.fail("effects." + name + "." + parameter + " must be a number, found " +
              (o.is_object() && o.contains(parameter) ? o.at(parameter).dump() : "none"));
  return o.at(parameter).get<double>();
}

}  // namespace

DriveConfig read_drive_config(const CoefficientFile& file, const std::string& who) {
  DriveConfig c;
  for (auto it = file.effects().begin(); it != file.effects().end(); ++it) {
    const std::string& name = it.key();
    if (name == "speed_limit" || name == "accel_limit" || name == "speed_scale" || name == "latency") continue;
    if (name.rfind("covariate:", 0) == 0)
      file.fail("effects." + name + ": " + who + " cannot apply it in ARGoS: it needs the log column '" +
                name.substr(10) + "', which ARGoS does not have (a diagnosis without --effects " + name +
                ", or a calibration file, runs in ARGoS)");
    file.fail("effects." + name + ": not a drive effect " + who +
              " can apply (the drive's are speed_limit, accel_limit, speed_scale, latency; wheel_slip, "
              "tof_offset and tof_scale are parameters)");
  }
  c.steps_per_m = file.scalar_or("steps_per_m", ms::kPluginStepsPerMetre);
  if (!(c.steps_per_m > 0)) file.fail("steps_per_m must be positive");
  c.effects.slip.tau_s = file.scalar_or("slip_time_constant_s", 0.0);
  if (!(c.effects.slip.tau_s >= 0)) file.fail("slip_time_constant_s must not be negative");
  if (file.effects().contains("speed_limit")) {
    c.effects.speed_limit.max_cm_s = effect_number(file, "speed_limit", "max_cm_s", 0);
    if (!(c.effects.speed_limit.max_cm_s > 0)) file.fail("effects.speed_limit.max_cm_s must be positive");
    c.limit_from = "speed_limit";
  } else {
    c.effects.speed_limit.max_cm_s = firmware_cap_cm_s(c.steps_per_m);
    c.limit_from = "firmware";
  }
  c.effects.accel_limit.accel_cm_s2 = effect_number(file, "accel_limit", "accel_cm_s2", ms::kDriveNoLimit);
  if (!(c.effects.accel_limit.accel_cm_s2 > 0)) file.fail("effects.accel_limit.accel_cm_s2 must be positive");
  c.effects.speed_scale.k = effect_number(file, "speed_scale", "k", 1.0);
  if (!(c.effects.speed_scale.k > 0)) file.fail("effects.speed_scale.k must be positive");
  c.effects.latency.delay_s = effect_number(file, "latency", "delay_s", 0.0);
  if (!(c.effects.latency.delay_s >= 0)) file.fail("effects.latency.delay_s must not be negative");
  c.effects.tof_scale.k = file.scalar_or("tof_scale", 1.0);
  c.effects.tof_offset.offset_mm = file.scalar_or("tof_offset_mm", 0.0);
  return c;
}

}  // namespace epuck2::argos_plugin
