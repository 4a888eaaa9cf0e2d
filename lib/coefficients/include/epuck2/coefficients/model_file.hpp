// A coefficient file as a model (lib/models kinds.hpp), for every kind, calibration files and
// diagnosis files alike (docs/coefficient-files.md):
//   "parameters": the base model's coefficients under the names the calibration writes, and the
//                 effects whose home is the parameters (the drive's tof_offset_mm, tof_scale,
//                 slip_time_constant_s); battery files have their tables instead
//                 (battery_tables.hpp) and "battery_model";
//   "effects":    {"NAME": {PARAM: value or [per sensor]}} for the catalogue's effects of the kind
//                 (lib/models effects.hpp, the one registry), and {"covariate:COLUMN": {"slope",
//                 "centre"}};
//   "noise":      {"CHANNEL": {"sd", "per_sensor_sd", "unit", ...}}: the reading noise;
//   "robots":     {"ID": {"parameters", "noise"}}: one robot's set, read over the pooled one when
//                 asked for; every set is validated whichever is read.
// Every other key must be one the calibrations or the diagnosis write for people
// (docs/coefficient-files.md, "Unknown keys"); an unknown one is refused, with "did you mean".
// Reading validates everything: a value outside its physical range (the registry's for an
// effect, the kind's for a base coefficient), a noise sd that is not finite or reaches full
// scale, an unknown effect or parameter name (with "did you mean"), a file of another kind. Every
// error is a logs::InputError at FILE:LINE:COLUMN naming the JSON path (the file is read again to
// find the line; an in-memory document gives the JSON path alone).
// Writing refuses (std::domain_error) a model that a reader would refuse, with the reader's reason:
// what is written always reads back.
#pragma once

#include <nlohmann/json.hpp>

#include <limits>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "epuck2/coefficients/battery_tables.hpp"
#include "epuck2/models/kinds.hpp"

namespace epuck2::coefficients {

namespace s = models::sensors;

/// The model of a coefficient file `j` read from `path`. With a non-empty `robot`, that robot's
/// set (`robots.<robot>`) replaces the pooled parameters and noise it has (an error when the file
/// has no such robot).
s::ProximityModel proximity_model_from_json(const nlohmann::json& j, const std::string& path, const std::string& robot = "");
/// Which of a proximity calibration's curves: Eq. 1 fitted to the maxima (a, b, c) or to the
/// means (mean_a, mean_b, mean_c; the same ranges).
enum class ProximityCurve { maxima, means };
s::ProximityModel proximity_model_from_json(const nlohmann::json& j, const std::string& path, const std::string& robot,
                                            ProximityCurve curve);
/// A light model: the pooled gamma (`parameters.gamma`) and a calibration's per-sensor fits
/// (`per_sensor[i]`: {"sensor": 0..7, "gamma"}; a robot's set its own list, never the file's, and
/// without one its gamma on every sensor) as `sensor_gamma_m`, each in gamma's physical range, one
/// entry per sensor at most.
s::LightModel light_model_from_json(const nlohmann::json& j, const std::string& path, const std::string& robot = "");
s::GroundModel ground_model_from_json(const nlohmann::json& j, const std::string& path, const std::string& robot = "");
s::CameraModel camera_model_from_json(const nlohmann::json& j, const std::string& path, const std::string& robot = "");
s::DriveModel drive_model_from_json(const nlohmann::json& j, const std::string& path, const std::string& robot = "");
/// Whether a drive calibration file's cap test found the wheels beat the e-puck2 firmware's cap
/// (`firmware_cap.kept` false): its wheels run uncapped (DriveModel::firmware_cap false, and so in
/// ARGoS, where a file without a `firmware_cap` section keeps the firmware's cap).
bool firmware_cap_refuted(const nlohmann::json& j);
/// A battery coefficient file (`epuck2-fit battery -o`) or a battery diagnosis report: its tables,
/// `battery_model` (default cubic), its effects and noise (a calibration file without `noise`:
/// the RMS of its speeds' `noise_sd`).
s::BatteryModel battery_model_from_json(const nlohmann::json& j, const std::string& path, const std::string& robot = "");
/// The same for a file with tables at some speeds only: the plug-in's tables elsewhere
/// (battery_tables.hpp), `sources` saying which are the file's.
s::BatteryModel battery_model_from_json(const nlohmann::json& j, const std::string& path, const std::string& robot,
                                        TableSources& sources);

/// A JSON file as parsed, its errors located: logs::InputError at FILE:LINE:COLUMN for a file that
/// cannot be opened, text that is not JSON, or a number too large for a double (1e999).
nlohmann::json read_json_file(const std::string& path);

/// The same, reading the file `path` (errors located in it).
template <class Model>
Model read_model_file(const std::string& path, const std::string& robot = "");

/// A model of any kind (lib/models kinds.hpp): what a caller that serves every kind holds, so that
/// it chooses the kind's model once, here, and runs it through overloads (std::visit) rather than
/// switching on the kind itself.
using AnyModel = std::variant<s::ProximityModel, s::LightModel, s::GroundModel, s::CameraModel, s::DriveModel, s::BatteryModel>;
/// The kind of a model ("proximity", ...: lib/models kind_facts.hpp's names).
std::string kind_of(const AnyModel& m);
/// The model of the coefficient file `j` read from `path`, of the kind `kind`: the reader above of
/// that kind (errors as theirs; a file of another kind is one). Throws std::invalid_argument for
/// a name that is no kind.
AnyModel model_from_json(const std::string& kind, const nlohmann::json& j, const std::string& path,
                         const std::string& robot = "");
/// The kind's model as the plug-in publishes it (every effect neutral, no noise). Throws
/// std::invalid_argument for a name that is no kind.
AnyModel plugin_model(const std::string& kind);

/// The robots a file has a set for (`robots`' keys), in the file's order.
std::vector<std::string> robot_ids(const nlohmann::json& j);

/// {"kind", "parameters", "effects" (non-neutral ones only), "noise"; light: "per_sensor" for the
/// sensors with their own gamma}: what the readers above read
/// back to the same model, bit for bit (a camera's field of view to the ulp: it is written in
/// degrees, and some radians have no exact degrees; what is read back then writes the same text).
/// Each runs the readers' validation on what it writes: a model a reader would refuse (a noise sd
/// at full scale, a centre outside the image, a coefficient outside its range, a camera image other
/// than 160x120 px) is refused with std::domain_error and the reader's reason.
nlohmann::json model_to_json(const s::ProximityModel& m);
nlohmann::json model_to_json(const s::LightModel& m);
nlohmann::json model_to_json(const s::GroundModel& m);
nlohmann::json model_to_json(const s::CameraModel& m);
nlohmann::json model_to_json(const s::DriveModel& m);
/// {"kind", "battery_model", "speeds", "simple" (the tables), "effects", "noise"}.
nlohmann::json model_to_json(const s::BatteryModel& m);

/// What a calibration file holds beside its model, for calibration_model_json.
struct CalibrationExtras {
  /// Each noise channel's sd over all its readings together, as the calibration measured it
  /// (channel -> sd), written as the channel's `sd`; a channel of several sensors then has
  /// `per_sensor_sd`, the model's, always (a reader reads those). A channel not given: as
  /// model_to_json writes it.
  std::map<std::string, double> pooled_sd;
  /// A camera's field of view as the calibration fitted it, in degrees: written as `fov_deg` when
  /// it reads back to the model's radians exactly (else std::domain_error); NaN: the degrees
  /// model_to_json writes.
  double fov_deg = std::numeric_limits<double>::quiet_NaN();
};

/// The model sections of a calibration file (`epuck2-fit KIND -o`, and each robot's set of it):
/// {"kind", "parameters", "noise"} as model_to_json writes them for the same model (the same
/// function: every key one the readers read and check), reshaped as a calibration holds them:
/// no `effects` section when no effect is on (a calibration fits the base model), each noise
/// channel with `extras.pooled_sd`, and what the kind's calibration holds fixed or derives: the
/// proximity's and light's `range_m`, the camera's `range_m`, `width_px`, `height_px` and
/// `aperture_deg` (from fov_deg). The proximity's adds the second curve, Eq. 1 fitted to the
/// means, as `mean_a`, `mean_b`, `mean_c` (`means`' base; read with ProximityCurve::means).
/// What is written reads back (std::domain_error otherwise, with the reader's reason); the
/// calibration adds its report fields (std_errors, mse, observations, the noise's `from`, `n`,
/// ...: docs/coefficient-files.md, "Informational keys") around it.
nlohmann::json calibration_model_json(const s::ProximityModel& maxima, const s::ProximityModel& means, const CalibrationExtras& extras);
nlohmann::json calibration_model_json(const s::LightModel& m, const CalibrationExtras& extras);
nlohmann::json calibration_model_json(const s::GroundModel& m, const CalibrationExtras& extras);
nlohmann::json calibration_model_json(const s::CameraModel& m, const CalibrationExtras& extras);
nlohmann::json calibration_model_json(const s::DriveModel& m, const CalibrationExtras& extras);

/// Writes robot `id`'s set into the calibration file `j` of the kind `kind`: `robots.<id>` =
/// `set`, whose `parameters` and `noise` are calibration_model_json's for that robot's model
/// (its other keys, std_errors, logs, usable, why, not_identifiable, are report fields). The file is then read for that robot (every set is
/// validated whichever is read): a set a reader would refuse is std::domain_error, with the
/// reader's reason, and `j` is left as it was.
void add_robot_set(nlohmann::json& j, const std::string& kind, const std::string& id, const nlohmann::json& set);

/// The camera's range of the file `j` (`parameters.range_m`, the robot's set first), read and
/// checked as camera_model_from_json reads it; none when the file has no range (a simulator then
/// keeps its own, the plug-in's 1 m by default).
std::optional<double> camera_range_m(const nlohmann::json& j, const std::string& path, const std::string& robot = "");

/// The noise section of one channel: {"sd", "per_sensor_sd" (when the sensors differ), "unit"};
/// sd is the root mean square of the sensors' (computed without overflow). Throws
/// std::domain_error for an sd that is negative or not finite.
nlohmann::json noise_json(const std::vector<double>& per_sensor_sd, const std::string& unit);

}  // namespace epuck2::coefficients
