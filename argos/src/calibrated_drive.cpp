#include "calibrated_drive.hpp"

#include <epuck2/models/effects.hpp>

#include <stdexcept>
#include <string>

#include <epuck2/coefficients/model_file.hpp>

namespace epuck2::argos_plugin {

DriveConfig read_drive_config(const CoefficientFile& file, const std::string& who) {
  /* What ARGoS cannot apply, said here; everything else is the project's one reader's
     (lib/coefficients: names, ranges, robot sets, errors at file:line:column) */
  for (auto it = file.effects().begin(); it != file.effects().end(); ++it) {
    const std::string& name = it.key();
    if (name.rfind("covariate:", 0) == 0)
      file.fail("effects." + name + ": " + who + " cannot apply it in ARGoS: it needs the log column '" +
                name.substr(10) + "', which ARGoS does not have (a diagnosis without --effects " + name +
                ", or a calibration file, runs in ARGoS)");
  }
  ms::DriveModel m;
  try {
    m = epuck2::coefficients::drive_model_from_json(file.root(), file.path(), file.robot());
  } catch (const std::exception& e) {
    throw std::runtime_error(e.what());
  }
  DriveConfig c;
  c.steps_per_m = m.steps_per_m;
  c.effects = m.effects;
  if (m.effects.speed_limit.max_cm_s < ms::kDriveLimitOn) {
    c.limit_from = epuck2::models::effects::drive_catalogue()[epuck2::models::effects::drive::speed_limit].name;
  } else {
    c.effects.speed_limit.max_cm_s = firmware_cap_cm_s(c.steps_per_m);
    c.limit_from = "firmware";
  }
  return c;
}

}  // namespace epuck2::argos_plugin
