#include "calibrated_sensors.hpp"
#include "applied_effects.hpp"
#include <epuck2/models/effects.hpp>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <typeinfo>

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
#include <argos3/plugins/simulator/entities/box_entity.h>
#include <argos3/plugins/simulator/entities/cylinder_entity.h>
#include <argos3/plugins/simulator/entities/ground_sensor_equipped_entity.h>
#include <argos3/plugins/simulator/entities/led_entity.h>
#include <argos3/plugins/simulator/entities/light_entity.h>
#include <argos3/plugins/simulator/entities/light_sensor_equipped_entity.h>
#include <argos3/plugins/simulator/entities/proximity_sensor_equipped_entity.h>

#include <epuck2/coefficients/model_file.hpp>
#include <epuck2/coefficients/model_sets.hpp>

namespace argos {

namespace ms = epuck2::models::sensors;
using epuck2::argos_plugin::ArgosNoise;
namespace ec = epuck2::coefficients;
namespace fx = epuck2::models::effects;

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

/// What every calibrated sensor reads from its XML node: the coefficient file (read once per
/// process through lib/coefficients, the project's one reader), the robot set this robot uses,
/// whether noise is on, its distribution and the uniform noise level.
struct SCommon {
  std::string Sensor;
  std::string Path;
  std::string Robot;  ///< the file's robot set this robot uses (empty: the top level)
  std::shared_ptr<const nlohmann::json> Root;
  bool HasNoise = false;  ///< the file has a `noise` section
  bool Noise = true;
  bool Uniform = false;  ///< noise_distribution="uniform"
  Real NoiseLevel = 0.0;
  bool NoiseLevelGiven = false;
  /// An error at `pointer` in the file: FILE:LINE:COLUMN, the JSON path and `what`.
  [[noreturn]] void Fail(const std::string& pointer, const std::string& what) const {
    epuck2::coefficients::fail_in_file(Path, pointer, what);
  }
};

SCommon ReadCommon(TConfigurationNode& t_tree, const std::string& str_sensor, const CEntity& c_component) {
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
  s.Path = ec::resolve_model_path(strFile, CSimulator::GetInstance().GetExperimentFileName());
  try {
    s.Root = ec::shared_json_file(s.Path);
    /* robot="auto": this robot's own set, by its entity id or robot_map */
    const auto sChoice = ec::choose_robot(*s.Root, s.Path, strRobot, strRobotMap, c_component.GetRootEntity().GetId());
    if (!sChoice.warning.empty()) WarnOnce("calibrated " + str_sensor + ": " + sChoice.warning);
    s.Robot = sChoice.robot;
    s.HasNoise = ec::has_noise_section(*s.Root, s.Robot);
  } catch (const std::exception& ex) {
    THROW_ARGOSEXCEPTION("calibrated " << str_sensor << ": " << ex.what());
  }
  return s;
}

/// A sensor's noise: with noise="true", the file's measured reading noise `vec_sd` (per sensor, in
/// the reading's units, as lib/coefficients read and checked it from noise.<channel>), as a
/// Gaussian of that sd, or with noise_distribution="uniform" as the plug-in's uniform noise of the
/// same variance (level sqrt(3) sd / scale). A file without a noise section: the plug-in's uniform
/// noise of noise_level, with a warning. `f_scale` is the model's factor from a unit noise to the
/// reading's units.
void ConfigureNoise(const SCommon& s, const std::string& str_channel, const std::vector<double>& vec_sd, double f_scale,
                    ArgosNoise& c_noise) {
  if (!s.Noise) {
    c_noise.off(vec_sd.size());
    return;
  }
  if (!s.HasNoise) {
    std::ostringstream os;
    os << "calibrated " << s.Sensor << ": " << s.Path
       << " has no 'noise' section (a file written before epuck2-fit measured the reading noise): using the "
          "plug-in's uniform noise of noise_level = "
       << s.NoiseLevel << (s.NoiseLevel == 0 ? " (none)" : "") << "; fit the logs again to get the measured noise";
    WarnOnce(os.str());
    c_noise.uniform(std::vector<double>(vec_sd.size(), s.NoiseLevel));
    return;
  }
  const auto HasChannel = [&](const nlohmann::json& j) {
    return j.is_object() && j.contains("noise") && j.at("noise").is_object() && j.at("noise").contains(str_channel);
  };
  const nlohmann::json* pcRobotSet = nullptr;
  if (!s.Robot.empty()) pcRobotSet = &s.Root->at("robots").at(s.Robot);
  if (!HasChannel(*s.Root) && !(pcRobotSet && HasChannel(*pcRobotSet)))
    WarnOnce("calibrated " + s.Sensor + ": " + s.Path + ": the 'noise' section has no '" + str_channel +
             "' entry: this sensor draws no noise (as simulate does with the file)");
  if (s.NoiseLevelGiven)
    WarnOnce("calibrated " + s.Sensor + ": noise_level is ignored: " + s.Path +
             " gives the measured reading noise (noise." + str_channel + "); noise=\"false\" turns noise off");
  if (s.Uniform) {
    std::vector<double> vecLevel;
    for (double fSd : vec_sd) vecLevel.push_back(ms::uniform_level_with_sd(fSd, f_scale));
    c_noise.uniform(vecLevel);
  } else {
    c_noise.gaussian(vec_sd, f_scale);
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

/// What ARGoS cannot apply stops it at Init, naming the effect, the file (line:column) and why:
/// a covariate (ARGoS has no log column), and a non-neutral effect of the kind's catalogue that
/// the sensor does not apply (`applied`: what its reading runs, applied_effects.hpp).
template <class Model>
void RefuseWhatArgosCannotApply(const SCommon& s, const Model& m, const epuck2::argos_plugin::Applied& applied) {
  if (!m.covariates.empty()) {
    const std::string strName = std::string(fx::kCovariatePrefix) + m.covariates.front().column;
    s.Fail("/effects/" + strName, "effects." + strName + ": the calibrated " + s.Sensor +
                                      " cannot apply it in ARGoS: it needs the log column '" + m.covariates.front().column +
                                      "', which ARGoS does not have");
  }
  epuck2::argos_plugin::refuse_unapplied(m, applied, *s.Root, s.Path, s.Robot, "the calibrated " + s.Sensor);
}

/// Each sensor's reading noise as a vector.
template <std::size_t N>
std::vector<double> Sd(const std::array<double, N>& a) {
  return {a.begin(), a.end()};
}

/// The noise paragraph of a calibrated sensor's help text (ARGoS's --query): the file's channel
/// noise.`str_channel`, its sd in `str_sd`, the plug-in's scale of a unit noise `str_scale`.
std::string NoiseHelp(const std::string& str_channel, const std::string& str_sd, const std::string& str_scale) {
  return "noise (default true): the coefficient file's measured reading noise, noise." + str_channel + "\n(its sd in " + str_sd +
         "), as a Gaussian of that sd drawn from ARGoS's\n"
         "random generator; noise_distribution=\"uniform\": the plug-in's uniform noise of\n"
         "the same variance, level sqrt(3) sd / " + str_scale + " (the file's argos_uniform_level).\n"
         "A file without a noise section: the plug-in's uniform noise of noise_level\n"
         "(x " + str_scale + "), with a warning. noise=\"false\": none.";
}

/// Effect `un_id`'s name in catalogue `c` (the help texts name effects through the registry).
std::string EffectName(const fx::Catalogue& c, std::size_t un_id) { return c[un_id].name; }

/// A calibrated drive sensor's file (ToF, encoders): what ARGoS runs of it and the model (noise).
struct SDriveFile {
  epuck2::argos_plugin::DriveConfig Drive;
  ms::DriveModel Model;
};
SDriveFile ReadDriveFile(const SCommon& s) {
  return {epuck2::argos_plugin::read_drive_config(*s.Root, s.Path, s.Robot, "the calibrated " + s.Sensor),
          ec::drive_model_from_json(*s.Root, s.Path, s.Robot)};
}

/// The plug-in's encoder noise scale: a unit noise is 32767 steps.
constexpr double kEncoderNoiseScale = ms::kPluginNoiseScaleEncoder_steps;

/// c_v rotated by the unit quaternion (f_w, f_x, f_y, f_z): v + w t + q × t with t = 2 q × v, inline
/// (the per-hit cost of CVector3::Rotate's call and CQuaternion::Inverse's copy is what this saves).
CVector3 RotateUnit(Real f_w, Real f_x, Real f_y, Real f_z, const CVector3& c_v) {
  const Real fTx = 2 * (f_y * c_v.GetZ() - f_z * c_v.GetY());
  const Real fTy = 2 * (f_z * c_v.GetX() - f_x * c_v.GetZ());
  const Real fTz = 2 * (f_x * c_v.GetY() - f_y * c_v.GetX());
  return CVector3(c_v.GetX() + f_w * fTx + (f_y * fTz - f_z * fTy),
                  c_v.GetY() + f_w * fTy + (f_z * fTx - f_x * fTz),
                  c_v.GetZ() + f_w * fTz + (f_x * fTy - f_y * fTx));
}

/// The ray of a ray-casting sensor (proximity, ToF) in world coordinates.
/// `f_scale` stretches it (1: the sensor's own length). The plug-in's arithmetic (start and end
/// rotated by the anchor's unit quaternion, then moved), with the rotation inline: CVector3::Rotate's
/// two quaternion products through a call cost about 90 instructions, RotateUnit about 30.
template <class SENSOR>
CRay3 WorldRay(const SENSOR& s_sensor, Real f_scale = 1.0) {
  const CQuaternion& cQ = s_sensor.Anchor.Orientation;
  CVector3 cEnd = s_sensor.Offset;
  cEnd += f_scale == 1.0 ? s_sensor.Direction : s_sensor.Direction * f_scale;
  return CRay3(RotateUnit(cQ.GetW(), cQ.GetX(), cQ.GetY(), cQ.GetZ(), s_sensor.Offset) + s_sensor.Anchor.Position,
               RotateUnit(cQ.GetW(), cQ.GetX(), cQ.GetY(), cQ.GetZ(), cEnd) + s_sensor.Anchor.Position);
}

}  // namespace

/****************************************/
/* Proximity                            */
/****************************************/

void CEPuck2CalibratedProximitySensor::Init(TConfigurationNode& t_tree) {
  const std::string strName = "epuck2_proximity";
  CEPuck2ProximityDefaultSensor::Init(t_tree);
  SCommon s = ReadCommon(t_tree, strName, *m_pcProximityEntity);
  std::string strCurve = "max";
  GetNodeAttributeOrDefault(t_tree, "curve", strCurve, strCurve);
  if (strCurve != "max" && strCurve != "mean")
    THROW_ARGOSEXCEPTION("calibrated " << strName << ": curve must be 'max' (Eq. 1 fitted to the maxima) or 'mean'");
  Checked(strName, [&] {
    /* The project's one reader (lib/coefficients): Eq. 1's a, b, c (or the means' curve), range_m,
       a diagnosis's effects, the noise; every value checked */
    m_sModel = ec::proximity_model_from_json(*s.Root, s.Path, s.Robot,
                                             strCurve == "mean" ? ec::ProximityCurve::means : ec::ProximityCurve::maxima);
    RefuseWhatArgosCannotApply(s, m_sModel, epuck2::argos_plugin::proximity_applies());
    /* incidence_angle: the angle of each hit surface, computed only when the file has one */
    m_bIncidence = m_sModel.effects.incidence.k != 0.0;
    if (m_tReadings.size() != m_sModel.noise_sd_raw.size())
      s.Fail("", "the robot has " + std::to_string(m_tReadings.size()) + " proximity sensors, the model " +
                     std::to_string(m_sModel.noise_sd_raw.size()));
    /* The rays reach as far as the model responds: the base curve's range_m, and a long tail
       until it falls below half a count (it rounds to nothing beyond) */
    Real fReach = m_sModel.base.range_m;
    const auto& sTail = m_sModel.effects.tail;
    if (std::abs(sTail.amplitude_raw) > 0.5)
      fReach = std::max(fReach, sTail.length_m * std::log(2.0 * std::abs(sTail.amplitude_raw)));
    m_vecRayScale.clear();
    for (UInt32 i = 0; i < m_tReadings.size(); ++i)
      m_vecRayScale.push_back(fReach / m_pcProximityEntity->GetSensor(i).Direction.Length());
    /* The model adds the noise in counts: a unit noise times 4095 */
    ConfigureNoise(s, "proximity", Sd(m_sModel.noise_sd_raw), ms::kPluginNoiseScaleProximity_counts, m_cNoise);
  });
  m_bAddNoise = false;
}

namespace {
/// The outward normal, in world coordinates, of the surface of a box or cylinder entity at the
/// point c_hit (world) on it; false for any other entity. An ARGoS box or cylinder's origin anchor
/// is the centre of its base, its size (box) or radius and height (cylinder) in its own frame, so
/// the face hit is the one whose plane lies nearest c_hit in that frame.
bool AnalyticNormal(const CEmbodiedEntity& c_entity, const CVector3& c_hit, CVector3& c_normal) {
  if (!c_entity.HasParent()) return false;
  const CComposableEntity& cParent = c_entity.GetParent();
  const SAnchor& sOrigin = c_entity.GetOriginAnchor();
  const CQuaternion& cQ = sOrigin.Orientation;
  /* the exact type (typeid, cheaper than dynamic_cast): a subclass takes the side rays */
  const bool bBox = typeid(cParent) == typeid(CBoxEntity);
  if (!bBox && typeid(cParent) != typeid(CCylinderEntity)) return false;
  /* c_hit in the entity's frame (the conjugate rotation), z from its base */
  const CVector3 cLocal = RotateUnit(cQ.GetW(), -cQ.GetX(), -cQ.GetY(), -cQ.GetZ(), c_hit - sOrigin.Position);
  if (bBox) {
    const auto* pcBox = static_cast<const CBoxEntity*>(&cParent);
    const CVector3 cHalf = pcBox->GetSize() * 0.5;
    const Real fCentred[3] = {cLocal.GetX(), cLocal.GetY(), cLocal.GetZ() - cHalf.GetZ()};
    const Real fHalf[3] = {cHalf.GetX(), cHalf.GetY(), cHalf.GetZ()};
    int nFace = 0;
    Real fNearest = fHalf[0] - Abs(fCentred[0]);
    for (int j = 1; j < 3; ++j) {
      const Real fGap = fHalf[j] - Abs(fCentred[j]);
      if (fGap < fNearest) { fNearest = fGap; nFace = j; }
    }
    Real fAxis[3] = {0, 0, 0};
    fAxis[nFace] = fCentred[nFace] < 0 ? -1.0 : 1.0;
    c_normal.Set(fAxis[0], fAxis[1], fAxis[2]);
  } else {
    const auto* pcCylinder = static_cast<const CCylinderEntity*>(&cParent);
    const Real fHalfHeight = pcCylinder->GetHeight() * 0.5;
    const Real fZ = cLocal.GetZ() - fHalfHeight;
    const Real fRadial = std::sqrt(cLocal.GetX() * cLocal.GetX() + cLocal.GetY() * cLocal.GetY());
    if (fHalfHeight - Abs(fZ) < pcCylinder->GetRadius() - fRadial || !(fRadial > 0)) {
      c_normal.Set(0, 0, fZ < 0 ? -1.0 : 1.0); /* a cap */
    } else {
      c_normal.Set(cLocal.GetX() / fRadial, cLocal.GetY() / fRadial, 0); /* the side: radial */
    }
  }
  c_normal = RotateUnit(cQ.GetW(), cQ.GetX(), cQ.GetY(), cQ.GetZ(), c_normal);
  return true;
}
}  // namespace

Real CEPuck2CalibratedProximitySensor::CosIncidence(const CRay3& c_ray, Real f_distance,
                                                     const CEmbodiedEntity* pc_hit) {
  const Real fEpsilon = 0.001;
  CVector3 cU = c_ray.GetEnd() - c_ray.GetStart();
  cU.Normalize();
  /* a box or a cylinder: the normal of the face hit, without another ray query */
  CVector3 cFaceNormal;
  if (pc_hit != nullptr && AnalyticNormal(*pc_hit, c_ray.GetStart() + cU * f_distance, cFaceNormal)) {
    return Abs(cFaceNormal.DotProduct(cU));
  }
  /* any other shape (robots...): two more rays 1 mm beside this one, across it */
  /* two directions across the ray */
  CVector3 cV1 = cU;
  cV1.CrossProduct(Abs(cU.GetZ()) < 0.9 ? CVector3::Z : CVector3::X);
  cV1.Normalize();
  CVector3 cV2 = cU;
  cV2.CrossProduct(cV1);
  cV2.Normalize();
  const CVector3 cHit = c_ray.GetStart() + cU * f_distance;
  SEmbodiedEntityIntersectionItem sSide;
  /* the hit of the ray moved by f_offset across it along c_v, or nothing */
  auto SideHit = [&](const CVector3& c_v, Real f_offset, CVector3& c_out) {
    const CRay3 cSide(c_ray.GetStart() + c_v * f_offset, c_ray.GetEnd() + c_v * f_offset);
    if (!GetClosestEmbodiedEntityIntersectedByRay(sSide, cSide, *m_pcEmbodiedEntity)) return false;
    c_out = cSide.GetStart() + cU * cSide.GetDistance(sSide.TOnRay);
    return true;
  };
  CVector3 cP1, cP2;
  if (!SideHit(cV1, fEpsilon, cP1) && !SideHit(cV1, -fEpsilon, cP1)) return 1.0;
  if (!SideHit(cV2, fEpsilon, cP2) && !SideHit(cV2, -fEpsilon, cP2)) return 1.0;
  CVector3 cNormal = cP1 - cHit;
  cNormal.CrossProduct(cP2 - cHit);
  const Real fLength = cNormal.Length();
  if (!(fLength > 0)) return 1.0;
  return Abs(cNormal.DotProduct(cU)) / fLength;
}

Real CEPuck2CalibratedProximitySensor::CalculateReading(Real f_distance) {
  return std::clamp(ms::mean_raw(m_sModel, 0, f_distance) / ms::kProximityFullScale_raw, 0.0, 1.0);
}

void CEPuck2CalibratedProximitySensor::Update() {
  SEmbodiedEntityIntersectionItem sIntersection;
  for (UInt32 i = 0; i < m_tReadings.size(); ++i) {
    CRay3 cRay = WorldRay(m_pcProximityEntity->GetSensor(i), m_vecRayScale[i]);
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
    /* the angle only where the model uses it: the base response, up to range_m (beyond it a long
       tail's rays still hit, and the tail has no angle) */
    const double fCos = m_bIncidence && fDistance && *fDistance <= m_sModel.base.range_m
                            ? CosIncidence(cRay, *fDistance, sIntersection.IntersectedEntity)
                            : 1.0;
    /* lib/models' mean (every effect the file has), the noise in counts, the rounding and the rails */
    const double fMean = ms::mean_raw(m_sModel, static_cast<int>(i), fDistance, fCos) +
                         ms::uniform_noise(m_cNoise.unit(i), m_cNoise.level(i)) * ms::kPluginNoiseScaleProximity_counts;
    m_tReadings[i].Value = std::clamp(std::round(fMean), 0.0, ms::kProximityFullScale_raw);
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
                "robot: use the file's robots.ID set.\n" +
                NoiseHelp("proximity", "counts, per sensor from per_sensor_sd", "4095"),
                "Usable");

/****************************************/
/* Ground                               */
/****************************************/

void CEPuck2CalibratedGroundSensor::Init(TConfigurationNode& t_tree) {
  const std::string strName = "epuck2_ground";
  CEPuck2GroundRotZOnlySensor::Init(t_tree);
  SCommon s = ReadCommon(t_tree, strName, *m_pcGroundSensorEntity);
  Checked(strName, [&] {
    /* The project's one reader (lib/coefficients): each sensor's gain and offset, a diagnosis's
       nonlinear_response; ARGoS cannot apply a covariate */
    m_sModel = ec::ground_model_from_json(*s.Root, s.Path, s.Robot);
    RefuseWhatArgosCannotApply(s, m_sModel, epuck2::argos_plugin::ground_applies());
    if (m_tReadings.size() != m_sModel.sensors.size())
      s.Fail("", "the robot has " + std::to_string(m_tReadings.size()) + " ground sensors, the model " +
                     std::to_string(m_sModel.sensors.size()));
    /* The model scales a unit noise by the full scale, 1023 counts */
    ConfigureNoise(s, "ground", Sd(m_sModel.noise_sd_raw), ms::kPluginNoiseScaleGround_counts, m_cNoise);
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
                "diagnosis's " + EffectName(fx::ground_catalogue(), fx::ground::nonlinear_response) +
                " exponent (1 without) from the coefficient file.\n\n"
                "  <epuck2_ground implementation=\"calibrated\" coefficients=\"ground.json\"\n"
                "                 robot=\"ID\" noise=\"true\" noise_distribution=\"gaussian\" />\n\n" +
                NoiseHelp("ground", "counts, per sensor from per_sensor_sd", "1023"),
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
  SCommon s = ReadCommon(t_tree, strName, *m_pcTOFEntity);
  Checked(strName, [&] {
    const auto [sDrive, sModel] = ReadDriveFile(s);
    m_sCoefficients.scale = sDrive.effects.tof_scale.k;
    m_sCoefficients.offset_mm = sDrive.effects.tof_offset.offset_mm;
    m_cDelay = epuck2::argos_plugin::DelayLine(sDrive.effects.latency.delay_s);
    m_sCoefficients.range_m = m_pcTOFEntity->GetSensor(0).Direction.Length();
    /* The model scales a unit noise by the range, in mm */
    ConfigureNoise(s, "tof", {sModel.tof_noise_sd_mm}, m_sCoefficients.range_m * 1000.0, m_cNoise);
    const bool bDriveEffects = (sDrive.limit_from != "firmware" && sDrive.limit_from != "calibration") || sDrive.effects.accel_limit.accel_cm_s2 < ms::kDriveLimitOn ||
                               sDrive.effects.speed_scale.k != 1.0 || sDrive.effects.slip.tau_s > 0;
    if (bDriveEffects && !epuck2::argos_plugin::DriveRegistry::find(m_pcRobot))
      WarnOnce("calibrated " + strName + ": " + s.Path +
               ": the robot's differential_steering is not implementation=\"calibrated\": the file's speed limit, "
               "slip and other drive effects do not move the body, only the ToF's own (" +
               epuck2::argos_plugin::applied_names(fx::drive_catalogue(), epuck2::argos_plugin::tof_applies()) + ") apply");
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
                "Same ray and control interface as the default implementation; the reading is\n" +
                std::string(fx::file_key(fx::drive_catalogue(), fx::drive::tof_scale)) +
                " * distance + tof_offset_mm in mm, rounded and clamped to [20, 2000],\n"
                "with " + fx::file_key(fx::drive_catalogue(), fx::drive::tof_scale) +
                " and tof_offset_mm from a drive coefficient file, the distance\n"
                "being the one " + EffectName(fx::drive_catalogue(), fx::drive::latency) +
                "'s delay_s ago (a diagnosis's effects." + EffectName(fx::drive_catalogue(), fx::drive::latency) + ").\n\n"
                "  <epuck2_tof implementation=\"calibrated\" coefficients=\"drive.json\"\n"
                "              robot=\"ID\" noise=\"true\" noise_distribution=\"gaussian\" />\n\n" +
                NoiseHelp("tof", "mm", "2000 mm (the range)"),
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
  SCommon s = ReadCommon(t_tree, strName, *m_pcEncoderEntity);
  Checked(strName, [&] {
    const auto [sDrive, sModel] = ReadDriveFile(s);
    m_sCoefficients.steps_per_m = sDrive.steps_per_m;
    /* The model scales a unit noise by 32767 steps; one channel per wheel */
    ConfigureNoise(s, "encoder", {sModel.encoder_noise_sd_steps, sModel.encoder_noise_sd_steps}, kEncoderNoiseScale, m_cNoise);
  });
  /* ARGoS sets up a controller's actuators before its sensors: the calibrated actuator's drive is
     there by now, if the robot has one */
  m_pcDrive = epuck2::argos_plugin::DriveRegistry::find(m_pcRobot);
  if (!m_pcDrive)
    WarnOnce("calibrated " + strName + ": " + s.Path +
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
                "                  robot=\"ID\" noise=\"true\" noise_distribution=\"gaussian\" />\n\n" +
                NoiseHelp("encoder", "steps", "32767") + "\n"
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
  SCommon s = ReadCommon(t_tree, strName, *m_pcLightEntity);
  Checked(strName, [&] {
    /* The project's one reader (lib/coefficients): Eq. 2's gamma, a calibration's per-sensor
       gammas (per_sensor; a robot's set's robots.ID.per_sensor), range_m, a diagnosis's effects
       (ambient_offset, falloff_exponent, sensor_gain: all applied), the noise; every value checked */
    m_sModel = ec::light_model_from_json(*s.Root, s.Path, s.Robot);
    RefuseWhatArgosCannotApply(s, m_sModel, epuck2::argos_plugin::light_applies());
    if (m_tReadings.size() != m_sModel.noise_sd_raw.size())
      s.Fail("", "the robot has " + std::to_string(m_tReadings.size()) + " light sensors, the model " +
                     std::to_string(m_sModel.noise_sd_raw.size()));
    /* The model adds the noise in counts: a unit noise times 4095 */
    ConfigureNoise(s, "light", Sd(m_sModel.noise_sd_raw), ms::kPluginNoiseScaleLight_counts, m_cNoise);
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
        if (cRay.GetLength() > m_sModel.base.range_m) continue;
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
    /* lib/models' mean over the visible lights (the sensor's own gamma, every effect the file has), the noise in counts
       (the plug-in's sign: noise raises the normalised sum, lowering the reading), the rounding
       and the rails */
    const double fMean = ms::mean_raw(m_sModel, static_cast<int>(i), vecLights) -
                         ms::uniform_noise(m_cNoise.unit(i), m_cNoise.level(i)) * ms::kPluginNoiseScaleLight_counts;
    m_tReadings[i].Value = std::clamp(std::round(fMean), 0.0, ms::kProximityFullScale_raw);
  }
}

REGISTER_SENSOR(CEPuck2CalibratedLightSensor, "epuck2_light", "calibrated", "epuck2-fit", "1.0",
                "The E-Puck2 ambient light sensors with coefficients fitted by epuck2-fit.",
                "Same rays, occlusions and control interface as the default implementation; the\n"
                "reading is (1 - sum over visible lights of (gamma I / d)^2) x 4095, rounded and\n"
                "clamped, with gamma from the coefficient file (per_sensor entries override it).\n\n"
                "  <epuck2_light implementation=\"calibrated\" coefficients=\"light.json\"\n"
                "                robot=\"ID\" noise=\"true\" noise_distribution=\"gaussian\" />\n\n" +
                NoiseHelp("light", "counts, per sensor from per_sensor_sd", "4095"),
                "Usable");

/****************************************/
/* Camera                               */
/****************************************/

void CEPuck2CalibratedCameraSensor::Init(TConfigurationNode& t_tree) {
  const std::string strName = "epuck2_colored_blob_perspective_camera";
  SCommon s = ReadCommon(t_tree, strName, *m_pcCamEntity);
  Checked(strName, [&] {
    /* The project's one reader (lib/coefficients): the field of view, the centre, the radial
       distortion (k1, k2, k3), every value checked; ARGoS cannot apply a covariate */
    m_sModel = ec::camera_model_from_json(*s.Root, s.Path, s.Robot);
    RefuseWhatArgosCannotApply(s, m_sModel, epuck2::argos_plugin::camera_applies());
    const double fW = m_pcCamEntity->GetImagePxWidth(), fH = m_pcCamEntity->GetImagePxHeight();
    m_sModel.base.width_px = fW;
    /* Which LEDs it sees: the cone of the fitted field of view's aperture (ARGoS's, the half-angle
       on the image diagonal) and the range, as the plug-in's camera */
    m_fAperture = ms::aperture_from_horizontal_fov_rad(m_sModel.base.horizontal_fov_rad, static_cast<int>(fW),
                                                       static_cast<int>(fH));
    /* The file's range_m (read and checked by the shared reader, the robot's set first) where
       the file has one, else the camera entity's */
    const std::optional<double> cFileRange = ec::camera_range_m(*s.Root, s.Path, s.Robot);
    m_fRange = cFileRange ? *cFileRange : m_pcCamEntity->GetRange();
    m_pcCamEntity->SetAperture(CRadians(m_fAperture));
    m_pcCamEntity->SetRange(m_fRange);
    m_pcCamEntity->SetImagePxSize(static_cast<SInt32>(fW), static_cast<SInt32>(fH));
    /* The pixel noise (noise.camera, px), each axis; scale 1: the noise is in pixels */
    ConfigureNoise(s, "camera", {m_sModel.noise_sd_px, m_sModel.noise_sd_px}, 1.0, m_cNoise);
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
    /* Off the image: no blob (lib/models' camera_image_holds, which simulate --like applies too) */
    if (!ms::camera_image_holds(fX, fY, m_cCam.GetImagePxWidth(), m_cCam.GetImagePxHeight())) return true;
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
                "sub-pixel accuracy, a diagnosis's " + EffectName(fx::camera_catalogue(), fx::camera::radial_distortion) +
                " (k1, k2, k3), and the measured pixel noise\n"
                "noise.camera (Gaussian, each axis), then rounded; blobs off the image are dropped.\n\n"
                "  <epuck2_colored_blob_perspective_camera implementation=\"calibrated\"\n"
                "      coefficients=\"camera.json\" medium=\"leds\" noise=\"true\" robot=\"ID|auto\" />",
                "Usable");

}  // namespace argos
