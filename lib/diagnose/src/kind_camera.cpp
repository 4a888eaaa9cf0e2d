// The diagnosis's camera kind: its base model and catalogue effects (see kinds.cpp).
#include "kind_common.hpp"

namespace epuck2::diagnose {

using namespace epuck2::fit;  // the engine (lib/fit)

namespace detail {
using namespace kinds_shared;  // the kinds' shared helpers
namespace {

// ---------------------------------------------------------------------------------------------
// camera: pinhole with square pixels, centre (80, 60), f = 80 / tan(h/2) (the plug-in's source);
// h free (fov_deg, 30 nominal). Catalogue: principal_offset, radial_distortion. Two residuals per
// row: px then py.
class Camera : public ProblemOf<Camera> {
 public:
  using BaseModel = s::CameraModel;
  explicit Camera(const std::vector<logs::Log>& logs) {
    std::vector<double> fw, lat, ver, axis, r2, image_row;
    for (const auto& log : logs) {
      const auto& f = log.col("forward_m");
      const auto& l = log.col("lateral_m");
      const auto& v = log.col("vertical_m");
      const auto& px = log.col("px");
      const auto& py = log.col("py");
      for (std::size_t i = 0; i < log.rows(); ++i) {
        // The image row the LED falls on (0 = top), as the plug-in's camera projects it: where in
        // the image, from the geometry, not the measured py (whose own noise its residual shares).
        double nominal_column = 0, nominal_row = 0;
        const s::CameraCoefficients plugin = s::plugin_camera();
        s::camera_projection(plugin.horizontal_fov_rad, plugin.cx_px, plugin.cy_px, s::kCameraWidth_px, f[i], l[i], v[i],
                             &nominal_column, &nominal_row);
        x_.push_back(l[i] / f[i]);
        z_.push_back(v[i] / f[i]);
        for (int a = 0; a < 2; ++a) {
          y.push_back(a == 0 ? px[i] : py[i]);
          row.push_back(rows);
          fw.push_back(f[i]);
          lat.push_back(l[i]);
          ver.push_back(v[i]);
          axis.push_back(a);
          r2.push_back(x_.back() * x_.back() + z_.back() * z_.back());
          image_row.push_back(nominal_row);
        }
        ++rows;
      }
    }
    // Nominal horizontal field of view: 30 deg (docs/diagnose.md; the plug-in's 18.5 deg
    // aperture on the diagonal gives 29.97 deg, the plug-in's source).
    constexpr double kNominalFov_deg = 30.0;
    fov_ = add_param(*this, "fov_deg", kNominalFov_deg, kNominalFov_deg, 1.0, 170.0);
    base_free = {fov_};
    ix_ = add_catalogue(*this, fx::camera_catalogue());
    dx_ = ix_[fx::camera::principal_offset][0][0];
    dy_ = ix_[fx::camera::principal_offset][1][0];
    covariates.emplace_back("forward_m", std::move(fw));
    covariates.emplace_back("lateral_m", std::move(lat));
    covariates.emplace_back("vertical_m", std::move(ver));
    covariates.emplace_back("axis", std::move(axis));
    covariates.emplace_back("radius2", std::move(r2));
    covariates.emplace_back("image_row", std::move(image_row));
  }
  /// A calibrated base: its field of view, centre and distortion.
  void set_base_model(const s::CameraModel& m) {
    set_base(*this, fov_, s::rad_to_deg(m.base.horizontal_fov_rad));
    set_base(*this, dx_, m.base.cx_px - s::kCameraWidth_px / 2.0);
    set_base(*this, dy_, m.base.cy_px - s::kCameraHeight_px / 2.0);
    set_base_effects(*this, ix_, m.distortion);
  }

  template <typename T>
  void eval(const T* p, T* out, std::size_t /*needed: every row is computed*/) const {
    s::CameraRadialDistortion<T> distortion;
    fill_effects(ix_, p, distortion);
    const T hfov_rad = p[fov_] * (s::kPi / 180.0);
    const T cx = s::kCameraWidth_px / 2.0 + p[dx_], cy = s::kCameraHeight_px / 2.0 + p[dy_];
    for (std::size_t i = 0; i < x_.size(); ++i)
      s::camera_projection(hfov_rad, cx, cy, s::kCameraWidth_px, 1.0, x_[i], z_[i], &out[2 * i], &out[2 * i + 1],
                           distortion);
  }

 private:
  std::vector<double> x_, z_;
  CatalogueIndex ix_;
  int fov_ = 0, dx_ = 0, dy_ = 0;
};

}  // namespace

std::unique_ptr<Problem> make_camera(const std::vector<logs::Log>& logs, const Options& options) {
  return with_base(std::make_unique<Camera>(logs), options);
}

}  // namespace detail
}  // namespace epuck2::diagnose
