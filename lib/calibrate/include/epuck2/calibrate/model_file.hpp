// A coefficient file as a model (lib/models kinds.hpp): its `parameters` are the base model's
// coefficients under the names the calibration writes (docs/coefficient-files.md), its optional
// `effects` the diagnosis catalogue's effects under their catalogue names (docs/diagnose.md), and
// its optional `noise` the reading noise per channel. A calibration file is a model without
// effects; `diagnose -o` writes the extended model the same way; `simulate KIND --like`,
// `codegen` and the ARGoS plug-in read either.
//
//   "parameters": {"a": .., "b": .., "c": .., "range_m": 0.05}            proximity
//                 {"gamma": .., "range_m": 0.5}                            light
//                 {"gain": [3 counts], "offset": [3 counts]}               ground
//                 {"fov_deg": .., "cx_px": .., "cy_px": ..}                camera
//                 {"steps_per_m": .., "tof_offset_mm": .., "tof_scale": .., "slip_time_constant_s": ..}  drive
//   battery: no `parameters`: its tables as a battery coefficient file has them (`speeds`,
//            `simple`; battery_json.hpp) and the discharge model, "battery_model": "cubic"
//   "effects":    {"ambient_offset": {"offset": ..}, "sensor_gain": {"gains": [8]},
//                  "long_tail": {"amplitude": .., "length_m": ..}, "incidence_angle": {"k": ..},
//                  "saturation": {"level": ..}}                            proximity
//                 {"ambient_offset": {"offset": ..}, "falloff_exponent": {"exponent": ..},
//                  "sensor_gain": {"gains": [8]}}                          light
//                 {"nonlinear_response": {"exponent": ..}}                 ground
//                 {"radial_distortion": {"k1": ..}}                        camera
//                 {"speed_limit": {"max_cm_s": ..}, "accel_limit": {"accel_cm_s2": ..},
//                  "speed_scale": {"k": ..}, "latency": {"delay_s": ..}}   drive
//                 {"capacity_scale": {"k": ..}}                            battery
//                 {"covariate:NAME": {"slope": .., "centre": ..}}          every kind (drive: the ToF)
//   "noise":      {"<channel>": {"sd": .., "per_sensor_sd": [..], "unit": ..}}  proximity, light,
//                  ground (counts), camera (px), tof (mm), encoder (steps), charge (battery; a
//                  battery calibration file without it: the RMS of its speeds' `noise_sd`)
//
// Readers take the parsed JSON and the file's name for messages; a missing or mistyped key throws
// std::runtime_error naming the file and the key.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "epuck2/models/kinds.hpp"

namespace epuck2::calibrate {

models::sensors::ProximityModel proximity_model_from_json(const nlohmann::json& j, const std::string& path);
models::sensors::LightModel light_model_from_json(const nlohmann::json& j, const std::string& path);
models::sensors::GroundModel ground_model_from_json(const nlohmann::json& j, const std::string& path);
models::sensors::CameraModel camera_model_from_json(const nlohmann::json& j, const std::string& path);
models::sensors::DriveModel drive_model_from_json(const nlohmann::json& j, const std::string& path);
/// A battery coefficient file (`epuck2-fit battery -o`) or a battery diagnosis report (`diagnose
/// -o`): its tables (errors: logs::InputError naming the entry), `battery_model` (default cubic),
/// its effects and noise.
models::sensors::BatteryModel battery_model_from_json(const nlohmann::json& j, const std::string& path);

/// {"kind", "parameters", "effects" (non-neutral ones only), "noise"}: what the readers above read
/// back to the same model.
nlohmann::json model_to_json(const models::sensors::ProximityModel& m);
nlohmann::json model_to_json(const models::sensors::LightModel& m);
nlohmann::json model_to_json(const models::sensors::GroundModel& m);
nlohmann::json model_to_json(const models::sensors::CameraModel& m);
nlohmann::json model_to_json(const models::sensors::DriveModel& m);
/// {"kind", "battery_model", "speeds", "simple" (the tables as battery_tables_to_json), "effects",
/// "noise"}.
nlohmann::json model_to_json(const models::sensors::BatteryModel& m);

}  // namespace epuck2::calibrate
