// The facts of each kind of log that every part of the project needs alike: its name, the
// channels it measures (name, unit, the register's rails, full scale, sensors, their names, the
// quantity in words), and where its base model's coefficients may physically lie (with their
// units), which columns set a reading's conditions and which hold its readings, and how wild
// readings are screened. The coefficient files' noise sections, the validation of a model, the
// log reader's ranges, the screening, `simulate --like`, the reports and the figures read them
// here: each column's physical range, a column that may stand in for a required one, the required
// metadata, the distances a unit check compares with, and the words of a column on a figure's axis.
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

/// "0..1023": a register's range as reports, figures and the log reader's messages print it.
inline std::string rails_text(double low, double high) {
  char text[64];
  std::snprintf(text, sizeof text, "%g..%g", low, high);
  return text;
}

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
  std::string rails_text() const { return has_rails() ? models::rails_text(low_rail, high_rail) : ""; }
  /// The unit as a figure's axis gives a reading's, where it is not "unit, rails" (a charge is a
  /// fraction of the full charge, with no register behind it); nullptr: "unit, rails".
  const char* axis_unit = nullptr;
};

/// A log column's physical range (docs/logs.md, "Ranges"): the log reader refuses a value outside.
struct ColumnRange {
  const char* column;
  double lo, hi;
  std::string what;      ///< what the reader says it expected ("a grey level in [0, 1]")
  bool integer = false;  ///< whole numbers only (a sensor index, an encoder count)
  /// A reading at or above this is the sensor's code, kept as read (the ToF's "no target in
  /// range"); +inf: none.
  double code_from = std::numeric_limits<double>::infinity();
  bool in_range(double v) const { return v >= code_from || (v >= lo && v <= hi); }
};

/// A column a log may carry instead of a required one (a battery log's voltage_v for charge).
struct StandIn {
  const char* required;
  const char* instead;
};

/// A metadata line a log of the kind must have (`# key: VALUE` before the header), with its range.
struct RequiredMetadata {
  const char* key;
  const char* placeholder;  ///< the value as the message shows it ("D")
  double lo, hi;
  const char* what;         ///< what a value must be ("a distance >= 0 m and <= 1000 m")
};

/// How far the kind's sensor sees, for the check that distances are in metres (lib/calibrate
/// plausibility.hpp): a distance_m far beyond it was written in another unit. sees_to_m 0: none.
struct DistanceCheck {
  const char* sensor = nullptr;  ///< the sensor in the message ("proximity sensor")
  double sees_to_m = 0;
};

/// A column's words on a figure's axis where they differ by kind (the drive's distance_m is the
/// distance travelled, the light's the distance to the light).
struct ColumnWords {
  const char* column;
  const char* words;
  const char* brief = "";  ///< a reading's quantity in a word, in a page's y label where a figure has several
};

/// A `sensor` column's range: an index 0..sensors-1, whole (`kind` names the sensor in the message).
inline ColumnRange sensor_index_range(const char* kind, int sensors) {
  return {"sensor", 0, sensors - 1.0, std::string("a ") + kind + " sensor index 0.." + std::to_string(sensors - 1), true};
}
/// A `value` column's range: a raw register reading between its rails.
inline ColumnRange raw_reading_range(double low_rail, double high_rail) {
  return {"value", low_rail, high_rail, "a raw reading " + rails_text(low_rail, high_rail)};
}

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
  std::vector<ColumnRange> ranges;           ///< the kind's columns' ranges (the reader adds time_s and distance_m)
  std::vector<StandIn> stand_ins = {};
  std::vector<RequiredMetadata> metadata = {};
  DistanceCheck distances = {};
  std::vector<ColumnWords> axis_words = {};  ///< a column's words on a figure's axis, where the kind has its own
  /// A coefficient file of the kind: its sections beside the common ones (kind, parameters,
  /// effects, noise, robots), e.g. the battery's tables or the light's per-sensor fits (a robot's
  /// set may hold those of them the calibration fits per robot: per_sensor), and the keys of its
  /// `parameters` beside the base coefficients and the parameter-home effects (lib/coefficients).
  std::vector<const char*> file_sections = {};
  std::vector<const char*> file_parameters = {};
  /// The range of `column`, or nullptr.
  const ColumnRange* range(const std::string& column) const {
    for (const ColumnRange& r : ranges)
      if (column == r.column) return &r;
    return nullptr;
  }
  /// The words of `column` on a figure's axis for this kind, or nullptr.
  const ColumnWords* words_of(const std::string& column) const {
    for (const ColumnWords& w : axis_words)
      if (column == w.column) return &w;
    return nullptr;
  }
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

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
/// The facts of the kind named `kind`; nullptr for another name.
inline const KindFacts* kind_facts(const std::string& kind) {
  namespace s = sensors;
  constexpr double inf = std::numeric_limits<double>::infinity();
  // Built kind by kind: one braced list this size makes GCC 12 (-O3) warn falsely of a use after
  // free; and of a vector maybe used uninitialised, whichever way it is built (the pragma above).
  static const std::vector<KindFacts> all = [] {
    std::vector<KindFacts> v;
    v.reserve(6);
    v.push_back(KindFacts{"proximity",
       {{"proximity", "counts", 0.0, s::kProximityFullScale_raw, s::kProximityFullScale_raw, s::kProximityCount, "proximity"}},
       {{"a", "1/m^2", -1e6, 1e6, false, false},
        {"b", "1/m", -1e5, 1e5, false, false},
        {"c", "1", -100.0, 100.0, false, false},
        {"range_m", "m", 0.0, 1.0, true, false}},
       {"distance_m", "sensor", "value"},
       {"value"},
       {"distance_m", "sensor", "angle_deg"},
       {},
       {Screening::How::replicates, {"value"}, 2.0},
       {sensor_index_range("proximity", s::kProximityCount), raw_reading_range(0.0, s::kProximityFullScale_raw),
        {"angle_deg", -90, 90, "an incidence angle in [-90, 90] degrees"}},
       {},
       {},
       {"proximity sensor", s::kPluginProximity.range_m}});
    // The proximity calibration's curve of the means (proximity_report.cpp).
    v.back().file_parameters = {"mean_a", "mean_b", "mean_c"};
    v.push_back(KindFacts{"light",
       {{"light", "counts", 0.0, s::kProximityFullScale_raw, s::kProximityFullScale_raw, s::kProximityCount, "light sensor"}},
       {{"gamma", "m", 0.0, 10.0, true, false}, {"range_m", "m", 0.0, 10.0, true, false}},
       {"distance_m", "intensity", "sensor", "value"},
       {"value"},
       {"distance_m", "intensity", "sensor"},
       {},
       {Screening::How::replicates, {"value"}, 2.0},
       // The model divides by the distance (gamma intensity / d): 0 or a subnormal overflows it.
       {{"distance_m", 1e-3, 1e3, "a distance from the light source in [0.001, 1000] m"},
        sensor_index_range("light", s::kProximityCount), raw_reading_range(0.0, s::kProximityFullScale_raw),
        {"intensity", 0, 1e6, "an intensity in [0, 1e6]"}},
       {},
       {},
       {"light sensor (the plug-in's range)", s::kPluginLight.range_m},
       {{"distance_m", "distance to the light (mm)"}}});
    // A light calibration's per-sensor fits (lib/calibrate light_report.cpp; in a robot's set too).
    v.back().file_sections = {"per_sensor"};
    v.push_back(KindFacts{"ground",
       {{"ground", "counts", 0.0, s::kGroundFullScale_raw, s::kGroundFullScale_raw, s::kGroundCount, "ground sensor",
         {"0 (right)", "1 (centre)", "2 (left)"}}},
       {{"gain", "counts", 0.0, 4.0 * s::kGroundFullScale_raw, true, false},
        {"offset", "counts", -s::kGroundFullScale_raw, s::kGroundFullScale_raw, false, false}},
       {"grey", "sensor", "value"},
       {"value"},
       {"grey", "sensor"},
       {},
       {Screening::How::replicates, {"value"}, 2.0},
       {sensor_index_range("ground", s::kGroundCount), raw_reading_range(0.0, s::kGroundFullScale_raw),
        {"grey", 0, 1, "a grey level in [0, 1]"}}});
    v.push_back(KindFacts{"camera",
       {{"camera", "px", -inf, inf, static_cast<double>(s::kCameraWidth_px), 1, "LED image position"}},
       {{"fov_deg", "deg", 0.0, 180.0, true, true},
        {"cx_px", "px", 0.0, static_cast<double>(s::kCameraWidth_px), false, false},
        {"cy_px", "px", 0.0, static_cast<double>(s::kCameraHeight_px), false, false}},
       {"forward_m", "lateral_m", "vertical_m", "px", "py"},
       {"px", "py"},
       {"forward_m", "lateral_m", "vertical_m"},
       {},
       {Screening::How::replicates, {"px", "py"}, 1.0},
       // An LED beyond a kilometre is no camera observation; the projection f y/x stays finite.
       {{"forward_m", 1e-12, 1e3, "a forward distance in (0, 1000] m"},
        {"lateral_m", -1e3, 1e3, "a lateral position in [-1000, 1000] m"},
        {"vertical_m", -1e3, 1e3, "a vertical position in [-1000, 1000] m"},
        {"px", 0, s::kCameraWidth_px - 1.0, "a pixel column 0.." + std::to_string(s::kCameraWidth_px - 1)},
        {"py", 0, s::kCameraHeight_px - 1.0, "a pixel row 0.." + std::to_string(s::kCameraHeight_px - 1)}},
       {},
       {},
       {},
       // Two readings a row, the LED's image column and row: a diagnosis figure's two panels.
       {{"px", "LED image column px", "column"}, {"py", "LED image row py", "row"}}});
    // The image size and range, and the ARGoS aperture from the field of view (camera_report.cpp).
    v.back().file_parameters = {"aperture_deg", "width_px", "height_px", "range_m"};
    v.push_back(KindFacts{"drive",
       {{"tof", "mm", s::kPluginTof.min_mm, s::kPluginTof.max_mm, s::kPluginTof.max_mm, 1, "ToF"},
        {"encoder", "steps", -inf, inf, 65536.0, 1, "wheel encoder"}},
       // Steps per metre within 20 % of the plug-in's (docs/fitting.md: wheels are not that far off).
       {{"steps_per_m", "steps/m", 0.8 * s::kPluginStepsPerMetre, 1.2 * s::kPluginStepsPerMetre, false, false}},
       {"time_s", "left_speed_cm_s", "right_speed_cm_s", "left_steps", "right_steps", "tof_mm"},
       {"left_steps", "right_steps", "tof_mm"},
       {"left_speed_cm_s", "right_speed_cm_s"},
       {},
       // A ToF spike of at least 50 mm: well above the VL53L0X's few mm of noise (docs/fitting.md).
       {Screening::How::spikes, {"tof_mm"}, 50.0},
       // The encoders' 16-bit registers; the ToF between its rails, or its "no target" code.
       {{"left_steps", -32768, 32767, "a 16-bit encoder count -32768..32767", true},
        {"right_steps", -32768, 32767, "a 16-bit encoder count -32768..32767", true},
        {"tof_mm", s::kPluginTof.min_mm, s::kPluginTof.max_mm,
         "a ToF reading " + rails_text(s::kPluginTof.min_mm, s::kPluginTof.max_mm) + " mm, or >= " +
             std::to_string(static_cast<int>(s::kTofOutOfRangeCode_mm)) + " (no target in range)",
         false, s::kTofOutOfRangeCode_mm},
        {"left_speed_cm_s", -1e3, 1e3, "a speed in [-1000, 1000] cm/s"},
        {"right_speed_cm_s", -1e3, 1e3, "a speed in [-1000, 1000] cm/s"}},
       {},
       {{"obstacle_distance_m", "D", 0.0, 1e3, "a distance >= 0 m and <= 1000 m"}},
       {},
       {{"speed_cm_s", "speed measured by the encoders (cm/s)"},
        {"distance_m", "distance travelled from the start (mm; negative: backwards)"}}});
    v.push_back(KindFacts{"battery",
       {{"charge", "charge", -1.0, 1.05, 1.0, 1, "charge", {}, "fraction of full charge"}},
       {},
       {"time_s", "speed_cm_s", "charge"},
       {"charge"},
       {"speed_cm_s"},
       {"voltage_v"},
       // A discharge run is a sequence, as a drive run: a charge spike of at least 0.1 from the
       // line through its neighbours (well above a gauge's ~0.01 of noise, and above the start's
       // drop from full to the curve's intercept, which is halved in that line) is wild; the
       // calibration leaves out the same readings by their distance from the speed's cubic
       // (docs/fitting.md).
       {Screening::How::spikes, {"charge"}, 0.1},
       {{"speed_cm_s", -1e3, 1e3, "a speed in [-1000, 1000] cm/s"},
        {"charge", -1.0, 1.05, "a normalised charge in [-1, 1.05]"},
        {"voltage_v", 0.0, 10.0, "a voltage in [0, 10] V"}},
       // A voltage-only log, as real robots report (its charge from a voltage->charge map).
       {{"charge", "voltage_v"}}});
    // Its coefficient file's tables (lib/calibrate battery_json.cpp).
    v.back().file_sections = {"battery_model", "speeds", "simple"};
    return v;
  }();
  for (const KindFacts& k : all)
    if (kind == k.name) return &k;
  return nullptr;
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

}  // namespace epuck2::models
