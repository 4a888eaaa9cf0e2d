// The virtual robot's camera protocol (paper section 4.1.6): an LED placed at known positions in
// the camera frame, across the field of view and at several depths; the log records where its blob
// appears in the 160x120 image. data/raw/camera/README.md documents the imperfections (field of
// view wider than the plug-in's, optical axis off the image centre and different per robot,
// centroid jitter, whole pixels, a centroid now and then jumping to a reflection).
#include <algorithm>
#include <cmath>

#include "epuck2/logs/output.hpp"
#include "epuck2/models/sensors.hpp"
#include "epuck2/virtual_robot/reference_logs.hpp"
#include "epuck2/virtual_robot/sensor_truth.hpp"

namespace epuck2::virtual_robot {

std::vector<GeneratedFile> camera_logs(const CameraTruth& truth, std::uint64_t seed) {
  namespace s = models::sensors;
  const double hfov = s::deg_to_rad(truth.horizontal_fov_deg);
  const double aperture = s::aperture_from_horizontal_fov_rad(hfov);
  const double half_w = std::tan(hfov / 2.0);                                        // lateral/forward at the edge
  const double half_h = half_w * s::kCameraHeight_px / static_cast<double>(s::kCameraWidth_px);  // square pixels
  std::vector<GeneratedFile> files;
  for (std::size_t r = 0; r < truth.robot_cx_shift_px.size(); ++r) {
    Gaussian noise(seed + 4000 + 100 * r);
    WildReadings wild(seed + 4500 + 100 * r, truth.wild_fraction);
    const double cx = truth.cx_px + truth.robot_cx_shift_px[r];
    logs::LogWriter w({"forward_m", "lateral_m", "vertical_m", "px", "py"});
    w.comment("Synthetic log recorded by epuck2-fit's virtual robot (see README.md); not a real robot.");
    w.metadata("robot", robot_id(r));
    w.metadata("seed", std::to_string(seed));
    for (double x : truth.depths_m) {
      for (int c = 0; c < truth.columns; ++c) {
        // Lateral positions from 90 % of the right edge to 90 % of the left edge.
        const double fc = truth.columns > 1 ? -0.9 + 1.8 * c / (truth.columns - 1) : 0.0;
        for (int row = 0; row < truth.rows; ++row) {
          const double fr = truth.rows > 1 ? -0.8 + 1.6 * row / (truth.rows - 1) : 0.0;
          // LED positions on a 5 mm grid, as a user would place and measure them.
          const double y = std::round(fc * half_w * x * 200.0) / 200.0;
          const double z = std::round(fr * half_h * x * 200.0) / 200.0;
          if (!s::camera_sees(aperture, s::kCameraRange_m, x, y, z)) continue;
          for (int f = 0; f < truth.frames; ++f) {
            double px, py;
            s::camera_projection(hfov, cx, truth.cy_px, s::kCameraWidth_px, x, y, z, &px, &py);
            px = whole_count(px + noise() * truth.pixel_noise_px, s::kCameraWidth_px - 1.0);
            py = whole_count(py + noise() * truth.pixel_noise_px, s::kCameraHeight_px - 1.0);
            // A reflection: the blob detector's centroid lands anywhere in the image.
            double wild_px, wild_py;
            const bool jumped = wild.next(0.0, s::kCameraWidth_px - 1.0, true, &wild_px);
            wild.next(0.0, s::kCameraHeight_px - 1.0, true, &wild_py);
            if (jumped) px = wild_px, py = wild_py;
            w.row({x, y, z, px, py});
          }
        }
      }
    }
    files.push_back({"camera_" + robot_id(r) + ".csv", w.str()});
  }
  return files;
}

std::vector<GeneratedFile> camera_reference_logs(std::uint64_t seed) { return camera_logs(CameraTruth{}, seed); }

}  // namespace epuck2::virtual_robot
