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
      const auto t = calibrate::battery_tables_from_json(j, "fuzz.json");
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
        const auto k = calibrate::load_proximity_coefficients(temp_path());
        finite({k.a_per_m2, k.b_per_m, k.c});
        break;
      }
      case 1: finite({calibrate::load_light_coefficients(temp_path()).gamma_m}); break;
      case 2:
        for (const auto& g : calibrate::load_ground_coefficients(temp_path())) finite({g.gain_raw, g.offset_raw});
        break;
      case 3: {
        const auto c = calibrate::load_camera_coefficients(temp_path());
        finite({c.horizontal_fov_rad, c.cx_px, c.cy_px});
        break;
      }
      case 4: {
        const auto d = calibrate::load_drive_coefficients(temp_path());
        finite({d.encoder.steps_per_m, d.tof.scale, d.tof.offset_mm, d.slip_time_constant_s});
        break;
      }
    }
  } catch (const std::runtime_error&) {
    // The documented failure: a message naming the file.
  }
  return 0;
}
