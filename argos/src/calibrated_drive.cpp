#include "calibrated_drive.hpp"
#include "applied_effects.hpp"

#include <epuck2/models/effects.hpp>

#include <string>

#include <epuck2/coefficients/model_file.hpp>
#include <epuck2/coefficients/model_sets.hpp>

namespace epuck2::argos_plugin {

DriveConfig read_drive_config(const nlohmann::json& root, const std::string& path, const std::string& robot,
                              const std::string& who) {
  /* Everything is the project's one reader's (lib/coefficients: names, ranges, robot sets, errors
     at file:line:column); what ARGoS cannot apply is said here */
  const ms::DriveModel m = epuck2::coefficients::drive_model_from_json(root, path, robot);
  if (!m.covariates.empty()) {
    const std::string name = std::string(epuck2::models::effects::kCovariatePrefix) + m.covariates.front().column;
    epuck2::coefficients::fail_in_file(
        path, "/effects/" + name,
        "effects." + name + ": " + who + " cannot apply it in ARGoS: it needs the log column '" +
            m.covariates.front().column + "', which ARGoS does not have (a diagnosis without --effects " + name +
            ", or a calibration file, runs in ARGoS)");
  }
  /* what neither the wheels nor the ToF apply would be ignored: refused (applied_effects.hpp) */
  refuse_unapplied(m, drive_applies(), root, path, robot, who);
  DriveConfig c;
  c.steps_per_m = m.steps_per_m;
  c.effects = m.effects;
  /* A calibration that found the encoders beat the firmware's cap says so (firmware_cap.kept
     false): simulate and codegen run such a file uncapped, and so do the wheels here. */
  const bool bCapRefuted = epuck2::coefficients::firmware_cap_refuted(root);
  if (m.effects.speed_limit.max_cm_s < ms::kDriveLimitOn) {
    c.limit_from = epuck2::models::effects::drive_catalogue()[epuck2::models::effects::drive::speed_limit].name;
  } else if (bCapRefuted) {
    c.effects.speed_limit.max_cm_s = ms::kDriveNoLimit;
    c.limit_from = "calibration";
  } else {
    c.effects.speed_limit.max_cm_s = firmware_cap_cm_s(c.steps_per_m);
    c.limit_from = "firmware";
  }
  return c;
}

DriveConfig read_drive_config(const std::string& path, const std::string& who) {
  return read_drive_config(epuck2::coefficients::read_json_file(path), path, "", who);
}

}  // namespace epuck2::argos_plugin
