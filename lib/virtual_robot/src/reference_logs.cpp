#include "epuck2/virtual_robot/reference_logs.hpp"

namespace epuck2::virtual_robot {

std::vector<GeneratedFile> reference_logs(logs::Kind kind, std::uint64_t seed) {
  switch (kind) {
    case logs::Kind::battery: return battery_reference_logs(seed);
    case logs::Kind::proximity: return proximity_reference_logs(seed);
    case logs::Kind::light: return light_reference_logs(seed);
    case logs::Kind::ground: return ground_reference_logs(seed);
    case logs::Kind::camera: return camera_reference_logs(seed);
    case logs::Kind::drive: return drive_reference_logs(seed);
  }
  return {};
}

}  // namespace epuck2::virtual_robot
