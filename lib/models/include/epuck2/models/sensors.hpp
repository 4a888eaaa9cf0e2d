// E-Puck2 sensor models: proximity, ambient light, ground, time of flight, encoders and camera,
// the LEDs the camera sees, and ARGoS's uniform noise.
//
// Each model is written once:
//  * the formula a fit needs derivatives of (proximity polynomial, light inverse square, ground
//    gain/offset, camera projection) is a template on the scalar, with no branch on a parameter,
//    so that lib/fit evaluates the very same code with ceres::Jet;
//  * the run-time reading (clamp, noise, quantisation) is plain double and reproduces the E-Puck2
//    ARGoS plug-in's arithmetic (as in the plug-in's source, its sensor models, "plug-in
//    compatible") when given the plug-in's coefficients, and the project's fitted ones otherwise
//    (data/fitted/<kind>.json, loaded by lib/fit's sensors.hpp, or compile-time constants).
//
// Header-only, standard library only: an ARGoS plug-in or a simulator can include it. Units are in
// every name; angles in radians unless a name says _deg.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <string_view>
#include <vector>

namespace epuck2::models::sensors {

// =============================================================================================
// Noise: ARGoS's uniform noise in [-1, 1] times a level (the plug-in's source)
// =============================================================================================

/// A seedable source of uniform numbers in [0, 1) built from std::mt19937_64's bits (whose
/// output the C++ standard fixes, unlike the distributions): same seed, same numbers everywhere.
class UnitUniform {
 public:
  explicit UnitUniform(std::uint64_t seed) : engine_(seed) {}
  /// 53 random bits scaled to [0, 1).
  double operator()() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }

 private:
  std::mt19937_64 engine_;
};

/// ARGoS's uniform noise: level * Uniform(-1, 1). A level of 0 draws nothing (the plug-in only
/// draws when noise is enabled), so the random stream is untouched when noise is off.
/// `unit` is any functor returning uniform numbers in [0, 1) (e.g. UnitUniform).
template <class UnitRandom>
double uniform_noise(UnitRandom& unit, double level) {
  if (level == 0.0) return 0.0;
  return level * (2.0 * unit() - 1.0);
}

/// No noise: the functor to pass when noise is off.
struct NoNoise {
  double operator()() const { return 0.5; }
};

// =============================================================================================
// Geometry (the plug-in's source)
// =============================================================================================

inline constexpr int kProximityCount = 8;
inline constexpr int kGroundCount = 3;
/// Proximity and light sensor angles, index 0..7, from the plug-in's source (docs/logs.md;
/// index 0 front-right, clockwise, negative = right side). The paper's Table 3 lists 15, 50, 90,
/// 150, 210, 270, 310, 345 degrees instead.
inline constexpr std::array<double, kProximityCount> kProximityAngles_deg{-17, -50, -90, -150, 150, 90, 50, 17};
inline constexpr double kProximityRingRadius_m = 0.036;   ///< the plug-in's source
inline constexpr double kProximityElevation_m = 0.043;    ///< the plug-in's source
inline constexpr double kBodyRadius_m = 0.035;            ///< the plug-in's source
inline constexpr double kInterWheel_m = 0.053;            ///< the plug-in's source
inline constexpr double kWheelRadius_m = 0.0205;          ///< the plug-in's source
/// ToF sensor position in the robot frame (the plug-in's source).
inline constexpr std::array<double, 3> kTofPosition_m{0.032, 0.0, 0.036};
/// Ground sensors (x, y) in the robot frame, index 0 = right, 1 = centre, 2 = left (reference
/// section 1; docs/logs.md for the index order).
inline constexpr std::array<std::array<double, 2>, kGroundCount> kGroundPositions_m{
    {{0.03, -0.009}, {0.03, 0.0}, {0.03, 0.009}}};

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double deg_to_rad(double deg) { return deg * (kPi / 180.0); }
inline constexpr double rad_to_deg(double rad) { return rad * (180.0 / kPi); }

// =============================================================================================
// 1. Proximity (paper Eq. 1; the plug-in's source)
// =============================================================================================

/// The response v(d) = a d^2 + b d + c (normalised to 0..1) for d <= range, else 0.
struct ProximityCoefficients {
  double a_per_m2 = 0;
  double b_per_m = 0;
  double c = 0;
  double range_m = 0.05;  ///< the plug-in's source: the ray is 0.05 m long
};

/// The E-Puck2 plug-in's polynomial, fitted by the paper to the maxima (paper section 4.1.1;
/// the plug-in's source).
inline constexpr ProximityCoefficients kPluginProximity{197.8633, -30.47182, 1.011635, 0.05};
/// The E-Puck (v1) polynomial (Garattoni and Francesca; paper section 4.1.1; reference 2.1).
inline constexpr ProximityCoefficients kEpuck1Proximity{298.701, -36.8961, 1.08212, 0.05};
/// Full scale of a proximity and light reading: 12-bit ADC (the plug-in's source).
inline constexpr double kProximityFullScale_raw = 4095.0;

/// The polynomial of Eq. 1 without its clamp: p = {a, b, c}. What a fit adjusts.
template <typename T>
T proximity_polynomial(const T* abc, double distance_m) {
  return (abc[0] * distance_m + abc[1]) * distance_m + abc[2];
}

/// Normalised response without noise: clamp01(poly(d)) for d <= range, else 0.
inline double proximity_response(const ProximityCoefficients& k, double distance_m) {
  if (!(distance_m <= k.range_m)) return 0.0;  // also no hit (NaN/inf)
  const double abc[3] = {k.a_per_m2, k.b_per_m, k.c};
  return std::clamp(proximity_polynomial(abc, distance_m), 0.0, 1.0);
}

/// The plug-in's reading 0..4095: clamp01(poly(d)) (0 beyond range or no hit), + noise, then
/// round(v * 4095) clamped to [0, 4095]. `distance_m` = std::nullopt when the ray hit nothing.
template <class UnitRandom>
int proximity_reading(const ProximityCoefficients& k, std::optional<double> distance_m, double noise_level,
                      UnitRandom& unit) {
  double v = distance_m ? proximity_response(k, *distance_m) : 0.0;
  v += uniform_noise(unit, noise_level);
  return static_cast<int>(std::clamp(std::round(v * kProximityFullScale_raw), 0.0, kProximityFullScale_raw));
}
inline int proximity_reading(const ProximityCoefficients& k, std::optional<double> distance_m) {
  NoNoise none;
  return proximity_reading(k, distance_m, 0.0, none);
}

// =============================================================================================
// 2. Ambient light (paper Eq. 2; the plug-in's source)
// =============================================================================================

struct LightCoefficients {
  /// Eq. 2's gamma (m per intensity unit): each light adds (gamma I)^2 / d^2. The plug-in divides
  /// I by 13.3333333333333 (the plug-in's source), i.e. gamma = 0.075 (paper section 4.1.2).
  double gamma_m = 1.0 / 13.3333333333333;
  double range_m = 0.50;  ///< lights farther than this are ignored (the plug-in's source)
};
inline constexpr LightCoefficients kPluginLight{};

/// One light's contribution (gamma I / d)^2 to the normalised sum. What a fit adjusts.
template <typename T>
T light_contribution(const T& gamma_m, double intensity, double distance_m) {
  const T r = gamma_m * intensity / distance_m;
  return r * r;
}

/// Normalised reading without noise for one light: 1 - (gamma I / d)^2, the quantity Eq. 2
/// clamps (not clamped here: the fit uses it on unsaturated readings).
template <typename T>
T light_response(const T& gamma_m, double intensity, double distance_m) {
  return T(1.0) - light_contribution(gamma_m, intensity, distance_m);
}

/// A light as one sensor sees it: distance and intensity (occlusion is the caller's business).
struct LightSource {
  double distance_m = 0;
  double intensity = 0;
};

/// The plug-in's reading 0..4095 (4095 = dark): sum over lights with I > 0 within range of
/// (I/13.333)^2/d^2, + noise, reading = round((1 - sum) * 4095) clamped to [0, 4095].
template <class Lights, class UnitRandom>
int light_reading(const LightCoefficients& k, const Lights& lights, double noise_level, UnitRandom& unit) {
  double sum = 0.0;
  for (const LightSource& l : lights)
    if (l.intensity > 0 && l.distance_m <= k.range_m) sum += light_contribution(k.gamma_m, l.intensity, l.distance_m);
  sum += uniform_noise(unit, noise_level);
  return static_cast<int>(std::clamp(std::round((1.0 - sum) * kProximityFullScale_raw), 0.0, kProximityFullScale_raw));
}
inline int light_reading(const LightCoefficients& k, double intensity, double distance_m) {
  NoNoise none;
  const std::array<LightSource, 1> one{{{distance_m, intensity}}};
  return light_reading(k, one, 0.0, none);
}

// =============================================================================================
// 3. Ground (the plug-in's source)
// =============================================================================================

/// value = offset + gain * grey, grey in [0, 1] (0 = black). The plug-in has offset 0 and gain
/// 1023: it multiplies a 0..255 grey level by 4.011764706 = 1023/255 (the plug-in's source).
struct GroundCoefficients {
  double gain_raw = 1023.0;   ///< reading of white minus reading of black, raw counts
  double offset_raw = 0.0;    ///< reading over black (the paper's residual detections)
};
inline constexpr GroundCoefficients kPluginGround{};
inline constexpr double kGroundFullScale_raw = 1023.0;        ///< 10-bit reading (reference 2.3)
inline constexpr double kPluginGroundPerGreyLevel = 4.011764706;  ///< the plug-in's source

/// The noiseless response to a grey level in [0, 1]. What a fit adjusts.
template <typename T>
T ground_response(const T& gain_raw, const T& offset_raw, double grey) {
  return offset_raw + gain_raw * grey;
}

/// The plug-in's reading from a 0..255 grey level: grey * 4.011764706 + noise * 1023, rounded,
/// clamped to [0, 1023] (the plug-in's source).
template <class UnitRandom>
int ground_reading_plugin(double grey_level_0_255, double noise_level, UnitRandom& unit) {
  const double v = grey_level_0_255 * kPluginGroundPerGreyLevel + uniform_noise(unit, noise_level) * kGroundFullScale_raw;
  return static_cast<int>(std::clamp(std::round(v), 0.0, kGroundFullScale_raw));
}
inline int ground_reading_plugin(double grey_level_0_255) {
  NoNoise none;
  return ground_reading_plugin(grey_level_0_255, 0.0, none);
}

/// The reading from a grey in [0, 1] with given coefficients: offset + gain * grey + noise * 1023,
/// rounded, clamped. With kPluginGround it equals ground_reading_plugin(grey * 255) up to the
/// rounding of 4.011764706 against 1023/255.
template <class UnitRandom>
int ground_reading(const GroundCoefficients& k, double grey, double noise_level, UnitRandom& unit) {
  const double v = ground_response(k.gain_raw, k.offset_raw, grey) + uniform_noise(unit, noise_level) * kGroundFullScale_raw;
  return static_cast<int>(std::clamp(std::round(v), 0.0, kGroundFullScale_raw));
}
inline int ground_reading(const GroundCoefficients& k, double grey) {
  NoNoise none;
  return ground_reading(k, grey, 0.0, none);
}

// =============================================================================================
// 4. Time of flight (the plug-in's source)
// =============================================================================================

struct TofCoefficients {
  double range_m = 2.0;       ///< the plug-in's source: one 2.0 m ray
  double min_mm = 20.0;       ///< VL53L0X minimum (the plug-in's source and the e-puck2 firmware)
  double max_mm = 2000.0;     ///< the plug-in's source
  double scale = 1.0;         ///< measured = scale * true distance + offset (plug-in: 1, 0)
  double offset_mm = 0.0;
};
inline constexpr TofCoefficients kPluginTof{};

/// The noiseless reading in mm before rounding: scale * 1000 d + offset. What a fit adjusts.
template <typename T>
T tof_response_mm(const T& scale, const T& offset_mm, const T& distance_m) {
  return scale * distance_m * 1000.0 + offset_mm;
}

/// The plug-in's reading: hit distance (range if no hit) + noise * range, in mm rounded, clamped
/// to [20, 2000]. With non-default scale/offset the response is scale * d + offset first.
template <class UnitRandom>
int tof_reading_mm(const TofCoefficients& k, std::optional<double> hit_distance_m, double noise_level, UnitRandom& unit) {
  const double d_m = hit_distance_m && *hit_distance_m <= k.range_m ? *hit_distance_m : k.range_m;
  const double reading_m = tof_response_mm(k.scale, k.offset_mm, d_m) / 1000.0 + uniform_noise(unit, noise_level) * k.range_m;
  return static_cast<int>(std::clamp(std::round(reading_m * 1000.0), k.min_mm, k.max_mm));
}
inline int tof_reading_mm(const TofCoefficients& k, std::optional<double> hit_distance_m) {
  NoNoise none;
  return tof_reading_mm(k, hit_distance_m, 0.0, none);
}

// =============================================================================================
// 5. Encoders (the plug-in's source and the e-puck2 firmware; paper section 3.5)
// =============================================================================================

/// 1000 steps per wheel revolution over a 0.0205 m wheel radius: 1000 / (2 pi 0.0205) =
/// 7763.656 steps per metre (the plug-in's source; the source names it StepsPerCm).
inline constexpr double kPluginStepsPerMetre = 7763.656;
/// The firmware's MOTOR_SPEED_LIMIT (the plug-in's source and the e-puck2 firmware).
inline constexpr double kFirmwareSpeedLimit_steps_s = 1100.0;

struct EncoderCoefficients {
  double steps_per_m = kPluginStepsPerMetre;
};

/// One wheel's encoder register as the plug-in keeps it: a continuous count, wrapped to int16,
/// read as floor(count); partial steps are carried from tick to tick.
class Encoder {
 public:
  explicit Encoder(EncoderCoefficients k = {}) : k_(k) {}
  /// One tick: count += steps_per_m * v * dt + noise * 32767, then the int16 wrap.
  template <class UnitRandom>
  void tick(double wheel_speed_m_s, double dt_s, double noise_level, UnitRandom& unit) {
    count_ += k_.steps_per_m * wheel_speed_m_s * dt_s;
    count_ += uniform_noise(unit, noise_level) * kInt16Max;
    if (count_ >= kWrap) count_ -= 2 * kWrap;
    if (count_ < -kWrap) count_ += 2 * kWrap;
  }
  void tick(double wheel_speed_m_s, double dt_s) {
    NoNoise none;
    tick(wheel_speed_m_s, dt_s, 0.0, none);
  }
  /// The register: floor of the count (-32768..32767).
  int reading() const { return static_cast<int>(std::floor(count_)); }
  double count() const { return count_; }
  void set_count(double c) { count_ = c; }

 private:
  static constexpr double kInt16Max = 32767.0;  ///< the plug-in's noise scale
  static constexpr double kWrap = 32768.0;      ///< int16 range is [-32768, 32768)
  EncoderCoefficients k_;
  double count_ = 0.0;
};

/// Undoes the int16 wrap between consecutive register readings (steps moved between two samples
/// are assumed to be fewer than 32768).
inline double unwrap_steps(double previous_unwrapped, double reading) {
  const double prev_wrapped = previous_unwrapped - 65536.0 * std::floor((previous_unwrapped + 32768.0) / 65536.0);
  double delta = reading - prev_wrapped;
  if (delta > 32767.0) delta -= 65536.0;
  if (delta < -32768.0) delta += 65536.0;
  return previous_unwrapped + delta;
}

/// A register's readings unwrapped from the first, which is taken as is (the encoders read 0 at
/// time 0, docs/logs.md).
inline std::vector<double> unwrap_steps(const std::vector<double>& readings) {
  std::vector<double> out(readings.size());
  for (std::size_t i = 0; i < readings.size(); ++i) out[i] = i ? unwrap_steps(out[i - 1], readings[i]) : readings[i];
  return out;
}

// =============================================================================================
// 6. Camera (the plug-in's source; paper section 4.1.6)
// =============================================================================================

inline constexpr int kCameraWidth_px = 160;    ///< the plug-in's source
inline constexpr int kCameraHeight_px = 120;   ///< the plug-in's source
inline constexpr double kCameraAperture_deg = 18.5;  ///< plug-in since 2024-01-25 (reference 1)
inline constexpr double kCameraRange_m = 1.0;        ///< the plug-in's source; paper 4.1.6
inline constexpr double kCameraFocal_m = 0.035;      ///< the plug-in's source (cancels out)
/// Camera position in the robot frame (the plug-in's source).
inline constexpr std::array<double, 3> kCameraPosition_m{0.035, 0.0, 0.032};

/// ARGoS's aperture is the half-angle of the visibility cone on the image diagonal. The image
/// plane's width is 2 f tan(aperture) W / sqrt(W^2 + H^2), so the horizontal field of view is
/// 2 atan(W / sqrt(W^2 + H^2) tan(aperture)) (= 29.97 deg for 18.5 deg; the plug-in's source).
inline double horizontal_fov_from_aperture_rad(double aperture_rad, int width_px = kCameraWidth_px,
                                               int height_px = kCameraHeight_px) {
  const double w = width_px, h = height_px;
  return 2.0 * std::atan(w / std::sqrt(w * w + h * h) * std::tan(aperture_rad));
}
inline double aperture_from_horizontal_fov_rad(double hfov_rad, int width_px = kCameraWidth_px,
                                               int height_px = kCameraHeight_px) {
  const double w = width_px, h = height_px;
  return std::atan(std::tan(hfov_rad / 2.0) * std::sqrt(w * w + h * h) / w);
}

/// Pinhole camera with square pixels: focal length in pixels f = (W/2) / tan(hfov/2).
struct CameraCoefficients {
  double horizontal_fov_rad = 0;
  double cx_px = kCameraWidth_px / 2.0;   ///< image column of the optical axis
  double cy_px = kCameraHeight_px / 2.0;  ///< image row of the optical axis
  double range_m = kCameraRange_m;
  int width_px = kCameraWidth_px;
  int height_px = kCameraHeight_px;
};
inline CameraCoefficients plugin_camera() {
  CameraCoefficients c;
  c.horizontal_fov_rad = horizontal_fov_from_aperture_rad(deg_to_rad(kCameraAperture_deg));
  return c;
}

/// Projection of a point (forward x > 0, lateral y to the left, vertical z up, camera frame) to
/// pixel coordinates: px = cx - f y/x, py = cy - f z/x, f = (W/2)/tan(hfov/2). This is the
/// plug-in's i = -W/Wm (y f/x - Wm/2), j = -H/Hm (z f/x - Hm/2) (the plug-in's source) written with
/// the field of view and the image centre as the parameters. What a fit adjusts.
template <typename T>
void camera_projection(const T& hfov_rad, const T& cx_px, const T& cy_px, double width_px, double forward_m,
                       double lateral_m, double vertical_m, T* px, T* py) {
  using std::tan;
  const T f_px = T(width_px / 2.0) / tan(hfov_rad / 2.0);
  px[0] = cx_px - f_px * (lateral_m / forward_m);
  py[0] = cy_px - f_px * (vertical_m / forward_m);
}

/// The plug-in's visibility test: inside the cone of half-angle `aperture` about the axis and
/// nearer than the range along the axis (the plug-in's source).
inline bool camera_sees(double aperture_rad, double range_m, double forward_m, double lateral_m, double vertical_m) {
  const double norm = std::sqrt(forward_m * forward_m + lateral_m * lateral_m + vertical_m * vertical_m);
  if (!(forward_m > 0.0) || norm == 0.0) return false;
  return std::acos(forward_m / norm) < aperture_rad && forward_m < range_m;
}

/// The paper's Table 4 method: the horizontal field of view from one point at the image's edge
/// seen at a known geometry. An object at `forward` whose image lies `offset_px` from the centre
/// column and `lateral` from the axis gives tan(alpha/2) = (lateral/forward) (W/2)/offset_px.
/// With an object at the edge (offset W/2) seen across a width w at distance x this is
/// alpha = 2 atan(w / (2 x)), which reproduces Table 4's ARGoS rows and its first robot row.
inline double alpha_from_pixel_offset_rad(double forward, double lateral, double offset_px,
                                          int width_px = kCameraWidth_px) {
  return 2.0 * std::atan(std::abs(lateral / forward) * (width_px / 2.0) / std::abs(offset_px));
}

// =============================================================================================
// LEDs (paper Table 2; the plug-in's source)
// =============================================================================================

enum class LedColour { red, rgb, green };
inline constexpr std::string_view to_string(LedColour c) {
  switch (c) {
    case LedColour::red: return "red";
    case LedColour::rgb: return "rgb";
    case LedColour::green: return "green";
  }
  return "?";
}

struct Led {
  int number = 0;        ///< 1..10 as in Table 2
  LedColour colour = LedColour::red;
  bool on_ring = false;  ///< LEDs 1..8: on the ring at angle_deg; 9 and 10: no position given
  double angle_deg = 0;  ///< ring angle (LEDs 1..8)
};
inline constexpr double kLedRingRadius_m = 0.037;   ///< the plug-in's source
inline constexpr double kLedElevation_m = 0.048;    ///< the plug-in's source
/// Paper Table 2: 1..8 around the ring at 0, 45, ..., 315 deg (RED, RGB alternating), 9 the front
/// LED (red), 10 the body LED (green). The reference gives no position for 9 and 10.
inline constexpr std::array<Led, 10> kLeds{{{1, LedColour::red, true, 0},
                                            {2, LedColour::rgb, true, 45},
                                            {3, LedColour::red, true, 90},
                                            {4, LedColour::rgb, true, 135},
                                            {5, LedColour::red, true, 180},
                                            {6, LedColour::rgb, true, 225},
                                            {7, LedColour::red, true, 270},
                                            {8, LedColour::rgb, true, 315},
                                            {9, LedColour::red, false, 0},
                                            {10, LedColour::green, false, 0}}};

/// A ring LED's position in its robot's frame (x forward, y left, z up).
inline std::array<double, 3> led_position_m(const Led& led) {
  const double a = deg_to_rad(led.angle_deg);
  return {kLedRingRadius_m * std::cos(a), kLedRingRadius_m * std::sin(a), kLedElevation_m};
}

}  // namespace epuck2::models::sensors
