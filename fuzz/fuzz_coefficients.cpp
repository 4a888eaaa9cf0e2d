// libFuzzer target: the coefficient file's one owner, lib/coefficients (read_model_file for every
// kind, which reads a path). Input: byte 0 picks the kind (0 proximity, 1 light, 2 ground,
// 3 camera, 4 drive, 5 battery; other values wrap), the rest is the file, written to a per-process
// temporary file. Contract checked: the reader returns or throws std::runtime_error (InputError is
// one); any other exception (a raw nlohmann::json exception, std::out_of_range...) or a crash is a
// finding; and a model that was read writes back and reads back to the same JSON (round_trip).
// With EPUCK2_FUZZ_FINITE=1 in the environment, a reader that returns a non-finite coefficient
// (JSON numbers such as 1e999 parse as infinity) aborts too.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <string>

#include <nlohmann/json.hpp>

#include "epuck2/coefficients/model_file.hpp"

namespace {

using namespace epuck2;

const std::string& temp_path() {
  static const std::string path = "/tmp/epuck2_fuzz_coefficients_" + std::to_string(::getpid()) + ".json";
  return path;
}

bool strict_finite() {
  static const bool strict = [] {
    const char* v = std::getenv("EPUCK2_FUZZ_FINITE");
    return v && v[0] == '1';
  }();
  return strict;
}

void finite(std::initializer_list<double> values) {
  if (!strict_finite()) return;
  for (double v : values)
    if (!std::isfinite(v)) {
      std::fprintf(stderr, "fuzz_coefficients: a reader returned a non-finite coefficient\n");
      std::abort();
    }
}

}  // namespace

/// The property of the one coefficient-file owner (lib/coefficients): a model that was read
/// writes back (or the write refuses, std::domain_error), and what is written reads back to the
/// same file, byte for byte of its JSON. Anything else is a finding.
template <class Model, class FromJson>
void round_trip(const Model& m, FromJson from_json) {
  nlohmann::json written;
  try {
    written = coefficients::model_to_json(m);
  } catch (const std::domain_error&) {
    return;  // the writer refuses a value it cannot write
  }
  try {
    const Model back = from_json(written, "round-trip.json", "");
    if (coefficients::model_to_json(back) != written) {
      std::fprintf(stderr, "fuzz_coefficients: a model read back differs from what was written:\n%s\n", written.dump().c_str());
      std::abort();
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_coefficients: what the writer wrote does not read back (%s):\n%s\n", e.what(), written.dump().c_str());
    std::abort();
  }
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const int pick = data[0] % 6;
  const std::string content(reinterpret_cast<const char*>(data + 1), size - 1);
  namespace s = epuck2::models::sensors;
  namespace co = epuck2::coefficients;
  try {
    {
      std::ofstream out(temp_path(), std::ios::binary | std::ios::trunc);
      out.write(content.data(), static_cast<std::streamsize>(content.size()));
    }
    switch (pick) {
      case 0: {
        const auto m = co::read_model_file<s::ProximityModel>(temp_path());
        finite({m.base.a_per_m2, m.base.b_per_m, m.base.c});
        round_trip(m, co::proximity_model_from_json);
        break;
      }
      case 1: {
        const auto m = co::read_model_file<s::LightModel>(temp_path());
        finite({m.base.gamma_m});
        round_trip(m, co::light_model_from_json);
        break;
      }
      case 2: {
        const auto m = co::read_model_file<s::GroundModel>(temp_path());
        for (const auto& g : m.sensors) finite({g.gain_raw, g.offset_raw});
        round_trip(m, co::ground_model_from_json);
        break;
      }
      case 3: {
        const auto m = co::read_model_file<s::CameraModel>(temp_path());
        finite({m.base.horizontal_fov_rad, m.base.cx_px, m.base.cy_px});
        round_trip(m, co::camera_model_from_json);
        break;
      }
      case 4: {
        const auto m = co::read_model_file<s::DriveModel>(temp_path());
        finite({m.steps_per_m, m.effects.tof_scale.k, m.effects.tof_offset.offset_mm, m.effects.slip.tau_s});
        round_trip(m, co::drive_model_from_json);
        break;
      }
      case 5: {
        const auto m = co::read_model_file<s::BatteryModel>(temp_path());
        for (std::size_t k = 0; k < m.tables.cubic.size(); ++k)
          finite({m.tables.cubic[k].a, m.tables.cubic[k].b, m.tables.cubic[k].c, m.tables.cubic[k].d, m.tables.lifetime_s[k],
                  m.tables.linear_slope_per_s[k]});
        round_trip(m, co::battery_model_from_json);
        break;
      }
    }
  } catch (const std::runtime_error&) {
    // The documented failure: a message naming the file (and, for a model, the line and column).
  }
  return 0;
}
