// libFuzzer target: the coefficient file's one owner, lib/coefficients (read_model_file for every
// kind, which reads a path). Input: byte 0 picks the kind (0 proximity, 1 light, 2 ground,
// 3 camera, 4 drive, 5 battery; other values wrap), the rest is the file, written to a per-process
// temporary file. Contract checked: the reader returns or throws std::runtime_error (InputError is
// one); any other exception (a raw nlohmann::json exception, std::out_of_range...) or a crash is a
// finding; and a model that was read writes back and reads back to the same JSON (round_trip).
// Byte 0 at 128 or more: the rest are numbers of a model built, not read (built_models.hpp),
// written and read back with the same property: equal, or the write refuses.
// With EPUCK2_FUZZ_FINITE=1 in the environment, a reader that returns a non-finite coefficient
// (JSON numbers such as 1e999 parse as infinity) aborts too.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <string>

#include <nlohmann/json.hpp>

#include "built_models.hpp"
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

/// The property of the one coefficient-file owner (lib/coefficients): a model writes back (or
/// the write refuses, std::domain_error), and what is written reads back to the same file, byte
/// for byte of its JSON (fuzzing::write_and_read_back). Anything else is a finding.
template <class Model, class FromJson>
void round_trip(const Model& m, FromJson from_json) {
  std::string why;
  const fuzzing::RoundTrip r = fuzzing::write_and_read_back(m, from_json, why);
  if (r == fuzzing::RoundTrip::differs || r == fuzzing::RoundTrip::unreadable) {
    std::fprintf(stderr, "fuzz_coefficients: %s\n", why.c_str());
    std::abort();
  }
}

/// Numbers from the fuzz bytes for fuzzing::built_model: each takes a selector byte: keep the
/// current value, change it by up to 50 %, a small whole number over 16, or 8 raw bytes as a
/// double (NaN, infinities and 1e300 among them). Past the end: the current value.
struct BytesToNumbers {
  const std::uint8_t* p;
  const std::uint8_t* end;
  double operator()(double current) {
    if (p >= end) return current;
    const std::uint8_t sel = *p++;
    switch (sel % 4) {
      case 0: return current;
      case 1: return p < end ? current * (1.0 + static_cast<std::int8_t>(*p++) / 256.0) : current;
      case 2: {
        if (end - p < 2) return current;
        const auto v = static_cast<std::int16_t>(p[0] | (p[1] << 8));
        p += 2;
        return v / 16.0;
      }
      default: {
        if (end - p < 8) return current;
        double v;
        std::memcpy(&v, p, 8);
        p += 8;
        return v;
      }
    }
  }
};

/// Byte 0 at 128 or more: a model built from the bytes (not read), written and read back.
void built(int pick, const std::uint8_t* data, std::size_t size) {
  namespace s = epuck2::models::sensors;
  namespace co = epuck2::coefficients;
  BytesToNumbers next{data, data + size};
  switch (pick) {
    case 0: round_trip(fuzzing::built_model<s::ProximityModel>(next), [](const auto& j, const auto& p, const auto& r) { return co::proximity_model_from_json(j, p, r); }); break;
    case 1: round_trip(fuzzing::built_model<s::LightModel>(next), [](const auto& j, const auto& p, const auto& r) { return co::light_model_from_json(j, p, r); }); break;
    case 2: round_trip(fuzzing::built_model<s::GroundModel>(next), [](const auto& j, const auto& p, const auto& r) { return co::ground_model_from_json(j, p, r); }); break;
    case 3: round_trip(fuzzing::built_model<s::CameraModel>(next), [](const auto& j, const auto& p, const auto& r) { return co::camera_model_from_json(j, p, r); }); break;
    case 4: round_trip(fuzzing::built_model<s::DriveModel>(next), [](const auto& j, const auto& p, const auto& r) { return co::drive_model_from_json(j, p, r); }); break;
    default: round_trip(fuzzing::built_model<s::BatteryModel>(next), [](const auto& j, const auto& p, const auto& r) { return co::battery_model_from_json(j, p, r); }); break;
  }
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const int pick = data[0] % 6;
  if (data[0] >= 128) {
    built(pick, data + 1, size - 1);
    return 0;
  }
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
        round_trip(m, [](const auto& j, const auto& p, const auto& r) { return co::proximity_model_from_json(j, p, r); });
        break;
      }
      case 1: {
        const auto m = co::read_model_file<s::LightModel>(temp_path());
        finite({m.base.gamma_m});
        round_trip(m, [](const auto& j, const auto& p, const auto& r) { return co::light_model_from_json(j, p, r); });
        break;
      }
      case 2: {
        const auto m = co::read_model_file<s::GroundModel>(temp_path());
        for (const auto& g : m.sensors) finite({g.gain_raw, g.offset_raw});
        round_trip(m, [](const auto& j, const auto& p, const auto& r) { return co::ground_model_from_json(j, p, r); });
        break;
      }
      case 3: {
        const auto m = co::read_model_file<s::CameraModel>(temp_path());
        finite({m.base.horizontal_fov_rad, m.base.cx_px, m.base.cy_px});
        round_trip(m, [](const auto& j, const auto& p, const auto& r) { return co::camera_model_from_json(j, p, r); });
        break;
      }
      case 4: {
        const auto m = co::read_model_file<s::DriveModel>(temp_path());
        finite({m.steps_per_m, m.effects.tof_scale.k, m.effects.tof_offset.offset_mm, m.effects.slip.tau_s});
        round_trip(m, [](const auto& j, const auto& p, const auto& r) { return co::drive_model_from_json(j, p, r); });
        break;
      }
      case 5: {
        const auto m = co::read_model_file<s::BatteryModel>(temp_path());
        for (std::size_t k = 0; k < m.tables.cubic.size(); ++k)
          finite({m.tables.cubic[k].a, m.tables.cubic[k].b, m.tables.cubic[k].c, m.tables.cubic[k].d, m.tables.lifetime_s[k],
                  m.tables.linear_slope_per_s[k]});
        round_trip(m, [](const auto& j, const auto& p, const auto& r) { return co::battery_model_from_json(j, p, r); });
        break;
      }
    }
  } catch (const std::runtime_error&) {
    // The documented failure: a message naming the file (and, for a model, the line and column).
  }
  return 0;
}
