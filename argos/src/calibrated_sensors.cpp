#include "calibrated_sensors.hpp"
#include <epuck2/models/effects.hpp>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <string>

#include <argos3/core/simulator/entity/composable_entity.h>
#include <argos3/core/simulator/entity/controllable_entity.h>
#include <argos3/core/simulator/entity/embodied_entity.h>
#include <argos3/core/simulator/entity/floor_entity.h>
#include <argos3/core/simulator/simulator.h>
#include <argos3/core/simulator/space/positional_indices/positional_index.h>
#include <argos3/core/utility/string_utilities.h>
#include <argos3/plugins/robots/e-puck2/simulator/epuck2_camera_equipped_entity.h>
#include <argos3/plugins/robots/e-puck2/simulator/epuck2_encoder_equipped_entity.h>
#include <argos3/plugins/robots/e-puck2/simulator/epuck2_tof_equipped_entity.h>
#include <argos3/plugins/simulator/entities/ground_sensor_equipped_entity.h>
#include <argos3/plugins/simulator/entities/led_entity.h>
#include <argos3/plugins/simulator/entities/light_entity.h>
#include <argos3/plugins/simulator/entities/light_sensor_equipped_entity.h>
#include <argos3/plugins/simulator/entities/proximity_sensor_equipped_entity.h>

#include "coefficient_file.hpp"

#include <epuck2/coefficients/model_file.hpp>

namespace argos {

namespace ms = epuck2::models::sensors;
using epuck2::argos_plugin::ArgosNoise;
using epuck2::argos_plugin::CoefficientFile;

namespace {

/// A warning on ARGoS's error log, once per process for each text (50 robots: one line).
void WarnOnce(const std::string& str_text) {
  static std::mutex cMutex;
  static std::set<std::string> setSaid;
  std::lock_guard<std::mutex> cLock(cMutex);
  if (!setSaid.insert(str_text).second) return;
  LOGERR << "[WARNING] " << str_text << std::endl;
  LOGERR.Flush();
}

/// What every calibrated sensor reads from its XML node: the coefficient file (loaded, with the
/// robot's set when `robot` is given), whether noise is on, its distribution and the uniform
/// noise level.
struct SCommon {
  std::string Sensor;
  std::string Robot;  ///< the file's robot set this robot uses (empty: the top level)
  std::optional<CoefficientFile> File;
  bool Noise = true;
  bool Uniform = false;  ///< noise_distribution="uniform"
  Real NoiseLevel = 0.0;
  bool NoiseLevelGiven = false;
};

SCommon ReadCommon(TConfigurationNode& t_tree, const std::string& str_sensor,
                   const std::vector<std::string>& vec_kinds, const CEntity& c_component) {
  SCommon s;
  s.Sensor = str_sensor;
  std::string strFile, strRobot, strRobotMap, strDistribution = "gaussian";
  GetNodeAttributeOrDefault(t_tree, "coefficients", strFile, strFile);
  if (strFile.empty())
    THROW_ARGOSEXCEPTION("calibrated " << str_sensor
                                       << ": the attribute 'coefficients' is required (a coefficient file written by epuck2-fit)");
  ExpandEnvVariables(strFile);
  GetNodeAttributeOrDefault(t_tree, "robot", strRobot, strRobot);
  GetNodeAttributeOrDefault(t_tree, "robot_map", strRobotMap, strRobotMap);
  GetNodeAttributeOrDefault(t_tree, "noise", s.Noise, s.Noise);
  GetNodeAttributeOrDefault(t_tree, "noise_distribution", strDistribution, strDistribution);
  if (strDistribution != "gaussian" && strDistribution != "uniform")
    THROW_ARGOSEXCEPTION("calibrated " << str_sensor << ": noise_distribution must be 'gaussian' or 'uniform', not '"
                                       << strDistribution << "'");
  s.Uniform = strDistribution == "uniform";
  s.NoiseLevelGiven = NodeAttributeExists(t_tree, "noise_level");
  GetNodeAttributeOrDefault(t_tree, "noise_level", s.NoiseLevel, s.NoiseLevel);
  if (s.NoiseLevel < 0) THROW_ARGOSEXCEPTION("calibrated " << str_sensor << ": noise_level must not be negative");
  const std::string strPath =
      epuck2::argos_plugin::resolve_coefficient_path(strFile, CSimulator::GetInstance().GetExperimentFileName());
  try {
    /* robot="auto": this robot's own set, by its entity id or robot_map */
    const auto sChoice = epuck2::argos_plugin::choose_robot(*epuck2::argos_plugin::parse_coefficient_file(strPath), strPath,
                                                            strRobot, strRobotMap, c_component.GetRootEntity().GetId());
    if (!sChoice.warning.empty()) WarnOnce("calibrated " + str_sensor + ": " + sChoice.warning);
    s.Robot = sChoice.robot;
    s.File = CoefficientFile::load(strPath, vec_kinds, s.Robot);
  } catch (const std::exception& ex) {
    THROW_ARGOSEXCEPTION("calibrated " << str_sensor << ": " << ex.what());
  }
  return s;
}

/// A sensor's noise: with noise="true", the file's measured reading noise noise.<channel> (sd in
/// `str_unit`, per sensor where the file has per_sensor_sd), as a Gaussian of that sd, or with
/// noise_distribution="uniform" as the plug-in's uniform noise of the same variance (level
/// sqrt(3) sd / scale). A file without a noise section: the plug-in's uniform noise of
/// noise_level, with a warning. `f_scale` is the model's factor from a unit noise to `str_unit`.
void ConfigureNoise(const SCommon& s, const std::string& str_channel, const std::string& str_unit, std::size_t un_sensors,
                    double f_scale, ArgosNoise& c_noise) {
  if (!s.Noise) {
    c_noise.off(un_sensors);
    return;
  }
  const std::optional<epuck2::argos_plugin::ReadingNoise> sNoise = s.File->noise(str_channel, str_unit, un_sensors);
  if (!sNoise) {
    std::ostringstream os;
    os << "calibrated " << s.Sensor << ": " << s.File->path()
       << " has no 'noise' section (a file written before epuck2-fit measured the reading noise): using the "
          "plug-in's uniform noise of noise_level = "
       << s.NoiseLevel << (s.NoiseLevel == 0 ? " (none)" : "") << "; fit the logs again to get the measured noise";
    WarnOnce(os.str());
    c_noise.uniform(std::vector<double>(un_sensors, s.NoiseLevel));
    return;
  }
  if (s.NoiseLevelGiven)
    WarnOnce("calibrated " + s.Sensor + ": noise_level is ignored: " + s.File->path() +
             " gives the measured reading noise (noise." + str_channel + "); noise=\"false\" turns noise off");
  const std::vector<double> vecSd = sNoise->sd_per_sensor(un_sensors);
  if (s.Uniform) {
    std::vector<double> vecLevel;
    for (double fSd : vecSd) vecLevel.push_back(ms::uniform_level_with_sd(fSd, f_scale));
    c_noise.uniform(vecLevel);
  } else {
    c_noise.gaussian(vecSd, f_scale);
  }
}

/// Runs `f` and turns a coefficient-file error into an ARGoS exception naming the sensor.
template <class F>
void Checked(const std::string& str_sensor, F&& f) {
  try {
    f();
  } catch (const CARGoSException&) {
    throw;
  } catch (const std::exception& ex) {
    THROW_ARGOSEXCEPTION("calibrated " << str_sensor << ": " << ex.what());
  }
}

/// A file's effects that this sensor does not apply yet (proximity, light, ground, camera: issue
/// #20's model-type sensors wait for the project's one coefficient reader): ARGoS stops at Init
/// naming them, rather than dropping them (a diagnosis's base curve was fitted together with
/// them and reads wrong without them).
void RefuseEffects(const SCommon& s) {
  const nlohmann::json& e = s.File->effects();
  if (e.empty()) return;
  std::string strNames;
  for (auto it = e.begin(); it != e.end(); ++it) strNames += (strNames.empty() ? "" : ", ") + std::string("effects.") + it.key();
  THROW_ARGOSEXCEPTION("calibrated " << s.Sensor << ": " << s.File->path() << ": " << strNames
                                     << ": the calibrated " << s.Sensor
                                     << " does not apply a diagnosis's effects yet, and its base was fitted together "
                                        "with them (docs/argos.md): use a calibration file (epuck2-fit KIND -o), or the "
                                        "extended model through the generated header in your own sensor");
}

/// The plug-in's encoder noise scale: a unit noise is 32767 steps.
constexpr double kEncoderNoiseScale = ms::kPluginNoiseScaleEncoder_steps;

/// The ray of a ray-casting sensor (proximity, ToF) in world coordinates.
template <class SENSOR>
CRay3 WorldRay(const SENSOR& s_sensor) {
  CVector3 cStart = s_sensor.Offset;
  cStart.Rotate(s_sensor.Anchor.Orientation);
  cStart += s_sensor.Anchor.Position;
  CVector3 cEnd = s_sensor.Offset;
  cEnd += s_sensor.Direction;
  cEnd.Rotate(s_sensor.Anchor.Orientation);
  cEnd += s_sensor.Anchor.Position;
  return CRay3(cStart, cEnd);
}

}  // namespace

/****************************************/
/* Proximity                            */
/****************************************/

void CEPuck2CalibratedProximitySensor::Init(TConfigurationNode& t_tree) {
  const std::string strName = "epuck2_proximity";
  CEPuck2ProximityDefaultSensor::Init(t_tree);
  SCommon s = ReadCommon(t_tree, strName, {"proximity"}, *m_pcProximityEntity);
  RefuseEffects(s);
  std::string strCurve = "max";
  GetNodeAttributeOrDefault(t_tree, "curve", strCurve, strCurve);
  if (strCurve != "max" && strCurve != "mean")
    THROW_ARGOSEXCEPTION("calibrated " << strName << ": curve must be 'max' (Eq. 1 fitted to the maxima) or 'mean'");
  const std::string strPrefix = strCurve == "mean" ? "mean_" : "";
  Checked(strName, [&] {
    const std::size_t n = m_tReadings.size();
    const auto a = s.File->per_sensor(strPrefix + "a", n), b = s.File->per_sensor(strPrefix + "b", n),
               c = s.File->per_sensor(strPrefix + "c", n);
    const double fRange = s.File->scalar_or("range_m", ms::kPluginProximity.range_m);
    m_vecCoefficients.resize(n);
    for (std::size_t i = 0; i < n; ++i) m_vecCoefficients[i] = ms::ProximityCoefficients{a[i], b[i], c[i], fRange};
    /* The model adds the noise to the normalised response, then multiplies by 4095 counts */
    ConfigureNoise(s, "proximity", "counts", n, ms::kPluginNoiseScaleProximity_counts, m_cNoise);
  });
  m_bAddNoise = false;
}

Real CEPuck2CalibratedProximitySensor::CalculateReading(Real f_distance) {
  return m_vecCoefficients.empty() ? 0.0 : ms::proximity_response(m_vecCoefficients[0], f_distance);
}

void CEPuck2CalibratedProximitySensor::Update() {
  SEmbodiedEntityIntersectionItem sIntersection;
  for (UInt32 i = 0; i < m_tReadings.size(); ++i) {
    CRay3 cRay = WorldRay(m_pcProximityEntity->GetSensor(i));
    std::optional<double> fDistance;
    if (GetClosestEmbodiedEntityIntersectedByRay(sIntersection, cRay, *m_pcEmbodiedEntity)) {
      if (m_bShowRays) {
        m_pcControllableEntity->AddIntersectionPoint(cRay, sIntersection.TOnRay);
        m_pcControllableEntity->AddCheckedRay(true, cRay);
      }
      fDistance = cRay.GetDistance(sIntersection.TOnRay);
    } else if (m_bShowRays) {
      m_pcControllableEntity->AddCheckedRay(false, cRay);
    }
    m_tReadings[i].Value = ms::proximity_reading(m_vecCoefficients[i], fDistance, m_cNoise.level(i), m_cNoise.unit(i));
  }
}

REGISTER_SENSOR(CEPuck2CalibratedProximitySensor, "epuck2_proximity", "calibrated", "epuck2-fit", "1.0",
                "The E-Puck2 proximity sensors with coefficients fitted by epuck2-fit.",
                "Same rays and control interface as the default implementation; the reading is\n"
                "Eq. 1, v = a d^2 + b d + c (clamped to [0, 1], 0 beyond range_m), times 4095,\n"
                "with a, b, c (each a number or an array of 8, one per sensor) from the\n"
                "coefficient file's parameters (or mean_a, mean_b, mean_c with curve=\"mean\").\n\n"
                "  <epuck2_proximity implementation=\"calibrated\" coefficients=\"proximity.json\"\n"
                "                    robot=\"ID\" curve=\"max\" noise=\"true\"\n"
                "                    noise_distribution=\"gaussian\" />\n\n"
                "coefficients: the file (relative: to the .argos file, then the working directory).\n"
                "robot: use the file's robots.ID set.\n"
                "noise (default true): the coefficient file's measured reading noise, noise.proximity\n"
                "(its sd in counts, per sensor from per_sensor_sd), as a Gaussian of that sd drawn from ARGoS's\n"
                "random generator; noise_distribution=\"uniform\": the plug-in's uniform noise of\n"
                "the same variance, level sqrt(3) sd / 4095 (the file's argos_uniform_level).\n"
                "A file without a noise section: the plug-in's uniform noise of noise_level\n"
                "(x 4095), with a warning. noise=\"false\": none.",
                "Usable");

/****************************************/
/* Ground                               */
/****************************************/

void CEPuck2CalibratedGroundSensor::Init(TConfigurationNode& t_tree) {
  const std::string strName = "epuck2_ground";
  CEPuck2GroundRotZOnlySensor::Init(t_tree);
  SCommon s = ReadCommon(t_tree, strName, {"ground"}, *m_pcGroundSensorEntity);
  Checked(strName, [&] {
    /* The project's one reader (lib/coefficients): each sensor's gain and offset, a diagnosis's
       nonlinear_response; ARGoS cannot apply a covariate */
    m_sModel = epuck2::coefficients::ground_model_from_json(s.File->root(), s.File->path(), s.Robot);
    if (!m_sModel.covariates.empty())
      s.File->fail("effects.covariate:" + m_sModel.covariates.front().column +
                   ": the calibrated epuck2_ground cannot apply it in ARGoS: it needs the log column '" +
                   m_sModel.covariates.front().column + "', which ARGoS does not have");
    if (m_tReadings.size() != m_sModel.sensors.size())
      s.File->fail("the robot has " + std::to_string(m_tReadings.size()) + " ground sensors, the model " +
                   std::to_string(m_sModel.sensors.size()));
    /* The model scales a unit noise by the full scale, 1023 counts */
    ConfigureNoise(s, "ground", "counts", m_tReadings.size(), ms::kPluginNoiseScaleGround_counts, m_cNoise);
  });
  m_bAddNoise = false;
}

void CEPuck2CalibratedGroundSensor::Update() {
  CRadians cRotZ, cRotY, cRotX;
  CVector2 cCenterPos, cSensorPos;
  for (UInt32 i = 0; i < m_tReadings.size(); ++i) {
    CGroundSensorEquippedEntity::SSensor& sSens = m_pcGroundSensorEntity->GetSensor(i);
    cCenterPos.Set(sSens.Anchor.Position.GetX(), sSens.Anchor.Position.GetY());
    sSens.Anchor.Orientation.ToEulerAngles(cRotZ, cRotY, cRotX);
    cSensorPos = sSens.Offset;
    cSensorPos.Rotate(cRotZ);
    cSensorPos += cCenterPos;
    const CColor& cColor = m_pcFloorEntity->GetColorAtPoint(cSensorPos.GetX(), cSensorPos.GetY());
    /* grey in [0, 1], 0 = black */
    const double fGrey = cColor.ToGrayScale() / 255.0;
    /* lib/models' mean (the nonlinear response included), the noise, the rounding and the rails */
    const double fMean = ms::mean_raw(m_sModel, static_cast<int>(i), fGrey) +
                         ms::uniform_noise(m_cNoise.unit(i), m_cNoise.level(i)) * ms::kPluginNoiseScaleGround_counts;
    m_tReadings[i] = static_cast<SInt32>(std::clamp(std::round(fMean), 0.0, ms::kGroundFullScale_raw));
  }
}

REGISTER_SENSOR(CEPuck2CalibratedGroundSensor, "epuck2_ground", "calibrated", "epuck2-fit", "1.0",
                "The E-Puck2 ground sensors with coefficients fitted by epuck2-fit.",
                "Same control interface and floor sampling as the rot_z_only implementation; the\n"
                "reading is offset + gain * grey^exponent (grey in [0, 1], 0 = black), rounded and\n"
                "clamped to [0, 1023], with gain and offset (arrays of 3: right, centre, left) and a\n"
                "diagnosis's nonlinear_response exponent (1 without) from the coefficient file.\n\n"
                "  <epuck2_ground implementation=\"calibrated\" coefficients=\"ground.json\"\n"
                "                 robot=\"ID\" noise=\"true\" noise_distribution=\"gaussian\" />\n\n"
                "noise (default true): the coefficient file's measured reading noise, noise.ground\n"
                "(its sd in counts, per sensor from per_sensor_sd), as a Gaussian of that sd drawn from ARGoS's\n"
                "random generator; noise_distribution=\"uniform\": the plug-in's uniform noise of\n"
                "the same variance, level sqrt(3) sd / 1023 (the file's argos_uniform_level).\n"
                "A file without a noise section: the plug-in's uniform noise of noise_level\n"
                "(x 1023), with a warning. noise=\"false\": none.",
                "Usable");

/****************************************/
/* Time of flight                       */
/****************************************/

void CEPuck2CalibratedTOFSensor::SetRobot(CComposableEntity& c_entity) {
  m_pcRobot = &c_entity;
  CEPuck2TOFDefaultSensor::SetRobot(c_entity);
}

void CEPuck2CalibratedTOFSensor::Init(TConfigurationNode& t_tree) {
  const std::string strName = "epuck2_tof";
  CEPuck2TOFDefaultSensor::Init(t_tree);
  SCommon s = ReadCommon(t_tree, strName, {"drive", "tof"}, *m_pcTOFEntity);
  Checked(strName, [&] {
    const auto sDrive = epuck2::argos_plugin::read_drive_config(*s.File, "the calibrated " + strName);
    m_sCoefficients.scale = sDrive.effects.tof_scale.k;
    m_sCoefficients.offset_mm = sDrive.effects.tof_offset.offset_mm;
    m_cDelay = epuck2::argos_plugin::DelayLine(sDrive.effects.latency.delay_s);
    m_sCoefficients.range_m = m_pcTOFEntity->GetSensor(0).Direction.Length();
    /* The model scales a unit noise by the range, in mm */
    ConfigureNoise(s, "tof", "mm", 1, m_sCoefficients.range_m * 1000.0, m_cNoise);
    const bool bDriveEffects = !s.File->effects().empty() || sDrive.effects.slip.tau_s > 0;
    if (bDriveEffects && !epuck2::argos_plugin::DriveRegistry::find(m_pcRobot))
      WarnOnce("calibrated " + strName + ": " + s.File->path() +
               ": the robot's differential_steering is not implementation=\"calibrated\": the file's speed limit, "
               "slip and other drive effects do not move the body, only the ToF's own (scale, offset, latency) apply");
  });
  m_bAddNoise = false;
  Reset();
}

void CEPuck2CalibratedTOFSensor::Reset() {
  m_cDelay.reset();
  m_fTime = 0;
}

void CEPuck2CalibratedTOFSensor::Update() {
  SEmbodiedEntityIntersectionItem sIntersection;
  CRay3 cRay = WorldRay(m_pcTOFEntity->GetSensor(0));
  std::optional<double> fDistance;
  if (GetClosestEmbodiedEntityIntersectedByRay(sIntersection, cRay, *m_pcEmbodiedEntity)) {
    if (m_bShowRays) {
      m_pcControllableEntity->AddIntersectionPoint(cRay, sIntersection.TOnRay);
      m_pcControllableEntity->AddCheckedRay(true, cRay);
    }
    fDistance = cRay.GetDistance(sIntersection.TOnRay);
  } else if (m_bShowRays) {
    m_pcControllableEntity->AddCheckedRay(false, cRay);
  }
  /* latency: the distance delay_s ago */
  m_fTime += CPhysicsEngine::GetSimulationClockTick();
  fDistance = m_cDelay.push_and_read(m_fTime, fDistance);
  m_iReading = ms::tof_reading_mm(m_sCoefficients, fDistance, m_cNoise.level(0), m_cNoise.unit(0));
}

REGISTER_SENSOR(CEPuck2CalibratedTOFSensor, "epuck2_tof", "calibrated", "epuck2-fit", "1.0",
                "The E-Puck2 time-of-flight sensor with coefficients fitted by epuck2-fit.",
                "Same ray and control interface as the default implementation; the reading is\n"
                "tof_scale * distance + tof_offset_mm in mm, rounded and clamped to [20, 2000],\n"
                "with tof_scale and tof_offset_mm from a drive coefficient file, the distance\n"
                "being the one latency's delay_s ago (a diagnosis's effects.latency).\n\n"
                "  <epuck2_tof implementation=\"calibrated\" coefficients=\"drive.json\"\n"
                "              robot=\"ID\" noise=\"true\" noise_distribution=\"gaussian\" />\n\n"
                "noise (default true): the coefficient file's measured reading noise, noise.tof\n"
                "(its sd in mm), as a Gaussian of that sd drawn from ARGoS's\n"
                "random generator; noise_distribution=\"uniform\": the plug-in's uniform noise of\n"
                "the same variance, level sqrt(3) sd / 2000 mm (the range) (the file's argos_uniform_level).\n"
                "A file without a noise section: the plug-in's uniform noise of noise_level\n"
                "(x 2000 mm (the range)), with a warning. noise=\"false\": none.",
                "Usable");

/****************************************/
/* Encoders                             */
/****************************************/

void CEPuck2CalibratedEncoderSensor::SetRobot(CComposableEntity& c_entity) {
  m_pcRobot = &c_entity;
  CEPuck2EncoderDefaultSensor::SetRobot(c_entity);
}

void CEPuck2CalibratedEncoderSensor::Init(TConfigurationNode& t_tree) {
  const std::string strName = "epuck2_encoder";
  CEPuck2EncoderDefaultSensor::Init(t_tree);
  SCommon s = ReadCommon(t_tree, strName, {"drive", "encoder"}, *m_pcEncoderEntity);
  Checked(strName, [&] {
    const auto sDrive = epuck2::argos_plugin::read_drive_config(*s.File, "the calibrated " + strName);
    m_sCoefficients.steps_per_m = sDrive.steps_per_m;
    /* The model scales a unit noise by 32767 steps; one channel per wheel */
    ConfigureNoise(s, "encoder", "steps", 2, kEncoderNoiseScale, m_cNoise);
  });
  /* ARGoS sets up a controller's actuators before its sensors: the calibrated actuator's drive is
     there by now, if the robot has one */
  m_pcDrive = epuck2::argos_plugin::DriveRegistry::find(m_pcRobot);
  if (!m_pcDrive)
    WarnOnce("calibrated " + strName + ": " + s.File->path() +
             ": the robot's differential_steering is not implementation=\"calibrated\": the encoders count the "
             "wheels as the plug-in turns them (the command, uncapped), not as the file's drive does");
  m_bAddNoise = false;
  Reset();
}

void CEPuck2CalibratedEncoderSensor::Reset() {
  m_cLeft = epuck2::models::sensors::Encoder(m_sCoefficients);
  m_cRight = epuck2::models::sensors::Encoder(m_sCoefficients);
  m_cLeftRegister = epuck2::argos_plugin::StepRegister(m_sCoefficients.steps_per_m);
  m_cRightRegister = epuck2::argos_plugin::StepRegister(m_sCoefficients.steps_per_m);
  m_fLeftTravel = m_fRightTravel = 0;
  m_tReadings.EncoderLeftWheel = 0;
  m_tReadings.EncoderRightWheel = 0;
}

void CEPuck2CalibratedEncoderSensor::Update() {
  if (m_pcEncoderEntity->GetNumSensors() == 0) {
    Reset();
    return;
  }
  const Real fDeltaT = CPhysicsEngine::GetSimulationClockTick();
  /* Each wheel's travel: the calibrated actuator's wheels, else the wheeled entity's speeds */
  const Real fLeftBefore = m_fLeftTravel, fRightBefore = m_fRightTravel;
  if (m_pcDrive) {
    m_fLeftTravel = m_pcDrive->state().xl;
    m_fRightTravel = m_pcDrive->state().xr;
  } else {
    CEPuck2EncoderEquippedEntity::SSensor& sSens = m_pcEncoderEntity->GetSensor(0);
    m_fLeftTravel += sSens.Wheels.GetWheelVelocity(0) * fDeltaT;
    m_fRightTravel += sSens.Wheels.GetWheelVelocity(1) * fDeltaT;
  }
  if (m_cNoise.gaussian() || !m_cNoise.any()) {
    /* The measured noise is the spread of a reading about the travel: added to the reading, drawn
       only when the count moved (a register standing still reads what it read) */
    auto read = [&](epuck2::argos_plugin::StepRegister& r, Real f_travel, std::size_t i) {
      const double fNoise =
          r.moved(f_travel) ? ms::uniform_noise(m_cNoise.unit(i), m_cNoise.level(i)) * kEncoderNoiseScale : 0.0;
      return r.read(f_travel, fNoise);
    };
    m_tReadings.EncoderLeftWheel = read(m_cLeftRegister, m_fLeftTravel, 0);
    m_tReadings.EncoderRightWheel = read(m_cRightRegister, m_fRightTravel, 1);
    return;
  }
  /* The plug-in's noise: added to the count every tick the wheel turns (it accumulates); a wheel
     standing still adds nothing */
  const bool bLeft = m_fLeftTravel != fLeftBefore, bRight = m_fRightTravel != fRightBefore;
  m_cLeft.tick((m_fLeftTravel - fLeftBefore) / fDeltaT, fDeltaT, bLeft ? m_cNoise.level(0) : 0.0, m_cNoise.unit(0));
  m_cRight.tick((m_fRightTravel - fRightBefore) / fDeltaT, fDeltaT, bRight ? m_cNoise.level(1) : 0.0, m_cNoise.unit(1));
  m_tReadings.EncoderLeftWheel = m_cLeft.reading();
  m_tReadings.EncoderRightWheel = m_cRight.reading();
}

REGISTER_SENSOR(CEPuck2CalibratedEncoderSensor, "epuck2_encoder", "calibrated", "epuck2-fit", "1.0",
                "The E-Puck2 wheel encoders with coefficients fitted by epuck2-fit.",
                "Same control interface as the default implementation; each wheel's register\n"
                "counts floor(steps_per_m * the wheel's travel) (int16 wrap), with steps_per_m\n"
                "from a drive coefficient file. With the calibrated differential_steering\n"
                "actuator the travel is its wheels' (capped, accelerated, not the lagging body).\n\n"
                "  <epuck2_encoder implementation=\"calibrated\" coefficients=\"drive.json\"\n"
                "                  robot=\"ID\" noise=\"true\" noise_distribution=\"gaussian\" />\n\n"
                "noise (default true): the coefficient file's measured reading noise, noise.encoder\n"
                "(its sd in steps), as a Gaussian of that sd drawn from ARGoS's\n"
                "random generator; noise_distribution=\"uniform\": the plug-in's uniform noise of\n"
                "the same variance, level sqrt(3) sd / 32767 (the file's argos_uniform_level).\n"
                "A file without a noise section: the plug-in's uniform noise of noise_level\n"
                "(x 32767), with a warning. noise=\"false\": none.\n"
                "The Gaussian is added to each reading (the count stays noiseless: a step\n"
                "counter does not drift), drawn only when the count moved: a register standing\n"
                "still reads exactly what it read; the uniform noise, as in the plug-in, to the count\n"
                "every tick the wheel turns, where it accumulates (after k ticks its sd is sqrt(k)\n"
                "times the file's).",
                "Usable");

/****************************************/
/* Ambient light                        */
/****************************************/

void CEPuck2CalibratedLightSensor::Init(TConfigurationNode& t_tree) {
  const std::string strName = "epuck2_light";
  CEPuck2LightDefaultSensor::Init(t_tree);
  SCommon s = ReadCommon(t_tree, strName, {"light"}, *m_pcLightEntity);
  RefuseEffects(s);
  Checked(strName, [&] {
    const std::size_t n = m_tReadings.size();
    const auto gamma = s.File->per_sensor("gamma", n);
    m_vecCoefficients.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      m_vecCoefficients[i].gamma_m = gamma[i];
      m_vecCoefficients[i].range_m = m_pcLightEntity->GetSensor(i).Direction.Length();
    }
    /* Per-sensor fits (light.json's per_sensor list) replace the common gamma; a robot's set
       has them in robots.ID.per_sensor */
    nlohmann::json jPer = s.File->root().value("per_sensor", nlohmann::json::array());
    if (!s.Robot.empty() && s.File->root().contains("robots"))
      jPer = s.File->root().at("robots").at(s.Robot).value("per_sensor", jPer);
    for (const auto& e : jPer) {
      if (!e.is_object() || !e.contains("sensor") || !e.contains("gamma") || !e.at("sensor").is_number_integer() ||
          !e.at("gamma").is_number())
        throw std::runtime_error(s.File->path() + ": per_sensor entries need an integer 'sensor' and a number 'gamma'");
      const int i = e.at("sensor").get<int>();
      if (i < 0 || static_cast<std::size_t>(i) >= n)
        throw std::runtime_error(s.File->path() + ": per_sensor: no sensor " + std::to_string(i));
      m_vecCoefficients[i].gamma_m = e.at("gamma").get<double>();
    }
    /* The model adds the noise to the normalised sum, then multiplies by 4095 counts */
    ConfigureNoise(s, "light", "counts", n, ms::kPluginNoiseScaleLight_counts, m_cNoise);
  });
  m_bAddNoise = false;
}

void CEPuck2CalibratedLightSensor::Update() {
  SEmbodiedEntityIntersectionItem sIntersection;
  std::vector<ms::LightSource> vecLights;
  CSpace::TMapPerTypePerId::iterator itLights = m_cSpace.GetEntityMapPerTypePerId().find("light");
  for (UInt32 i = 0; i < m_tReadings.size(); ++i) {
    vecLights.clear();
    CVector3 cRayStart = m_pcLightEntity->GetSensor(i).Position;
    cRayStart.Rotate(m_pcLightEntity->GetSensor(i).Anchor.Orientation);
    cRayStart += m_pcLightEntity->GetSensor(i).Anchor.Position;
    if (itLights != m_cSpace.GetEntityMapPerTypePerId().end()) {
      for (auto& tLight : itLights->second) {
        CLightEntity& cLight = *any_cast<CLightEntity*>(tLight.second);
        if (cLight.GetIntensity() <= 0.0) continue;
        CRay3 cRay(cRayStart, cLight.GetPosition());
        if (cRay.GetLength() > m_vecCoefficients[i].range_m) continue;
        if (GetClosestEmbodiedEntityIntersectedByRay(sIntersection, cRay)) {
          if (m_bShowRays) {
            m_pcControllableEntity->AddIntersectionPoint(cRay, sIntersection.TOnRay);
            m_pcControllableEntity->AddCheckedRay(true, cRay);
          }
          continue;
        }
        if (m_bShowRays) m_pcControllableEntity->AddCheckedRay(false, cRay);
        vecLights.push_back(ms::LightSource{cRay.GetLength(), cLight.GetIntensity()});
      }
    }
    m_tReadings[i].Value = ms::light_reading(m_vecCoefficients[i], vecLights, m_cNoise.level(i), m_cNoise.unit(i));
  }
}

REGISTER_SENSOR(CEPuck2CalibratedLightSensor, "epuck2_light", "calibrated", "epuck2-fit", "1.0",
                "The E-Puck2 ambient light sensors with coefficients fitted by epuck2-fit.",
                "Same rays, occlusions and control interface as the default implementation; the\n"
                "reading is (1 - sum over visible lights of (gamma I / d)^2) x 4095, rounded and\n"
                "clamped, with gamma from the coefficient file (per_sensor entries override it).\n\n"
                "  <epuck2_light implementation=\"calibrated\" coefficients=\"light.json\"\n"
                "                robot=\"ID\" noise=\"true\" noise_distribution=\"gaussian\" />\n\n"
                "noise (default true): the coefficient file's measured reading noise, noise.light\n"
                "(its sd in counts, per sensor from per_sensor_sd), as a Gaussian of that sd drawn from ARGoS's\n"
                "random generator; noise_distribution=\"uniform\": the plug-in's uniform noise of\n"
                "the same variance, level sqrt(3) sd / 4095 (the file's argos_uniform_level).\n"
                "A file without a noise section: the plug-in's uniform noise of noise_level\n"
                "(x 4095), with a warning. noise=\"false\": none.",
                "Usable");

/****************************************/
/* Camera                               */
/****************************************/

void CEPuck2CalibratedCameraSensor::Init(TConfigurationNode& t_tree) {
  const std::string strName = "epuck2_colored_blob_perspective_camera";
  SCommon s = ReadCommon(t_tree, strName, {"camera"}, *m_pcCamEntity);
  Checked(strName, [&] {
    /* The project's one reader (lib/coefficients): the field of view, the centre, the radial
       distortion (k1, k2, k3), every value checked; ARGoS cannot apply a covariate */
    m_sModel = epuck2::coefficients::camera_model_from_json(s.File->root(), s.File->path(), s.Robot);
    if (!m_sModel.covariates.empty())
      s.File->fail("effects.covariate:" + m_sModel.covariates.front().column +
                   ": the calibrated camera cannot apply it in ARGoS: it needs the log column '" +
                   m_sModel.covariates.front().column + "', which ARGoS does not have");
    const double fW = m_pcCamEntity->GetImagePxWidth(), fH = m_pcCamEntity->GetImagePxHeight();
    m_sModel.base.width_px = fW;
    /* Which LEDs it sees: the cone of the fitted field of view's aperture (ARGoS's, the half-angle
       on the image diagonal) and the range, as the plug-in's camera */
    m_fAperture = ms::aperture_from_horizontal_fov_rad(m_sModel.base.horizontal_fov_rad, static_cast<int>(fW),
                                                       static_cast<int>(fH));
    m_fRange = s.File->scalar_or("range_m", m_pcCamEntity->GetRange());
    m_pcCamEntity->SetAperture(CRadians(m_fAperture));
    m_pcCamEntity->SetRange(m_fRange);
    m_pcCamEntity->SetImagePxSize(static_cast<SInt32>(fW), static_cast<SInt32>(fH));
    /* The pixel noise (noise.camera, px), each axis; scale 1: the noise is in pixels */
    ConfigureNoise(s, "camera", "px", 2, 1.0, m_cNoise);
  });
  CEPuck2ColoredBlobPerspectiveCameraDefaultSensor::Init(t_tree);
}

namespace {

/// The LEDs the calibrated camera sees in one frame, projected with lib/models' camera model.
class CCalibratedCameraLEDs : public CPositionalIndex<CLEDEntity>::COperation {
 public:
  CCalibratedCameraLEDs(CEPuck2CameraEquippedEntity& c_cam, CEmbodiedEntity& c_body, const ms::CameraModel& s_model,
                        Real f_aperture, Real f_range, ArgosNoise& c_noise,
                        CCI_ColoredBlobPerspectiveCameraSensor::TBlobList& t_blobs)
      : m_cCam(c_cam), m_cBody(c_body), m_sModel(s_model), m_fAperture(f_aperture), m_fRange(f_range), m_cNoise(c_noise),
        m_tBlobs(t_blobs), m_cInverse(c_cam.GetOrientation().Inverse()) {
    m_cRay.SetStart(c_cam.GetPosition());
  }
  bool operator()(CLEDEntity& c_led) override {
    if (c_led.GetColor() == CColor::BLACK || &c_led.GetRootEntity() == &m_cBody.GetRootEntity()) return true;
    CVector3 cRel = c_led.GetPosition() - m_cCam.GetPosition();
    cRel.Rotate(m_cInverse);  // X forward, Y left, Z up
    if (!ms::camera_sees(m_fAperture, m_fRange, cRel.GetX(), cRel.GetY(), cRel.GetZ())) return true;
    m_cRay.SetEnd(c_led.GetPosition());
    SEmbodiedEntityIntersectionItem sItem;
    if (GetClosestEmbodiedEntityIntersectedByRay(sItem, m_cRay, m_cBody)) return true;
    /* The sub-pixel image position, the noise, then the rounding (lib/models' reading) */
    const auto p = ms::mean_px(m_sModel, cRel.GetX(), cRel.GetY(), cRel.GetZ());
    const double fX = std::round(p[0] + ms::uniform_noise(m_cNoise.unit(0), m_cNoise.level(0)));
    const double fY = std::round(p[1] + ms::uniform_noise(m_cNoise.unit(1), m_cNoise.level(1)));
    if (fX < 0 || fY < 0 || fX >= m_cCam.GetImagePxWidth() || fY >= m_cCam.GetImagePxHeight()) return true;
    m_tBlobs.push_back(new CCI_ColoredBlobPerspectiveCameraSensor::SBlob(c_led.GetColor(), static_cast<SInt32>(fX),
                                                                         static_cast<SInt32>(fY)));
    return true;
  }

 private:
  CEPuck2CameraEquippedEntity& m_cCam;
  CEmbodiedEntity& m_cBody;
  const ms::CameraModel& m_sModel;
  Real m_fAperture, m_fRange;
  ArgosNoise& m_cNoise;
  CCI_ColoredBlobPerspectiveCameraSensor::TBlobList& m_tBlobs;
  CQuaternion m_cInverse;
  CRay3 m_cRay;
};

}  // namespace

void CEPuck2CalibratedCameraSensor::Update() {
  if (IsDisabled()) return;
  ++m_sReadings.Counter;
  auto& tBlobs = m_sReadings.BlobList;
  while (!tBlobs.empty()) {
    delete tBlobs.back();
    tBlobs.pop_back();
  }
  /* The plug-in's search box: half the range ahead, as wide as the aperture there */
  const Real fHalfRange = m_fRange * 0.5;
  const Real fHalfSide = fHalfRange * std::tan(m_fAperture);
  CVector3 cCenter(fHalfRange, 0.0, 0.0);
  cCenter.Rotate(m_pcCamEntity->GetOrientation());
  cCenter += m_pcCamEntity->GetPosition();
  CVector3 cCorner(fHalfRange, fHalfSide, fHalfSide);
  cCorner.Rotate(m_pcCamEntity->GetOrientation());
  const CVector3 cHalf(Abs(cCorner.GetX()) + fHalfSide, Abs(cCorner.GetY()) + fHalfSide, Abs(cCorner.GetZ()) + fHalfSide);
  CCalibratedCameraLEDs cOp(*m_pcCamEntity, *m_pcEmbodiedEntity, m_sModel, m_fAperture, m_fRange, m_cNoise, tBlobs);
  m_pcLEDIndex->ForEntitiesInBoxRange(cCenter, cHalf, cOp);
}

REGISTER_SENSOR(CEPuck2CalibratedCameraSensor, "epuck2_colored_blob_perspective_camera", "calibrated", "epuck2-fit",
                "1.0", "The E-Puck2 camera with the project's projection and the coefficients fitted by epuck2-fit.",
                "The LEDs of the LED medium the plug-in's camera would see (cone of the fitted field of\n"
                "view's aperture, range_m, occlusions), each projected with lib/models' camera model:\n"
                "the camera file's horizontal field of view fov_deg, image centre cx_px, cy_px at\n"
                "sub-pixel accuracy, a diagnosis's radial_distortion (k1, k2, k3), and the measured pixel noise\n"
                "noise.camera (Gaussian, each axis), then rounded; blobs off the image are dropped.\n\n"
                "  <epuck2_colored_blob_perspective_camera implementation=\"calibrated\"\n"
                "      coefficients=\"camera.json\" medium=\"leds\" noise=\"true\" robot=\"ID|auto\" />",
                "Usable");

}  // namespace argos
