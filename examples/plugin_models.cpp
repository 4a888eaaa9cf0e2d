// The fitted models as an ARGoS plug-in (or any simulator) uses them: every kind's model from the
// header `epuck2-fit codegen` writes (epuck2::fitted::<kind>_model(), battery_tables()), run by
// lib/models (kinds.hpp, battery.hpp). It links epuck2::models and epuck2::fitted only: no JSON,
// no Ceres. docs/plugin-models.md ("Using the models from an ARGoS plug-in") quotes the part between the
// [readme] marks (tests/test_docs.cpp checks the quote). CTest runs it (example_plugin_models) and
// examples/check_plugin_models.py checks every number it prints against data/fitted/<kind>.json by
// the documented formulas.
//
// Output: one `name = value` a line; *_mean are the model's expected readings (before noise and
// rounding), *_reading the register a robot would report, with the fitted noise.
#include <cstdio>

// [readme]
#include "epuck2/fitted/coefficients.hpp"  // epuck2-fit codegen data/fitted/*.json -o ...
#include "epuck2/models/battery.hpp"       // battery::step
#include "epuck2/models/kinds.hpp"         // mean_raw, mean_px, reading, DriveSimulation
#include "epuck2/models/noise.hpp"         // StandardNormal

namespace fitted = epuck2::fitted;
namespace s = epuck2::models::sensors;
namespace b = epuck2::models::battery;

int main() {
  s::StandardNormal normal(42);      // one seeded source for every reading's noise
  auto no_noise = [] { return 0.0; };  // the expected register: the model's noise left out

  // Proximity sensor 0, a surface 2 cm away, facing it (cos of the incidence angle 1).
  const s::ProximityModel proximity = fitted::proximity_model();
  std::printf("proximity_mean = %.12g\n", s::mean_raw(proximity, 0, 0.02));
  std::printf("proximity_reading = %d\n", s::reading(proximity, 0, 0.02, 1.0, normal));

  // Light sensor 0, a light of intensity 1 (ARGoS units) 20 cm away.
  const s::LightModel light = fitted::light_model();
  std::printf("light_mean = %.12g\n", s::mean_raw(light, 0, 1.0, 0.20));
  std::printf("light_reading = %d\n", s::reading(light, 0, 1.0, 0.20, normal));

  // Ground sensor 1 (centre) over a mid-grey floor (0 black, 1 white).
  const s::GroundModel ground = fitted::ground_model();
  std::printf("ground_mean = %.12g\n", s::mean_raw(ground, 1, 0.5));
  std::printf("ground_reading = %d\n", s::reading(ground, 1, 0.5, normal));

  // Camera: an LED 50 cm ahead, 5 cm to the left, 2 cm up; its image column and row.
  const s::CameraModel camera = fitted::camera_model();
  const auto px = s::mean_px(camera, 0.50, 0.05, 0.02);
  std::printf("camera_px_mean = %.12g\ncamera_py_mean = %.12g\n", px[0], px[1]);
  const auto led = s::reading(camera, 0.50, 0.05, 0.02, normal);
  std::printf("camera_px_reading = %d\ncamera_py_reading = %d\n", led[0], led[1]);

  // Drive: both wheels at 5 cm/s from rest towards an obstacle 30 cm ahead, a sample every 0.1 s.
  s::DriveSimulation drive(fitted::drive_model(), 0.30);
  for (int k = 0; k <= 10; ++k) {
    const auto r = drive.sample(0.1 * k, 5.0, 5.0, no_noise);
    std::printf("drive_tof_mm_%d = %d\ndrive_left_steps_%d = %d\n", k, r.tof_mm, k, r.left_steps);
  }

  // Battery: the corrected Cubic at 5 cm/s (0.5 cm per 0.1 s tick) from a full charge, one hour.
  double charge = 1.0;
  for (int tick = 1; tick <= 36000; ++tick) {
    charge = b::step(b::Model::cubic, b::Behaviour::corrected, fitted::battery_tables(), charge, 0.005, 0.1);
    if (tick == 1 || tick == 600 || tick == 36000) std::printf("battery_charge_%d = %.12g\n", tick, charge);
  }
}
// [readme]
