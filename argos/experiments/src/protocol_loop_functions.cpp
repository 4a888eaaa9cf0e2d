// The paper's calibration protocols run in ARGoS, writing logs in the project's CSV formats (the
// formats epuck2-fit reads, one kind each):
//   proximity  time_s,distance_m,sensor,value        PROX0 facing a wall at 0, 5, ..., 60 mm
//   ground     grey,sensor,value                     the whole floor at greys 0, 0.1, ..., 1
//              (with black_below_x="X": the floor is black where x < X, so that which sensor reads
//              the grey depends on where the robot's pose puts it)
//   light      distance_m,intensity,sensor,value     a light on sensor 0's then sensor 7's axis
//              (with robot_yaw="DEG": the robot turned by DEG, the light on the turned axis)
//   drive      time_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm
//              towards / away from an obstacle 0.3 m ahead of the ToF sensor, one run per speed
//   battery    time_s,speed_cm_s,charge              robot i spins in place at i cm/s until empty
//              (with arc="a", a in [-1, 1): it drives a circle instead, left wheel a i, right i cm/s)
// every file with a `# robot: ID` line. The loop functions place the robots (and lights), command
// the wheels through the recorder controller and read the sensors it holds: which sensor
// implementation produced the readings (the plug-in's or the calibrated one) is the .argos
// file's business. With like="LOG" like_out="OUT" (scripts/argos-record.sh --like) any kind
// replays a measured log instead: LOG read through lib/logs (replay_log.hpp), each row's
// conditions set up in ARGoS, ARGoS's readings written as one log in LOG's format, row for row,
// renamed to OUT once whole.
//
//   <loop_functions library="libepuck2_argos_protocols" label="epuck2_protocol"
//                   kind="proximity" output_dir="." robot="argos-epuck2" samples="20"/>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <argos3/core/simulator/loop_functions.h>
#include <argos3/core/simulator/simulator.h>
#include <argos3/core/simulator/physics_engine/physics_engine.h>
#include <argos3/core/utility/math/vector2.h>
#include <argos3/plugins/robots/e-puck2/simulator/epuck2_battery_equipped_entity.h>
#include <argos3/plugins/robots/e-puck2/simulator/epuck2_camera_equipped_entity.h>
#include <argos3/plugins/robots/e-puck2/simulator/epuck2_entity.h>
#include <argos3/plugins/robots/e-puck2/simulator/epuck2_tof_equipped_entity.h>
#include <argos3/plugins/simulator/entities/box_entity.h>
#include <argos3/plugins/simulator/entities/light_entity.h>
#include <argos3/plugins/simulator/entities/light_sensor_equipped_entity.h>
#include <argos3/plugins/simulator/entities/proximity_sensor_equipped_entity.h>

#include <epuck2/models/kinds.hpp>

#include "recorder_controller.hpp"
#include "replay_log.hpp"

namespace argos {

namespace {

/// "a:step:b" or "x,y,z" to a list of numbers.
std::vector<Real> ParseList(const std::string& str) {
  std::vector<Real> v;
  if (std::count(str.begin(), str.end(), ':') == 2) {
    Real a, s, b;
    char c1, c2;
    std::istringstream is(str);
    is >> a >> c1 >> s >> c2 >> b;
    if (!is || s <= 0) THROW_ARGOSEXCEPTION("bad range \"" << str << "\" (expected from:step:to)");
    for (int k = 0; a + k * s <= b + 1e-9; ++k) v.push_back(std::round((a + k * s) * 1e9) / 1e9);
    return v;
  }
  std::istringstream is(str);
  std::string item;
  while (std::getline(is, item, ',')) v.push_back(std::stod(item));
  return v;
}

std::string Num(Real f, int digits = 6) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, f);
  return buf;
}

/// Steps moved since `start`, as a 16-bit register that read 0 at the run's start.
SInt32 Wrap16(SInt32 now, SInt32 start) {
  SInt32 d = now - start;
  while (d >= 32768) d -= 65536;
  while (d < -32768) d += 65536;
  return d;
}

}  // namespace

class CEPuck2ProtocolLoopFunctions : public CLoopFunctions {
 public:
  void Init(TConfigurationNode& t_tree) override {
    GetNodeAttribute(t_tree, "kind", m_strKind);
    GetNodeAttributeOrDefault(t_tree, "output_dir", m_strOutDir, std::string("."));
    GetNodeAttributeOrDefault(t_tree, "robot", m_strRobot, std::string("argos-epuck2"));
    GetNodeAttributeOrDefault(t_tree, "samples", m_unSamples, m_unSamples);
    m_fTick = CPhysicsEngine::GetSimulationClockTick();
    CSpace::TMapPerType& tRobots = GetSpace().GetEntitiesByType("e-puck2");
    for (auto& t : tRobots) m_vecRobots.push_back(any_cast<CEPuck2Entity*>(t.second));
    if (m_vecRobots.empty()) THROW_ARGOSEXCEPTION("epuck2_protocol: no e-puck2 in the arena");
    /* like="LOG": replay a measured log row by row into like_out (scripts/argos-record.sh --like) */
    GetNodeAttributeOrDefault(t_tree, "like", m_strLike, m_strLike);
    GetNodeAttributeOrDefault(t_tree, "like_out", m_strLikeOut, m_strLikeOut);
    if (!m_strLike.empty()) {
      InitReplay();
      return;
    }
    if (m_strKind == "proximity") {
      std::string str = "0:0.005:0.06";
      GetNodeAttributeOrDefault(t_tree, "distances", str, str);
      m_vecSteps = ParseList(str);
      Open(m_strOutDir + "/proximity_" + m_strRobot + ".csv", "time_s,distance_m,sensor,value",
           {"protocol: ARGoS, PROX0 facing a wall at each distance, " + std::to_string(m_unSamples) + " readings each"});
    } else if (m_strKind == "ground") {
      std::string str = "0:0.1:1";
      GetNodeAttributeOrDefault(t_tree, "greys", str, str);
      for (Real g : ParseList(str)) m_vecSteps.push_back(std::round(g * 255.0) / 255.0);  // 8-bit floor colours
      if (NodeAttributeExists(t_tree, "black_below_x")) {
        GetNodeAttribute(t_tree, "black_below_x", m_fBlackBelowX);
        m_bBlackBelow = true;
      }
      Open(m_strOutDir + "/ground_" + m_strRobot + ".csv", "grey,sensor,value",
           {"protocol: ARGoS, the whole floor at each grey (8-bit colour, grey = level/255)"});
      /* Several robots (a swarm, each with its own set): every other robot's log too, named and
         tagged with its entity id */
      for (std::size_t i = 1; i < m_vecRobots.size(); ++i) {
        const std::string& id = m_vecRobots[i]->GetId();
        m_vecGroundOut.push_back(std::make_unique<std::ofstream>(m_strOutDir + "/ground_" + id + ".csv"));
        if (!*m_vecGroundOut.back()) THROW_ARGOSEXCEPTION("epuck2_protocol: cannot write in " << m_strOutDir);
        *m_vecGroundOut.back() << "# robot: " << id << "\n# protocol: ARGoS, the whole floor at each grey\ngrey,sensor,value\n";
      }
    } else if (m_strKind == "light") {
      std::string str = "0.1:0.05:0.5", strI = "0.5,1,1.5,2";
      GetNodeAttributeOrDefault(t_tree, "distances", str, str);
      GetNodeAttributeOrDefault(t_tree, "intensities", strI, strI);
      m_vecSteps = ParseList(str);
      m_vecIntensities = ParseList(strI);
      m_pcLight = &dynamic_cast<CLightEntity&>(GetSpace().GetEntity("light"));
      /* robot_yaw="DEG": the robot turned by DEG about z, the light on the turned sensor's axis (the
         same geometry turned: the readings must not change) */
      GetNodeAttributeOrDefault(t_tree, "robot_yaw", m_fRobotYawDeg, m_fRobotYawDeg);
    } else if (m_strKind == "drive") {
      std::string str = "2.5,5,7.5,10,12.5,15";
      GetNodeAttributeOrDefault(t_tree, "speeds", str, str);
      GetNodeAttributeOrDefault(t_tree, "obstacle_distance", m_fObstacle, m_fObstacle);
      GetNodeAttributeOrDefault(t_tree, "travel", m_fTravel, m_fTravel);
      /* right_wheel="r": the right wheel at r times the command (1, the default: straight runs; 0: the
         robot pivots on its still right wheel, which the logged right speed says) */
      GetNodeAttributeOrDefault(t_tree, "right_wheel", m_fRightWheel, m_fRightWheel);
      if (!(m_fRightWheel >= 0.0 && m_fRightWheel <= 1.0)) THROW_ARGOSEXCEPTION("epuck2_protocol: right_wheel must be in [0, 1], not " << m_fRightWheel);
      for (Real s : ParseList(str)) {
        m_vecSteps.push_back(s);
        m_vecSteps.push_back(-s);
      }
    } else if (m_strKind == "camera") {
      /* An LED (the light entity, in the LED medium) at each position of a grid in the camera's
         frame (forward, lateral, vertical), held for a settling tick and then `samples` frames */
      std::string strF = "0.15:0.05:0.4", strL = "-0.06:0.02:0.06", strV = "-0.03:0.015:0.03";
      GetNodeAttributeOrDefault(t_tree, "forward", strF, strF);
      GetNodeAttributeOrDefault(t_tree, "lateral", strL, strL);
      GetNodeAttributeOrDefault(t_tree, "vertical", strV, strV);
      for (Real f : ParseList(strF))
        for (Real l : ParseList(strL))
          for (Real v : ParseList(strV)) m_vecCameraPoints.push_back(CVector3(f, l, v));
      m_pcLight = &dynamic_cast<CLightEntity&>(GetSpace().GetEntity("light"));
      Open(m_strOutDir + "/camera_" + m_strRobot + ".csv", "forward_m,lateral_m,vertical_m,px,py",
           {"protocol: ARGoS, one LED at each position of a grid in the camera's frame, " + std::to_string(m_unSamples) +
            " frames each"});
    } else if (m_strKind == "battery") {
      GetNodeAttributeOrDefault(t_tree, "period", m_fPeriod, m_fPeriod);
      /* Significant digits of the charge (the firmware's percentage/100 has 6; 17 for bit-exact comparisons) */
      GetNodeAttributeOrDefault(t_tree, "charge_digits", m_nChargeDigits, m_nChargeDigits);
      /* arc="a": the left wheel at a times the right's (-1, the default: spinning in place). Moving
         on a circle, a robot's displacement per tick is not 0, so the discharge models take it,
         not the rotation, as its speed. */
      GetNodeAttributeOrDefault(t_tree, "arc", m_fArc, m_fArc);
      if (!(m_fArc >= -1.0 && m_fArc < 1.0)) THROW_ARGOSEXCEPTION("epuck2_protocol: arc must be in [-1, 1), not " << m_fArc);
      for (std::size_t i = 0; i < m_vecRobots.size(); ++i) {
        /* Robot i spins at speed i cm/s (its id's number when it has one) */
        Real fSpeed = static_cast<Real>(i);
        const std::string& id = m_vecRobots[i]->GetId();
        const auto p = id.find_last_not_of("0123456789");
        if (p + 1 < id.size()) fSpeed = std::stod(id.substr(p + 1));
        SBatteryRun s;
        s.Speed = fSpeed;
        char name[64];
        std::snprintf(name, sizeof name, "_speed-%02d.csv", static_cast<int>(fSpeed));
        s.Out = std::make_unique<std::ofstream>(m_strOutDir + "/" + m_strRobot + name);
        if (!*s.Out) THROW_ARGOSEXCEPTION("epuck2_protocol: cannot write in " << m_strOutDir);
        if (m_fArc == -1.0)
          *s.Out << "# robot: " << m_strRobot << "\n# protocol: ARGoS, spinning in place at " << Num(fSpeed)
                 << " cm/s from full charge until the charge reads 0\ntime_s,speed_cm_s,charge\n";
        else
          *s.Out << "# robot: " << m_strRobot << "\n# protocol: ARGoS, driving a circle, left wheel " << Num(m_fArc * fSpeed)
                 << " cm/s, right wheel " << Num(fSpeed) << " cm/s, from full charge until the charge reads 0\ntime_s,speed_cm_s,charge\n";
        m_vecBattery.push_back(std::move(s));
        Controller(i).SetWheels(m_fArc * fSpeed, fSpeed);
      }
    } else {
      THROW_ARGOSEXCEPTION("epuck2_protocol: kind must be proximity, ground, light, camera, drive or battery, not \"" << m_strKind << "\"");
    }
  }

  void PreStep() override {
    if (m_bReplay) {
      ReplayPreStep();
      return;
    }
    if (m_bDone || m_unSample != 0) return;
    if (m_strKind == "proximity") PlaceFacing(CurrentWall(), 0, m_vecSteps[m_unStep]);
    if (m_strKind == "light") PlaceLight();
    if (m_strKind == "camera") PlaceLed();
    if (m_strKind == "drive") {
      StartRun();
    }
  }

  void PostStep() override {
    if (m_bDone) return;
    const Real t = GetSpace().GetSimulationClock() * m_fTick;
    CEPuck2RecorderController& c = Controller(0);
    if (m_bReplay) {
      ReplayPostStep(c);
      return;
    }
    if (m_strKind == "proximity") {
      m_cOut << Num(t) << ',' << Num(m_vecSteps[m_unStep]) << ",0," << c.Proximity().at(0) << '\n';
      Advance(m_unSamples, m_vecSteps.size());
    } else if (m_strKind == "ground") {
      const auto v = c.Ground();
      for (std::size_t i = 0; i < v.size(); ++i) m_cOut << Num(m_vecSteps[m_unStep], 8) << ',' << i << ',' << v[i] << '\n';
      for (std::size_t r = 1; r < m_vecRobots.size(); ++r) {
        const auto w = Controller(r).Ground();
        for (std::size_t i = 0; i < w.size(); ++i)
          *m_vecGroundOut[r - 1] << Num(m_vecSteps[m_unStep], 8) << ',' << i << ',' << w[i] << '\n';
      }
      Advance(m_unSamples, m_vecSteps.size());
    } else if (m_strKind == "light") {
      const auto v = c.Light();
      m_cOut << Num(m_vecSteps[m_unStep]) << ',' << Num(m_vecIntensities[m_unIntensity]) << ',' << m_unLightSensor << ','
             << v.at(m_unLightSensor) << '\n';
      if (++m_unSample == m_unSamples) {
        m_unSample = 0;
        if (++m_unStep == m_vecSteps.size()) {
          m_unStep = 0;
          if (m_unLightSensor == 0) m_unLightSensor = 7;
          else {
            m_unLightSensor = 0;
            if (++m_unIntensity == m_vecIntensities.size()) m_bDone = true;
          }
        }
      }
    } else if (m_strKind == "drive") {
      DriveStep(c, t);
    } else if (m_strKind == "battery") {
      BatteryStep(t);
    } else if (m_strKind == "camera") {
      CameraStep(c);
    }
  }

  bool IsExperimentFinished() override { return m_bDone; }

  CColor GetFloorColor(const CVector2& c_pos) override {
    if (m_strKind == "ground" && m_bBlackBelow && c_pos.GetX() < m_fBlackBelowX) return CColor::BLACK;
    if (m_bReplay && m_strKind == "ground") {
      const UInt8 v = static_cast<UInt8>(std::lround(m_fReplayGrey * 255.0));
      return CColor(v, v, v);
    }
    if (m_strKind != "ground" || m_vecSteps.empty()) return CColor::WHITE;
    const UInt8 v = static_cast<UInt8>(std::lround(m_vecSteps[std::min<std::size_t>(m_unStep, m_vecSteps.size() - 1)] * 255.0));
    return CColor(v, v, v);
  }

  void Destroy() override {
    for (const SBatteryRun& r : m_vecBattery)
      LOG << "[epuck2_protocol] battery: commanded " << r.Speed << " cm/s, the discharge model saw "
          << r.MinSpeed << ".." << r.MaxSpeed << " cm/s" << std::endl;
    m_cOut.close();
    m_vecBattery.clear();
    m_vecGroundOut.clear();
  }

 private:
  struct SBatteryRun {
    Real Speed = 0;
    std::unique_ptr<std::ofstream> Out;
    bool Done = false;
    Real LastTime = 0, LastCharge = 1;
    /* The speed the plug-in's discharge models compute from the body's motion (0.01 cm/s) */
    CVector3 OldPosition;
    CQuaternion OldOrientation;
    Real MinSpeed = 1e9, MaxSpeed = -1e9;
  };

  CEPuck2RecorderController& Controller(std::size_t i) {
    return dynamic_cast<CEPuck2RecorderController&>(m_vecRobots[i]->GetControllableEntity().GetController());
  }

  void Open(const std::string& path, const std::string& header, const std::vector<std::string>& meta) {
    m_cOut.close();
    m_cOut.open(path);
    if (!m_cOut) THROW_ARGOSEXCEPTION("epuck2_protocol: cannot write \"" << path << "\"");
    m_cOut << "# robot: " << m_strRobot << '\n';
    for (const auto& m : meta) m_cOut << "# " << m << '\n';
    m_cOut << header << '\n';
  }

  void Advance(UInt32 un_samples, std::size_t un_steps) {
    if (++m_unSample == un_samples) {
      m_unSample = 0;
      if (++m_unStep == un_steps) m_bDone = true;
    }
  }

  /// The x of the wall's face the robot looks at (the box "wall" or "obstacle").
  Real CurrentWall() {
    CBoxEntity& cBox = dynamic_cast<CBoxEntity&>(GetSpace().GetEntity(m_strKind == "drive" ? "obstacle" : "wall"));
    return cBox.GetEmbodiedEntity().GetOriginAnchor().Position.GetX() - cBox.GetSize().GetX() / 2.0;
  }

  /// Places robot 0 so that the ray of proximity sensor `un_sensor` (or the ToF's, for drive)
  /// points along +x and starts `f_distance` before the wall's face at `f_face_x`.
  void PlaceFacing(Real f_face_x, UInt32 un_sensor, Real f_distance) {
    CVector3 cOffset, cDirection;
    if (m_strKind == "drive") {
      auto& s = m_vecRobots[0]->GetComponent<CEPuck2TOFEquippedEntity>("tof_sensor").GetSensor(0);
      cOffset = s.Offset;
      cDirection = s.Direction;
    } else {
      auto& s = m_vecRobots[0]->GetComponent<CProximitySensorEquippedEntity>("proximity_sensors").GetSensor(un_sensor);
      cOffset = s.Offset;
      cDirection = s.Direction;
    }
    Place(f_face_x, cOffset, cDirection, f_distance);
  }

  /// The sensor at (offset, direction) in the robot's frame looks at the wall's face at `f_face_x`
  /// from `f_distance` along its axis, the axis `f_angle_rad` off the wall's normal (+x).
  void Place(Real f_face_x, CVector3 c_offset, const CVector3& c_direction, Real f_distance, Real f_angle_rad = 0.0) {
    const CRadians cYaw = -ATan2(c_direction.GetY(), c_direction.GetX()) + CRadians(f_angle_rad);
    c_offset.RotateZ(cYaw);
    const CVector3 cPos(f_face_x - f_distance * std::cos(f_angle_rad) - c_offset.GetX(), -c_offset.GetY(), 0.0);
    CQuaternion cOrient;
    cOrient.FromAngleAxis(cYaw, CVector3::Z);
    if (!m_vecRobots[0]->GetEmbodiedEntity().MoveTo(cPos, cOrient, false, true))
      THROW_ARGOSEXCEPTION("epuck2_protocol: cannot place the robot at " << cPos);
  }

  /// Robot at the origin looking along +x; the light on light sensor m_unLightSensor's axis,
  /// at the current distance from it and at its height.
  void PlaceLight() {
    PlaceLightAt(m_unLightSensor, m_vecSteps[m_unStep], m_vecIntensities[m_unIntensity]);
    if (m_unStep == 0 && m_unLightSensor == 0) {
      char name[64];
      std::snprintf(name, sizeof name, "/light_intensity_%.2f.csv", m_vecIntensities[m_unIntensity]);
      Open(m_strOutDir + name, "distance_m,intensity,sensor,value",
           {"protocol: ARGoS, one light on sensor 0's then sensor 7's axis, at the sensor's height"});
    }
  }

  /// Robot at the origin looking along +x; the light on light sensor `un_sensor`'s axis, at
  /// `f_distance` from it and at its height, of intensity `f_intensity`.
  void PlaceLightAt(UInt32 un_sensor, Real f_distance, Real f_intensity) {
    CQuaternion cOrient;
    cOrient.FromAngleAxis(ToRadians(CDegrees(m_fRobotYawDeg)), CVector3::Z);
    m_vecRobots[0]->GetEmbodiedEntity().MoveTo(CVector3(0, 0, 0), cOrient, false, true);
    auto& s = m_vecRobots[0]->GetComponent<CLightSensorEquippedEntity>("light_sensors").GetSensor(un_sensor);
    CVector3 cPos = s.Position, cDir = s.Direction;  // in the robot's frame
    cPos.Rotate(cOrient);
    cDir.Rotate(cOrient);
    cDir.Normalize();
    m_pcLight->SetPosition(cPos + cDir * f_distance);
    m_pcLight->SetIntensity(f_intensity);
  }

  /// Camera: the LED at the current grid point, in the camera's frame (X forward, Y left, Z up).
  void PlaceLed() {
    if (m_bCameraSettled) return;
    PlaceLedAt(m_vecCameraPoints[m_unStep]);
  }

  void PlaceLedAt(CVector3 c_point) {
    auto& cCam = m_vecRobots[0]->GetComponent<CEPuck2CameraEquippedEntity>("perspective_camera");
    c_point.Rotate(cCam.GetOrientation());
    m_pcLight->SetPosition(cCam.GetPosition() + c_point);
  }

  /// A settling tick after each move (the LED medium's index follows the light a tick later), then
  /// `samples` frames: every blob the camera reports is a row.
  void CameraStep(CEPuck2RecorderController& c) {
    if (!m_bCameraSettled) {
      m_bCameraSettled = true;
      return;
    }
    const CVector3& p = m_vecCameraPoints[m_unStep];
    for (const auto& b : c.Blobs())
      m_cOut << Num(p.GetX()) << ',' << Num(p.GetY()) << ',' << Num(p.GetZ()) << ',' << b.first << ',' << b.second << '\n';
    if (++m_unSample == m_unSamples) {
      m_unSample = 0;
      m_bCameraSettled = false;
      if (++m_unStep == m_vecCameraPoints.size()) m_bDone = true;
    }
  }

  /// Drive: a run per signed speed: 1 s still, drive `travel` m, 1 s still.
  void StartRun() {
    if (m_unRunTick != 0) return;
    const Real v = m_vecSteps[m_unStep];
    auto& s = m_vecRobots[0]->GetComponent<CEPuck2TOFEquippedEntity>("tof_sensor").GetSensor(0);
    Place(CurrentWall(), s.Offset, s.Direction, m_fObstacle);
    char name[96];
    std::snprintf(name, sizeof name, "/drive_%s_%04.1f_cm_s.csv", v > 0 ? "toward" : "away", std::abs(v));
    Open(m_strOutDir + name, "time_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm",
         {"obstacle_distance_m: " + Num(m_fObstacle), "commanded_speed_cm_s: " + Num(v),
          "protocol: ARGoS, still 1 s, drive " + Num(m_fTravel) + " m, still 1 s"});
    m_bRunStarted = true;
  }

  void DriveStep(CEPuck2RecorderController& c, Real) {
    const Real v = m_vecSteps[m_unStep];
    const UInt32 unStill = static_cast<UInt32>(std::lround(1.0 / m_fTick));
    const UInt32 unMove = static_cast<UInt32>(std::lround(m_fTravel / (std::abs(v) / 100.0) / m_fTick));
    if (m_unRunTick == 0) {
      m_nStartLeft = c.LeftSteps();
      m_nStartRight = c.RightSteps();
    }
    /* The command for the coming tick, logged with this tick's readings */
    const Real fCmd = (m_unRunTick >= unStill && m_unRunTick < unStill + unMove) ? v : 0.0;
    c.SetWheels(fCmd, m_fRightWheel * fCmd);
    m_cOut << Num(m_unRunTick * m_fTick) << ',' << Num(fCmd) << ',' << Num(m_fRightWheel * fCmd) << ','
           << Wrap16(c.LeftSteps(), m_nStartLeft) << ',' << Wrap16(c.RightSteps(), m_nStartRight) << ',' << c.Tof() << '\n';
    if (++m_unRunTick > 2 * unStill + unMove) {
      m_unRunTick = 0;
      m_cOut.close();
      if (++m_unStep == m_vecSteps.size()) m_bDone = true;
    }
  }

  /// like=: the log read through lib/logs (replay_log.hpp), its rows set up one by one. Errors
  /// name the file and line.
  void InitReplay() {
    if (m_strLikeOut.empty()) THROW_ARGOSEXCEPTION("epuck2_protocol: like= needs like_out= (the log to write)");
    try {
      m_sReplay = epuck2::argos_replay::read_replay_log(m_strLike, m_strKind);
    } catch (const std::exception& e) {
      THROW_ARGOSEXCEPTION(e.what());
    }
    m_bReplay = true;
    if (m_strKind == "light" || m_strKind == "camera") m_pcLight = &dynamic_cast<CLightEntity&>(GetSpace().GetEntity("light"));
    std::string strProtocol = "ARGoS, the conditions of the log above row by row: ";
    if (m_strKind == "proximity") strProtocol += "the sensor's axis on a wall at distance_m (angle_deg off its normal)";
    if (m_strKind == "ground") strProtocol += "the whole floor at grey (8-bit colour: level round(255 grey)/255)";
    if (m_strKind == "light") strProtocol += "one light on the sensor's axis at distance_m, of the row's intensity";
    if (m_strKind == "camera") strProtocol += "one LED at the row's position in the camera's frame, a settling tick, one frame";
    if (m_strKind == "drive") {
      strProtocol = "ARGoS, the commands of the log above row by row, readings at the tick nearest each row's time";
      m_fObstacle = m_sReplay.obstacle_distance_m;
    }
    if (m_strKind == "battery") {
      strProtocol += "spinning in place at the row's speed, the charge read at the tick nearest each row's time";
      /* The run starts where the log's does, as simulate --like starts it: from a full charge when
         its first charge reads at least kBatteryStartsFull, else from that reading (a run logged
         from a part-charged battery). */
      const auto c = m_sReplay.numeric.find("charge");
      if (c != m_sReplay.numeric.end() && !c->second.empty() && c->second.front() < epuck2::models::sensors::kBatteryStartsFull) {
        CEPuck2BatteryEquippedEntity& cBattery = m_vecRobots[0]->GetBatterySensorEquippedEntity();
        cBattery.SetAvailableCharge(std::max(0.0, c->second.front()) * cBattery.GetFullCharge());
        strProtocol += ", from the log's first charge, " + Num(c->second.front(), 6) + " (below " +
                       Num(epuck2::models::sensors::kBatteryStartsFull) + ": not a full battery)";
      }
    }
    m_cOut.open(m_strLikeOut + ".part");
    if (!m_cOut) THROW_ARGOSEXCEPTION("epuck2_protocol: cannot write \"" << m_strLikeOut << ".part\"");
    m_cOut << epuck2::argos_replay::replay_head(m_sReplay, m_strRobot, strProtocol);
    if (m_strKind == "battery") {
      const Real v = std::abs(m_sReplay.col("speed_cm_s").front());
      Controller(0).SetWheels(-v, v);
    }
  }

  Real ReplayCell(const char* pch_column) const {
    const auto& n = m_sReplay.numeric;
    const auto it = n.find(pch_column);
    return it == n.end() ? 0.0 : it->second[m_unLikeRow];
  }

  void ReplayPreStep() {
    if (m_bDone || m_unLikeRow >= m_sReplay.rows()) return;
    if (m_strKind == "drive" && !m_bRunStarted) {
      /* The robot stands where the log's run starts: its ToF obstacle_distance_m from the obstacle */
      auto& s = m_vecRobots[0]->GetComponent<CEPuck2TOFEquippedEntity>("tof_sensor").GetSensor(0);
      Place(CurrentWall(), s.Offset, s.Direction, m_fObstacle);
      m_bRunStarted = true;
    }
    const UInt32 unSensor = static_cast<UInt32>(ReplayCell("sensor"));
    if (m_strKind == "proximity") {
      auto& s = m_vecRobots[0]->GetComponent<CProximitySensorEquippedEntity>("proximity_sensors").GetSensor(unSensor);
      Place(CurrentWall(), s.Offset, s.Direction, ReplayCell("distance_m"), ToRadians(CDegrees(ReplayCell("angle_deg"))).GetValue());
    } else if (m_strKind == "ground") {
      m_fReplayGrey = ReplayCell("grey");
    } else if (m_strKind == "light") {
      PlaceLightAt(unSensor, ReplayCell("distance_m"), ReplayCell("intensity"));
    } else if (m_strKind == "camera" && !m_bCameraSettled) {
      PlaceLedAt(CVector3(ReplayCell("forward_m"), ReplayCell("lateral_m"), ReplayCell("vertical_m")));
    }
  }

  void ReplayPostStep(CEPuck2RecorderController& c) {
    if (m_bDone) return;
    const std::size_t unRows = m_sReplay.rows();
    const UInt32 unSensor = static_cast<UInt32>(ReplayCell("sensor"));
    auto fnWrite = [&](std::map<std::string, std::string> m) {
      m_cOut << epuck2::argos_replay::replay_row(m_sReplay, m_unLikeRow, m);
      /* ARGoS against the log, per reading column (a column the log lacks is not compared) */
      for (const auto& [strColumn, strValue] : m) {
        const auto it = m_sReplay.numeric.find(strColumn);
        if (it == m_sReplay.numeric.end()) continue;
        m_mapReplayDiff[strColumn].push_back(std::stod(strValue) - it->second[m_unLikeRow]);
      }
      ++m_unLikeRow;
    };
    if (m_strKind == "proximity") {
      fnWrite({{"value", std::to_string(c.Proximity().at(unSensor))}});
    } else if (m_strKind == "ground") {
      fnWrite({{"value", std::to_string(c.Ground().at(unSensor))}});
    } else if (m_strKind == "light") {
      fnWrite({{"value", std::to_string(c.Light().at(unSensor))}});
    } else if (m_strKind == "camera") {
      /* The LED medium indexes the light a tick after it moved: one settling tick, then a frame */
      if (!m_bCameraSettled) {
        m_bCameraSettled = true;
        return;
      }
      m_bCameraSettled = false;
      const auto vecBlobs = c.Blobs();
      if (vecBlobs.size() != 1)
        THROW_ARGOSEXCEPTION(m_strLike << ":" << m_sReplay.line_of_row[m_unLikeRow] << ": ARGoS's camera sees "
                                       << vecBlobs.size() << " blobs of the LED at forward_m, lateral_m, vertical_m = "
                                       << ReplayCell("forward_m") << ", " << ReplayCell("lateral_m") << ", " << ReplayCell("vertical_m")
                                       << " (expected one: the LED outside its image?)");
      fnWrite({{"px", std::to_string(vecBlobs[0].first)}, {"py", std::to_string(vecBlobs[0].second)}});
    } else if (m_strKind == "drive" || m_strKind == "battery") {
      /* The first PostStep is the log's first time (where the encoders count from); each row is
         read at the tick nearest its time, and its commands (drive) or speed (battery) then hold
         until the next row */
      const UInt64 unClock = GetSpace().GetSimulationClock();
      if (m_unLikeRow == 0) {
        m_unLikeStart = unClock;
        m_nStartLeft = c.LeftSteps();
        m_nStartRight = c.RightSteps();
      }
      const auto& vecTime = m_sReplay.col("time_s");
      const Real fNow = vecTime.front() + static_cast<Real>(unClock - m_unLikeStart) * m_fTick;
      while (m_unLikeRow < unRows && vecTime[m_unLikeRow] <= fNow + m_fTick / 2) {
        if (m_strKind == "drive") {
          const Real fLeft = ReplayCell("left_speed_cm_s"), fRight = ReplayCell("right_speed_cm_s");
          fnWrite({{"left_steps", std::to_string(Wrap16(c.LeftSteps(), m_nStartLeft))},
                   {"right_steps", std::to_string(Wrap16(c.RightSteps(), m_nStartRight))},
                   {"tof_mm", std::to_string(c.Tof())}});
          c.SetWheels(fLeft, fRight);
        } else {
          const Real v = std::abs(ReplayCell("speed_cm_s"));
          fnWrite({{"charge", Num(c.Charge(), m_nChargeDigits)}});
          c.SetWheels(-v, v);
        }
      }
    }
    if (m_unLikeRow == unRows) FinishReplay();
  }

  /// The replay is renamed into place only when every row is written: whole or not at all.
  void FinishReplay() {
    m_cOut.close();
    if (!m_cOut || std::rename((m_strLikeOut + ".part").c_str(), m_strLikeOut.c_str()) != 0)
      THROW_ARGOSEXCEPTION("epuck2_protocol: cannot write \"" << m_strLikeOut << "\"");
    m_bDone = true;
    /* One line scripts/argos-record.sh prints: how far ARGoS's readings are from the log's */
    LOG << "[epuck2_protocol] replay: " << m_sReplay.rows() << " rows, ARGoS - log";
    for (auto& [strColumn, vecDiff] : m_mapReplayDiff) {
      Real fSum = 0, fSquares = 0;
      for (Real& f : vecDiff) {
        fSum += f;
        fSquares += f * f;
        f = std::abs(f);
      }
      std::sort(vecDiff.begin(), vecDiff.end());  // now |differences|: the median is robust to a few wild log rows
      const std::size_t n = vecDiff.size();
      const Real fMedian = n % 2 ? vecDiff[n / 2] : (vecDiff[n / 2 - 1] + vecDiff[n / 2]) / 2;
      LOG << "; " << strColumn << ": MSE " << Num(fSquares / n, 6) << ", mean " << Num(fSum / n, 4) << ", median |.| "
          << Num(fMedian, 4);
    }
    LOG << std::endl;
  }

  void BatteryStep(Real t) {
    bool bAll = true;
    const long tick = std::lround(t / m_fTick);
    const long period = std::lround(m_fPeriod / m_fTick);
    for (std::size_t i = 0; i < m_vecBattery.size(); ++i) {
      SBatteryRun& r = m_vecBattery[i];
      if (r.Done) continue;
      const Real q = Controller(i).Charge();
      if (tick == 1) *r.Out << "0," << Num(r.Speed) << ",1\n";  // full at t = 0
      if (q <= 0.0) {
        /* Stopped: the last row is the last tick with charge left (its time is the lifetime) */
        if (tick == 1 || std::lround(r.LastTime / m_fTick) % period != 0)
          *r.Out << Num(r.LastTime, 8) << ',' << Num(r.Speed) << ',' << Num(r.LastCharge, m_nChargeDigits) << '\n';
        r.Done = true;
        r.Out->close();
        Controller(i).SetWheels(0, 0);
        continue;
      }
      bAll = false;
      /* The speed as the discharge models see it: displacement, or rotation angle x 0.0265f */
      const SAnchor& sBody = m_vecRobots[i]->GetEmbodiedEntity().GetOriginAnchor();
      if (tick > 1) {
        Real fDelta = Distance(sBody.Position, r.OldPosition);
        CRadians cAngle;
        CVector3 cAxis;
        (r.OldOrientation.Inverse() * sBody.Orientation).ToAngleAxis(cAngle, cAxis);
        if (fDelta == 0.0 && cAngle.GetValue() != 0.0) fDelta = cAngle.GetValue() * 0.0265f;
        const Real fSpeed = std::round(std::max(0.0, std::min(0.150, fDelta / m_fTick)) * 10000.0) / 100.0;
        r.MinSpeed = std::min(r.MinSpeed, fSpeed);
        r.MaxSpeed = std::max(r.MaxSpeed, fSpeed);
      }
      r.OldPosition = sBody.Position;
      r.OldOrientation = sBody.Orientation;
      if (tick % period == 0) *r.Out << Num(t, 8) << ',' << Num(r.Speed) << ',' << Num(q, m_nChargeDigits) << '\n';
      r.LastTime = t;
      r.LastCharge = q;
    }
    m_bDone = bAll;
  }

  std::string m_strKind, m_strOutDir, m_strRobot;
  UInt32 m_unSamples = 20;
  Real m_fTick = 0.1;
  std::vector<CEPuck2Entity*> m_vecRobots;
  std::vector<Real> m_vecSteps, m_vecIntensities;
  std::size_t m_unStep = 0, m_unIntensity = 0;
  UInt32 m_unSample = 0, m_unLightSensor = 0, m_unRunTick = 0;
  bool m_bDone = false, m_bRunStarted = false;
  std::ofstream m_cOut;
  std::vector<std::unique_ptr<std::ofstream>> m_vecGroundOut;  ///< ground: robots 1.. (a swarm)
  std::vector<CVector3> m_vecCameraPoints;  ///< camera: the LED's positions in the camera's frame
  bool m_bCameraSettled = false;
  CLightEntity* m_pcLight = nullptr;
  Real m_fObstacle = 0.3, m_fTravel = 0.22, m_fPeriod = 10.0, m_fArc = -1.0, m_fRightWheel = 1.0;
  SInt32 m_nStartLeft = 0, m_nStartRight = 0;
  /* like=: the measured log replayed */
  std::string m_strLike, m_strLikeOut;
  std::size_t m_unLikeRow = 0;
  UInt64 m_unLikeStart = 0;
  int m_nChargeDigits = 6;
  /* like= for the other kinds: the log, and the grey of the floor under the current row */
  epuck2::argos_replay::ReplayLog m_sReplay;
  bool m_bReplay = false;
  std::map<std::string, std::vector<Real>> m_mapReplayDiff;  ///< per reading column: ARGoS - log, row by row
  Real m_fReplayGrey = 1.0;
  /* ground with black_below_x: the floor is black where x < m_fBlackBelowX */
  bool m_bBlackBelow = false;
  Real m_fBlackBelowX = 0;
  /* light with robot_yaw: the robot's yaw in degrees */
  Real m_fRobotYawDeg = 0;
  std::vector<SBatteryRun> m_vecBattery;
};

REGISTER_LOOP_FUNCTIONS(CEPuck2ProtocolLoopFunctions, "epuck2_protocol")

/// A floor of grey bands 0.1 m wide and nothing else: bench/argos_cost.sh's arena.
class CEPuck2BenchFloorLoopFunctions : public CLoopFunctions {
 public:
  CColor GetFloorColor(const CVector2& c_pos) override {
    const UInt8 v = static_cast<UInt8>(static_cast<int>(std::floor(c_pos.GetX() * 10.0)) * 37 & 0xFF);
    return CColor(v, v, v);
  }
};

REGISTER_LOOP_FUNCTIONS(CEPuck2BenchFloorLoopFunctions, "epuck2_bench_floor")

}  // namespace argos
