// The `calibrated` differential steering actuator: the wheels turn as the robot's wheels do, with
// the drive coefficient file's firmware cap (or a diagnosis's speed_limit), accel_limit,
// speed_scale and wheel_slip (lib/models drive.hpp's drive_advance, through calibrated_drive.hpp).
//
//   <actuators>
//     <differential_steering implementation="calibrated" coefficients="drive.json" [robot="ID"]/>
//
// The physics engine is given, every tick, the speeds that move the body as far as the model's
// body moves over that tick (with slip, behind the wheels); the robot's calibrated encoders count
// the wheels' own travel, and its calibrated ToF reads the body's distance (delayed by latency).
#include <argos3/core/simulator/actuator.h>
#include <argos3/core/simulator/entity/composable_entity.h>
#include <argos3/core/simulator/physics_engine/physics_engine.h>
#include <argos3/core/simulator/simulator.h>
#include <argos3/core/utility/logging/argos_log.h>
#include <argos3/core/utility/plugins/factory.h>
#include <argos3/core/utility/string_utilities.h>
#include <argos3/plugins/robots/generic/control_interface/ci_differential_steering_actuator.h>
#include <argos3/plugins/simulator/entities/wheeled_entity.h>

#include <memory>
#include <sstream>

#include "calibrated_drive.hpp"
#include <epuck2/models/effects.hpp>
#include <epuck2/coefficients/model_sets.hpp>

namespace argos {

namespace {
namespace fx = epuck2::models::effects;
/// A drive effect's name, from the registry (the help text below names effects through it).
std::string DriveEffectName(std::size_t un_id) { return fx::drive_catalogue()[un_id].name; }
}  // namespace

class CEPuck2CalibratedDifferentialSteeringActuator : public CSimulatedActuator,
                                                      public CCI_DifferentialSteeringActuator {
 public:
  void SetRobot(CComposableEntity& c_entity) override {
    m_pcRobot = &c_entity;
    try {
      m_pcWheeledEntity = &c_entity.GetComponent<CWheeledEntity>("wheels");
      if (m_pcWheeledEntity->GetNumWheels() != 2)
        THROW_ARGOSEXCEPTION("the differential steering actuator needs a robot with 2 wheels");
      m_pcWheeledEntity->Enable();
    } catch (CARGoSException& ex) {
      THROW_ARGOSEXCEPTION_NESTED("calibrated differential_steering: robot \"" << c_entity.GetId() << "\"", ex);
    }
  }

  void Init(TConfigurationNode& t_tree) override {
    CCI_DifferentialSteeringActuator::Init(t_tree);
    std::string strFile, strRobot, strRobotMap;
    bool bFirmwareCap = true;
    GetNodeAttributeOrDefault(t_tree, "firmware_cap", bFirmwareCap, bFirmwareCap);
    GetNodeAttributeOrDefault(t_tree, "coefficients", strFile, strFile);
    GetNodeAttributeOrDefault(t_tree, "robot", strRobot, strRobot);
    GetNodeAttributeOrDefault(t_tree, "robot_map", strRobotMap, strRobotMap);
    if (strFile.empty())
      THROW_ARGOSEXCEPTION(
          "calibrated differential_steering: the attribute 'coefficients' is required (a drive coefficient file or "
          "a drive diagnosis written by epuck2-fit)");
    ExpandEnvVariables(strFile);
    const std::string strPath =
        epuck2::coefficients::resolve_model_path(strFile, CSimulator::GetInstance().GetExperimentFileName());
    epuck2::argos_plugin::DriveConfig sConfig;
    try {
      /* robot="auto": this robot's own set, by its entity id or robot_map */
      const auto pcRoot = epuck2::coefficients::shared_json_file(strPath);
      const auto sChoice = epuck2::coefficients::choose_robot(*pcRoot, strPath, strRobot, strRobotMap, m_pcRobot->GetId());
      if (!sChoice.warning.empty()) {
        static bool bWarned = false;
        if (!bWarned) LOGERR << "[WARNING] calibrated differential_steering: " << sChoice.warning << std::endl;
        bWarned = true;
      }
      sConfig = epuck2::argos_plugin::read_drive_config(*pcRoot, strPath, sChoice.robot,
                                                        "the calibrated differential_steering actuator");
    } catch (const std::exception& ex) {
      THROW_ARGOSEXCEPTION("calibrated differential_steering: " << ex.what());
    }
    /* firmware_cap="false": a robot without the e-puck2 firmware's cap (a simulated robot of
       another model); a diagnosis's speed_limit still applies */
    if (!bFirmwareCap && sConfig.limit_from == "firmware") {
      sConfig.effects.speed_limit.max_cm_s = epuck2::models::sensors::kDriveNoLimit;
      sConfig.limit_from = "none";
    }
    m_pcDrive = epuck2::argos_plugin::DriveRegistry::create(m_pcRobot, sConfig.effects);
    std::ostringstream os;
    os << "calibrated differential_steering: " << strPath << ": ";
    if (sConfig.limit_from == "none")
      os << "wheels not capped (firmware_cap=\"false\")";
    else if (sConfig.limit_from == "calibration")
      os << "wheels not capped (the calibration found the encoders beat the firmware's cap: firmware_cap.kept false)";
    else
      os << "wheels capped at " << sConfig.effects.speed_limit.max_cm_s << " cm/s ("
         << (sConfig.limit_from == "firmware" ? "the firmware's 1100 steps/s over steps_per_m" : "the diagnosis's " + sConfig.limit_from)
         << ")";
    if (sConfig.effects.accel_limit.accel_cm_s2 < epuck2::models::sensors::kDriveLimitOn)
      os << ", acceleration limited to " << sConfig.effects.accel_limit.accel_cm_s2 << " cm/s^2";
    if (sConfig.effects.speed_scale.k != 1.0) os << ", body speed " << sConfig.effects.speed_scale.k << " x the wheels'";
    if (sConfig.effects.slip.tau_s > 0) os << ", body lagging the wheels by tau = " << sConfig.effects.slip.tau_s << " s";
    static bool bSaid = false;  // once per process: 50 robots, one line
    if (!bSaid) {
      LOG << "[INFO] " << os.str() << std::endl;
      bSaid = true;
    }
  }

  void SetLinearVelocity(Real f_left_velocity, Real f_right_velocity) override {
    /* cm/s, as the controller gives them; the drive model caps and ramps them at Update */
    m_fCommand[0] = f_left_velocity;
    m_fCommand[1] = f_right_velocity;
  }

  void Update() override {
    const auto v = m_pcDrive->step(m_fCommand[0], m_fCommand[1], CPhysicsEngine::GetSimulationClockTick());
    m_fCurrentVelocity[0] = v[0];
    m_fCurrentVelocity[1] = v[1];
    m_pcWheeledEntity->SetVelocities(m_fCurrentVelocity);
  }

  void Reset() override {
    m_fCommand[0] = m_fCommand[1] = 0.0;
    m_fCurrentVelocity[0] = m_fCurrentVelocity[1] = 0.0;
    if (m_pcDrive) m_pcDrive->reset();
  }

 private:
  CComposableEntity* m_pcRobot = nullptr;
  CWheeledEntity* m_pcWheeledEntity = nullptr;
  std::shared_ptr<epuck2::argos_plugin::CalibratedDrive> m_pcDrive;
  Real m_fCommand[2] = {0.0, 0.0};
};

REGISTER_ACTUATOR(CEPuck2CalibratedDifferentialSteeringActuator, "differential_steering", "calibrated", "epuck2-fit",
                  "1.0", "The E-Puck2's wheels as the robot's wheels turn, from a drive file fitted by epuck2-fit.",
                  "Same control interface as the default implementation (SetLinearVelocity in cm/s).\n"
                  "The wheels: the command capped at the firmware's 1100 steps/s over the file's\n"
                  "steps_per_m (or at a diagnosis's " + DriveEffectName(fx::drive::speed_limit) + "), reached at the diagnosis's\n" +
                  DriveEffectName(fx::drive::accel_limit) + "; the body moves " + DriveEffectName(fx::drive::speed_scale) +
                  "'s k times the wheels, lagging them by\n"
                  "slip_time_constant_s (" + DriveEffectName(fx::drive::wheel_slip) + "). The robot's calibrated encoders count the\n"
                  "wheels' travel, its calibrated ToF reads the body's distance. An effect ARGoS\n"
                  "cannot apply (a covariate, an effect of another kind, one neither the wheels nor\n"
                  "the ToF run) stops ARGoS at Init.\n\n"
                  "  <differential_steering implementation=\"calibrated\" coefficients=\"drive.json\"\n"
                  "                         robot=\"ID|auto\" robot_map=\"ep*:robot1\"\n"
                  "                         firmware_cap=\"true\" />\n\n"
                  "firmware_cap=\"false\": no firmware cap (a diagnosis's " + DriveEffectName(fx::drive::speed_limit) +
                  " still applies).\n"
                  "robot: the file's robots.ID set; \"auto\": each robot's own set, named like its\n"
                  "entity id or by robot_map (PATTERN:ID pairs, * any run of characters).",
                  "Usable");

}  // namespace argos
