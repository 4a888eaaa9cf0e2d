// Camera: the plug-in's pinhole projection and visibility test.
// Header-only, standard library only (epuck2::models); units in every name, angles in radians
// unless a name says _deg. Umbrella: sensors.hpp.
#pragma once

#include <array>
#include <cmath>

#include "epuck2/models/geometry.hpp"

namespace epuck2::models::sensors {

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

/// radial_distortion, distortion_k2, distortion_k3 (docs/diagnose.md; OpenCV's k1, k2, k3): with
/// x = lateral/forward, y = vertical/forward and r^2 = x^2 + y^2, both are scaled by
/// (1 + k1 r^2 + k2 r^4 + k3 r^6) before projection. All 0: the pinhole.
template <typename T = double>
struct CameraRadialDistortion {
  T k1 = T(0.0);
  T k2 = T(0.0);
  T k3 = T(0.0);
};

/// Projection of a point (forward x > 0, lateral y to the left, vertical z up, camera frame) to
/// pixel coordinates: px = cx - f y/x, py = cy - f z/x, f = (W/2)/tan(hfov/2). This is the
/// plug-in's i = -W/Wm (y f/x - Wm/2), j = -H/Hm (z f/x - Hm/2) (the plug-in's source) written with
/// the field of view and the image centre as the parameters, with radial distortion (neutral by
/// default). A principal offset (docs/diagnose.md's principal_offset) is a centre (cx, cy) other
/// than (W/2, H/2). What a fit adjusts.
template <typename T>
void camera_projection(const T& hfov_rad, const T& cx_px, const T& cy_px, double width_px, double forward_m,
                       double lateral_m, double vertical_m, T* px, T* py,
                       const CameraRadialDistortion<T>& distortion = CameraRadialDistortion<T>{}) {
  using std::tan;
  const T f_px = T(width_px / 2.0) / tan(hfov_rad / 2.0);
  const double x = lateral_m / forward_m, y = vertical_m / forward_m;
  const double r2 = x * x + y * y;
  // Left to right: at k2 = k3 = 0 the added terms are exact zeros, the k1-only scale bit for bit.
  const T scale = 1.0 + distortion.k1 * r2 + distortion.k2 * (r2 * r2) + distortion.k3 * (r2 * r2 * r2);
  px[0] = cx_px - f_px * x * scale;
  py[0] = cy_px - f_px * y * scale;
}

/// The plug-in's visibility test: inside the cone of half-angle `aperture` about the axis and
/// nearer than the range along the axis (the plug-in's source).
inline bool camera_sees(double aperture_rad, double range_m, double forward_m, double lateral_m, double vertical_m) {
  const double norm = std::sqrt(forward_m * forward_m + lateral_m * lateral_m + vertical_m * vertical_m);
  if (!(forward_m > 0.0) || norm == 0.0) return false;
  return std::acos(forward_m / norm) < aperture_rad && forward_m < range_m;
}

/// Whether the camera reports an LED whose image falls at (px, py) (sub-pixel, noise included):
/// the position rounded to a pixel must lie in the image, columns 0..W-1 and rows 0..H-1; a blob
/// off the image is dropped (the project's ARGoS camera, argos/src/calibrated_sensors.cpp; the log
/// format has no "not seen": a log lists only the LEDs the camera reported, docs/logs.md). A
/// position that is not finite is left to the caller to refuse (true here).
inline bool camera_image_holds(double px, double py, int width_px = kCameraWidth_px, int height_px = kCameraHeight_px) {
  if (!std::isfinite(px) || !std::isfinite(py)) return true;
  const double x = std::round(px), y = std::round(py);
  return x >= 0.0 && y >= 0.0 && x <= width_px - 1.0 && y <= height_px - 1.0;
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

}  // namespace epuck2::models::sensors
