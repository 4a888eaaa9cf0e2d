// The facts of each kind of log that every part of the project needs alike: its name, the
// channels it measures (name, unit, the register's rails, full scale, sensors, their names, the
// quantity in words), and where its base model's coefficients may physically lie (with their
// units), which columns set a reading's conditions and which hold its readings, and how wild
// readings are screened. The coefficient files' noise sections, the validation of a model, the
// log reader's ranges, the screening, `simulate --like`, the reports and the figures read them
// here.
//
// Header-only, standard library only (epuck2::models).
#pragma once

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "epuck2/models/kinds.hpp"

namespace epuck2::models {

/// One measured quantity of a kind.
struct Channel {
  const char* name;     ///< the noise section's key in a coefficient file ("proximity", "tof", ...)
  const char* unit;     ///< "counts", "mm", "steps", "px", "charge"
  double low_rail;      ///< the register's lowest value (-inf: none)
  double high_rail;     ///< the register's highest value (+inf: none)
  double full_scale;    ///< a noise sd at or above this is not a reading's noise
  int sensors;          ///< how many sensors share the channel (a noise sd per sensor)
  const char* label;    ///< the quantity in words, for reports and figures ("ground sensor", "ToF")
  std::vector<const char*> sensor_names = {};  ///< each sensor's name where they have one (else numbered)
  /// Whether the register has rails (a reading there is censored).
  bool has_rails() const { return std::isfinite(low_rail) && std::isfinite(high_rail); }
  /// A reading as every fit reads it (docs/fitting.md, "Readings on a rail"): at or beyond a rail
  /// the rail itself (the reading is censored there), else the reading.
  double on_rails(double v) const { return v <= low_rail ? low_rail : v >= high_rail ? high_rail : v; }
  /// "0..1023": the register's range as reports and figures print it ("" without rails).
  std::string rails_text() const {
    if (!has_rails()) return "";
    char text[64];
    std::snprintf(text, sizeof text, "%g..%g", low_rail, high_rail);
    return text;
  }
};

/// One base coefficient of a kind's model: its key in a coefficient file's "parameters", unit and
/// physical range (open where `open` says so).
struct BaseParam {
  const char* key;
  const char* unit;
  double lower, upper;
  bool open_lower, open_upper;
};

/// How the screening (lib/diagnose screening.hpp, docs/fitting.md) finds a kind's wild readings.
struct Screening {
  enum class How {
    none,        ///< not screened
    replicates,  ///< a reading far from the others taken under the same conditions (KindFacts::conditions)
    spikes,      ///< a sequence: a reading far from the line through its two neighbours, on a row whose
                 ///< conditions (the commands) repeat the previous row's
  };
  How how = How::none;
  std::vector<const char*> readings = {};  ///< the columns screened, all of the first channel (its rails censor them)
  /// replicates: the smallest robust sd between replicates (a few counts of quantisation);
  /// spikes: the smallest deviation from the neighbours' line that is a spike. In the channel's unit.
  double floor = 0;
};

struct KindFacts {
  const char* name;
  std::vector<Channel> channels;
  std::vector<BaseParam> base;
  std::vector<const char*> columns;   ///< the columns every log of the kind has (docs/logs.md)
  std::vector<const char*> readings;  ///< those of them that hold the readings (a simulation replaces them)
  /// The columns that set a reading's conditions (a simulation sets itself up from them; optional
  /// ones such as angle_deg included): the same values, replicates of one reading.
  std::vector<const char*> conditions;
  /// Measured columns the kind's model does not simulate (a battery log's voltage_v): a simulated
  /// log leaves them out, since beside the simulated readings they would contradict them.
  std::vector<const char*> not_simulated;
  Screening screening;
  /// Sensor `k` of the first channel as reports name it: its name where the sensors have names
  /// ("0 (right)"), else its number.
  std::string sensor_name(std::size_t k) const {
    const Channel& c = channels.front();
    return k < c.sensor_names.size() ? std::string(c.sensor_names[k]) : std::to_string(k);
  }
  /// The base coefficient `key`, or nullptr.
  const BaseParam* base_param(const std::string& key) const {
    for (const BaseParam& p : base)
      if (key == p.key) return &p;
    return nullptr;
  }
};

/// The facts of the kind named `kind`; nullptr for another name.
inline const KindFacts* kind_facts(const std::string& kind) {
  namespace s = sensors;
  constexpr double inf = std::numeric_limits<double>::infinity();
  static const std::vector<KindFacts> all{
      {"proximity",
       {{"proximity", "counts", 0.0, s::kProximityFullScale_raw, s::kProximityFullScale_raw, s::kProximityCount, "proximity"}},
       {{"a", "1/m^2", -1e6, 1e6, false, false},
        {"b", "1/m", -1e5, 1e5, false, false},
        {"c", "1", -100.0, 100.0, false, false},
        {"range_m", "m", 0.0, 1.0, true, false}},
       {"distance_m", "sensor", "value"},
       {"value"},
       {"distance_m", "sensor", "angle_deg"},
       {},
       {Screening::How::replicates, {"value"}, 2.0}},
      {"light",
       {{"light", "counts", 0.0, s::kProximityFullScale_raw, s::kProximityFullScale_raw, s::kProximityCount, "light sensor"}},
       {{"gamma", "m", 0.0, 10.0, true, false}, {"range_m", "m", 0.0, 10.0, true, false}},
       {"distance_m", "intensity", "sensor", "value"},
       {"value"},
       {"distance_m", "intensity", "sensor"},
       {},
       {Screening::How::replicates, {"value"}, 2.0}},
      {"ground",
       {{"ground", "counts", 0.0, s::kGroundFullScale_raw, s::kGroundFullScale_raw, s::kGroundCount, "ground sensor",
         {"0 (right)", "1 (centre)", "2 (left)"}}},
       {{"gain", "counts", 0.0, 4.0 * s::kGroundFullScale_raw, true, false},
        {"offset", "counts", -s::kGroundFullScale_raw, s::kGroundFullScale_raw, false, false}},
       {"grey", "sensor", "value"},
       {"value"},
       {"grey", "sensor"},
       {},
       {Screening::How::replicates, {"value"}, 2.0}},
      {"camera",
       {{"camera", "px", -inf, inf, static_cast<double>(s::kCameraWidth_px), 1, "LED image position"}},
       {{"fov_deg", "deg", 0.0, 180.0, true, true},
        {"cx_px", "px", 0.0, static_cast<double>(s::kCameraWidth_px), false, false},
        {"cy_px", "px", 0.0, static_cast<double>(s::kCameraHeight_px), false, false}},
       {"forward_m", "lateral_m", "vertical_m", "px", "py"},
       {"px", "py"},
       {"forward_m", "lateral_m", "vertical_m"},
       {},
       {Screening::How::replicates, {"px", "py"}, 1.0}},
      {"drive",
       {{"tof", "mm", s::kPluginTof.min_mm, s::kPluginTof.max_mm, s::kPluginTof.max_mm, 1, "ToF"},
        {"encoder", "steps", -inf, inf, 65536.0, 1, "wheel encoder"}},
       // Steps per metre within 20 % of the plug-in's (docs/fitting.md: wheels are not that far off).
       {{"steps_per_m", "steps/m", 0.8 * s::kPluginStepsPerMetre, 1.2 * s::kPluginStepsPerMetre, false, false}},
       {"time_s", "left_speed_cm_s", "right_speed_cm_s", "left_steps", "right_steps", "tof_mm"},
       {"left_steps", "right_steps", "tof_mm"},
       {"left_speed_cm_s", "right_speed_cm_s"},
       {},
       // A ToF spike of at least 50 mm: well above the VL53L0X's few mm of noise (docs/fitting.md).
       {Screening::How::spikes, {"tof_mm"}, 50.0}},
      {"battery",
       {{"charge", "charge", -1.0, 1.05, 1.0, 1, "charge"}},
       {},
       {"time_s", "speed_cm_s", "charge"},
       {"charge"},
       {"speed_cm_s"},
       {"voltage_v"},
       {Screening::How::none}},
  };
  for (const KindFacts& k : all)
    if (kind == k.name) return &k;
  return nullptr;
}

}  // namespace epuck2::models
