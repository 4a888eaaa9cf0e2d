#include "recorder_controller.hpp"

namespace argos {

void CEPuck2RecorderController::Init(TConfigurationNode& t_node) {
  /* Optional constant wheel speeds (cm/s), e.g. for the cost bench: <params left="5" right="4"/> */
  GetNodeAttributeOrDefault(t_node, "left", m_fLeft, m_fLeft);
  GetNodeAttributeOrDefault(t_node, "right", m_fRight, m_fRight);
  if (HasActuator("differential_steering"))
    m_pcWheels = GetActuator<CCI_DifferentialSteeringActuator>("differential_steering");
  if (HasSensor("epuck2_proximity")) m_pcProximity = GetSensor<CCI_EPuck2ProximitySensor>("epuck2_proximity");
  if (HasSensor("epuck2_ground")) m_pcGround = GetSensor<CCI_Epuck2GroundSensor>("epuck2_ground");
  if (HasSensor("epuck2_light")) m_pcLight = GetSensor<CCI_EPuck2LightSensor>("epuck2_light");
  if (HasSensor("epuck2_tof")) m_pcTof = GetSensor<CCI_EPuck2TOFSensor>("epuck2_tof");
  if (HasSensor("epuck2_encoder")) m_pcEncoder = GetSensor<CCI_EPuck2EncoderSensor>("epuck2_encoder");
  if (HasSensor("epuck2_battery")) m_pcBattery = GetSensor<CCI_BatterySensor>("epuck2_battery");
  if (HasSensor("epuck2_colored_blob_perspective_camera")) {
    m_pcCamera = GetSensor<CCI_ColoredBlobPerspectiveCameraSensor>("epuck2_colored_blob_perspective_camera");
    m_pcCamera->Enable();  // the camera starts disabled
  }
}

void CEPuck2RecorderController::ControlStep() {
  if (m_pcWheels) m_pcWheels->SetLinearVelocity(m_fLeft, m_fRight);
}

void CEPuck2RecorderController::SetWheels(Real f_left_cm_s, Real f_right_cm_s) {
  m_fLeft = f_left_cm_s;
  m_fRight = f_right_cm_s;
  if (m_pcWheels) m_pcWheels->SetLinearVelocity(m_fLeft, m_fRight);
}

std::vector<SInt32> CEPuck2RecorderController::Proximity() const {
  std::vector<SInt32> v;
  if (m_pcProximity)
    for (const auto& r : m_pcProximity->GetReadings()) v.push_back(r.Value);
  return v;
}
std::vector<SInt32> CEPuck2RecorderController::Ground() const {
  return m_pcGround ? m_pcGround->GetReadings() : std::vector<SInt32>{};
}
std::vector<SInt32> CEPuck2RecorderController::Light() const {
  std::vector<SInt32> v;
  if (m_pcLight)
    for (const auto& r : m_pcLight->GetReadings()) v.push_back(r.Value);
  return v;
}
SInt32 CEPuck2RecorderController::Tof() const { return m_pcTof ? m_pcTof->GetReading() : 0; }
SInt32 CEPuck2RecorderController::LeftSteps() const { return m_pcEncoder ? m_pcEncoder->GetReadings().EncoderLeftWheel : 0; }
SInt32 CEPuck2RecorderController::RightSteps() const { return m_pcEncoder ? m_pcEncoder->GetReadings().EncoderRightWheel : 0; }
Real CEPuck2RecorderController::Charge() const { return m_pcBattery ? m_pcBattery->GetReading().AvailableCharge : 0.0; }

std::vector<std::pair<SInt32, SInt32>> CEPuck2RecorderController::Blobs() const {
  std::vector<std::pair<SInt32, SInt32>> v;
  if (m_pcCamera)
    for (const auto* b : m_pcCamera->GetReadings().BlobList) v.emplace_back(b->X, b->Y);
  return v;
}

REGISTER_CONTROLLER(CEPuck2RecorderController, "epuck2_recorder_controller")

}  // namespace argos
