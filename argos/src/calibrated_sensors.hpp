// The `calibrated` implementations of the E-Puck2 plug-in's sensors. Each derives from the
// plug-in's own implementation (same control interface, same entities, same rays), reads its
// coefficients from a project coefficient file at Init, and computes its readings with
// epuck2::models::sensors; what is here is only the ARGoS plumbing (rays, floor, lights, wheels).
//
// XML (inside <sensors>):
//   <epuck2_proximity implementation="calibrated" coefficients="proximity.json" [robot="ID"]
//                     [curve="max|mean"] [noise="true|false"] [noise_distribution="gaussian|uniform"]
//                     [noise_level="0.05"] [show_rays="true"]/>
//   <epuck2_ground    implementation="calibrated" coefficients="ground.json" .../>
//   <epuck2_tof       implementation="calibrated" coefficients="drive.json" .../>
//   <epuck2_encoder   implementation="calibrated" coefficients="drive.json" .../>
//   <epuck2_light     implementation="calibrated" coefficients="light.json" .../>
//   <epuck2_colored_blob_perspective_camera implementation="calibrated" coefficients="camera.json"
//                     medium="leds" .../>
// Noise (noise="true", the default): the coefficient file's measured reading noise noise.<channel>
// (<channel> = proximity, ground, tof, encoder, light; sd in counts, mm or steps, per sensor where
// the file has per_sensor_sd), as a Gaussian of that sd, or with noise_distribution="uniform" as
// the plug-in's uniform noise of the same variance. A file without a noise section: the plug-in's
// uniform noise of the noise_level attribute (0: none), with a warning. noise="false": none.
#pragma once

#include <vector>

#include <argos3/plugins/robots/e-puck2/simulator/epuck2_colored_blob_perspective_camera_default_sensor.h>
#include <argos3/plugins/robots/e-puck2/simulator/epuck2_encoder_default_sensor.h>
#include <argos3/plugins/robots/e-puck2/simulator/epuck2_ground_rotzonly_sensor.h>
#include <argos3/plugins/robots/e-puck2/simulator/epuck2_light_default_sensor.h>
#include <argos3/plugins/robots/e-puck2/simulator/epuck2_proximity_default_sensor.h>
// The plug-in's ToF sensor header uses the ToF entity without including it.
#include <argos3/plugins/robots/e-puck2/simulator/epuck2_tof_equipped_entity.h>
#include <argos3/plugins/robots/e-puck2/simulator/epuck2_tof_default_sensor.h>

#include <epuck2/models/kinds.hpp>
#include <epuck2/models/sensors.hpp>

#include "argos_noise.hpp"
#include "calibrated_drive.hpp"

namespace argos {

class CEPuck2CalibratedProximitySensor : public CEPuck2ProximityDefaultSensor {
 public:
  void Init(TConfigurationNode& t_tree) override;
  void Update() override;
  /// Sensor 0's noiseless normalised response (the plug-in's virtual, kept meaningful).
  Real CalculateReading(Real f_distance) override;

 private:
  /// cos of the angle between `c_ray` and the normal of the surface it hit `f_distance` along it:
  /// ARGoS's ray query gives no normal, only the entity hit (`pc_hit`): for a box, the normal of
  /// the face hit from its position, orientation and size; for a cylinder, radial (or a cap's);
  /// for any other shape two more rays 1 mm beside it find the surface's plane through the three
  /// hits (1 when a side ray misses on both sides: an edge).
  Real CosIncidence(const CRay3& c_ray, Real f_distance, const CEmbodiedEntity* pc_hit);

  epuck2::models::sensors::ProximityModel m_sModel;
  bool m_bIncidence = false;        ///< the file's incidence_angle is not neutral: compute the angle
  std::vector<Real> m_vecRayScale;  ///< each ray stretched to where the model stops responding
  epuck2::argos_plugin::ArgosNoise m_cNoise;
};

class CEPuck2CalibratedGroundSensor : public CEPuck2GroundRotZOnlySensor {
 public:
  void Init(TConfigurationNode& t_tree) override;
  void Update() override;

 private:
  epuck2::models::sensors::GroundModel m_sModel;
  epuck2::argos_plugin::ArgosNoise m_cNoise;
};

class CEPuck2CalibratedTOFSensor : public CEPuck2TOFDefaultSensor {
 public:
  void SetRobot(CComposableEntity& c_entity) override;
  void Init(TConfigurationNode& t_tree) override;
  void Update() override;
  void Reset() override;

 private:
  const void* m_pcRobot = nullptr;
  epuck2::models::sensors::TofCoefficients m_sCoefficients;
  epuck2::argos_plugin::DelayLine m_cDelay;  ///< latency (a diagnosis's effects.latency.delay_s)
  Real m_fTime = 0;
  epuck2::argos_plugin::ArgosNoise m_cNoise;
};

class CEPuck2CalibratedEncoderSensor : public CEPuck2EncoderDefaultSensor {
 public:
  void SetRobot(CComposableEntity& c_entity) override;
  void Init(TConfigurationNode& t_tree) override;
  void Update() override;
  void Reset() override;

 private:
  const void* m_pcRobot = nullptr;
  epuck2::models::sensors::EncoderCoefficients m_sCoefficients;
  epuck2::models::sensors::Encoder m_cLeft, m_cRight;
  /// With the calibrated actuator: the wheels' travel it computes, counted by these registers
  std::shared_ptr<const epuck2::argos_plugin::CalibratedDrive> m_pcDrive;
  epuck2::argos_plugin::StepRegister m_cLeftRegister, m_cRightRegister;
  Real m_fLeftTravel = 0, m_fRightTravel = 0;  ///< the wheels' travel without the calibrated actuator, m
  epuck2::argos_plugin::ArgosNoise m_cNoise;
};

class CEPuck2CalibratedLightSensor : public CEPuck2LightDefaultSensor {
 public:
  void Init(TConfigurationNode& t_tree) override;
  void Update() override;

 private:
  epuck2::models::sensors::LightModel m_sModel;  ///< the file's model (each sensor's own gamma included)
  epuck2::argos_plugin::ArgosNoise m_cNoise;
};

/// The camera with the project's projection (lib/models camera.hpp): the fitted horizontal field
/// of view, the image centre at sub-pixel accuracy before rounding, radial distortion and the
/// calibrated pixel noise; LEDs found, seen and occluded as the plug-in's camera does.
class CEPuck2CalibratedCameraSensor : public CEPuck2ColoredBlobPerspectiveCameraDefaultSensor {
 public:
  void Init(TConfigurationNode& t_tree) override;
  void Update() override;

 private:
  epuck2::models::sensors::CameraModel m_sModel;
  Real m_fAperture = 0, m_fRange = 0;
  epuck2::argos_plugin::ArgosNoise m_cNoise;  ///< two channels: px, py (the same sd)
};

}  // namespace argos
