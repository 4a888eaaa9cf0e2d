// libFuzzer target: the coefficient-file readers (lib/fit sensors.hpp load_*_coefficients, which
// take a path, and battery_json.hpp battery_tables_from_json). Input: byte 0 picks the reader
// (0 proximity, 1 light, 2 ground, 3 camera, 4 drive, 5 battery; other values wrap), the rest is the
// file. The sensor loaders read a file: the input is written to a per-process temporary file.
// Contract checked: the readers return or throw std::runtime_error (InputError is one); any other
// exception (a raw nlohmann::json exception, std::out_of_range...) or a crash is a finding.
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

#include "epuck2/calibrate/battery_json.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/coefficients/model_file.hpp"

namespace {

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

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const int pick = data[0] % 6;
  const std::string content(reinterpret_cast<const char*>(data + 1), size - 1);
  namespace fit = epuck2::fit;
  try {
    if (pick == 5) {
      nlohmann::json j;
      try {
        j = nlohmann::json::parse(content);
      } catch (const nlohmann::json::exception&) {
        // Not JSON, or a number out of double's range (out_of_range.406): the caller parses the
        // text, so that is the caller's business, not this reader's.
        return 0;
      }
      const auto t = coefficients::battery_tables_from_json(j, "fuzz.json");
      for (std::size_t s = 0; s < t.cubic.size(); ++s)
        finite({t.cubic[s].a, t.cubic[s].b, t.cubic[s].c, t.cubic[s].d, t.lifetime_s[s], t.linear_slope_per_s[s]});
      return 0;
    }
    {
      std::ofstream out(temp_path(), std::ios::binary | std::ios::trunc);
      out.write(content.data(), static_cast<std::streamsize>(content.size()));
    }
    switch (pick) {
      case 0: {
        const auto k = coefficients::read_model_file<models::sensors::ProximityModel>(temp_path());
        finite({k.base.a_per_m2, k.base.b_per_m, k.base.c});
        break;
      }
      case 1: finite({coefficients::read_model_file<models::sensors::LightModel>(temp_path()).base.gamma_m}); break;
      case 2:
        for (const auto& g : coefficients::read_model_file<models::sensors::GroundModel>(temp_path()).sensors) finite({g.gain_raw, g.offset_raw});
        break;
      case 3: {
        const auto c = coefficients::read_model_file<models::sensors::CameraModel>(temp_path());
        finite({c.base.horizontal_fov_rad, c.base.cx_px, c.base.cy_px});
        break;
      }
      case 4: {
        const auto d = coefficients::read_model_file<models::sensors::DriveModel>(temp_path());
        finite({d.steps_per_m, d.effects.tof_scale.k, d.effects.tof_offset.offset_mm, d.effects.slip.tau_s});
        break;
      }
    }
  } catch (const std::runtime_error&) {
    // The documented failure: a message naming the file.
  }
  return 0;
}
