// A controller that holds the latest readings of whatever E-Puck2 sensors its XML lists and
// drives the wheels as told. The protocol loop functions (protocol_loop_functions.cpp) decide
// what the robot does and write the logs; the controller only reads sensors through the
// plug-in's control interfaces, so any implementation (default or calibrated) can be recorded.
#pragma once

#include <utility>
#include <vector>

#include <argos3/core/control_interface/ci_controller.h>
#include <argos3/plugins/robots/e-puck2/control_interface/ci_epuck2_encoder_sensor.h>
#include <argos3/plugins/robots/e-puck2/control_interface/ci_epuck2_ground_sensor.h>
#include <argos3/plugins/robots/e-puck2/control_interface/ci_epuck2_light_sensor.h>
#include <argos3/plugins/robots/e-puck2/control_interface/ci_epuck2_proximity_sensor.h>
#include <argos3/plugins/robots/e-puck2/control_interface/ci_epuck2_tof_sensor.h>
#include <argos3/plugins/robots/generic/control_interface/ci_battery_sensor.h>
#include <argos3/plugins/robots/generic/control_interface/ci_colored_blob_perspective_camera_sensor.h>
#include <argos3/plugins/robots/generic/control_interface/ci_differential_steering_actuator.h>

namespace argos {

class CEPuck2RecorderController : public CCI_Controller {
 public:
  void Init(TConfigurationNode& t_node) override;
  void ControlStep() override;
  void Reset() override { m_fLeft = m_fRight = 0; }

  /// Wheel speeds in cm/s, given to the actuator at once: they drive the next physics step
  /// (and every ControlStep keeps them).
  void SetWheels(Real f_left_cm_s, Real f_right_cm_s);
  Real LeftCmS() const { return m_fLeft; }
  Real RightCmS() const { return m_fRight; }

  std::vector<SInt32> Proximity() const;
  std::vector<SInt32> Ground() const;
  std::vector<SInt32> Light() const;
  SInt32 Tof() const;
  SInt32 LeftSteps() const;
  SInt32 RightSteps() const;
  Real Charge() const;
  /// The camera's blobs (x, y in pixels), when the controller has the camera (enabled at Init).
  std::vector<std::pair<SInt32, SInt32>> Blobs() const;

 private:
  CCI_DifferentialSteeringActuator* m_pcWheels = nullptr;
  CCI_EPuck2ProximitySensor* m_pcProximity = nullptr;
  CCI_Epuck2GroundSensor* m_pcGround = nullptr;
  CCI_EPuck2LightSensor* m_pcLight = nullptr;
  CCI_EPuck2TOFSensor* m_pcTof = nullptr;
  CCI_EPuck2EncoderSensor* m_pcEncoder = nullptr;
  CCI_BatterySensor* m_pcBattery = nullptr;
  CCI_ColoredBlobPerspectiveCameraSensor* m_pcCamera = nullptr;
  Real m_fLeft = 0, m_fRight = 0;
};

}  // namespace argos
