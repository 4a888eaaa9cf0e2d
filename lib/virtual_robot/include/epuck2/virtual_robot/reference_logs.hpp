// The virtual E-Puck2's reference logs: what it records when it runs each of the paper's
// calibration protocols. `epuck2-fit generate KIND --out data/raw/KIND` writes them; each kind's
// physics, imperfections and calibration are documented in data/raw/KIND/README.md.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "epuck2/logs/log.hpp"

namespace epuck2::virtual_robot {

/// One log file: its name inside the kind's folder and its CSV text (docs/logs.md).
struct GeneratedFile {
  std::string name;
  std::string content;
};

/// Default seed of the shipped reference logs.
inline constexpr std::uint64_t kReferenceSeed = 20241121;

std::vector<GeneratedFile> battery_reference_logs(std::uint64_t seed);
std::vector<GeneratedFile> proximity_reference_logs(std::uint64_t seed);
std::vector<GeneratedFile> light_reference_logs(std::uint64_t seed);
std::vector<GeneratedFile> ground_reference_logs(std::uint64_t seed);
std::vector<GeneratedFile> camera_reference_logs(std::uint64_t seed);
std::vector<GeneratedFile> drive_reference_logs(std::uint64_t seed);

/// Dispatches on the kind.
std::vector<GeneratedFile> reference_logs(logs::Kind kind, std::uint64_t seed);

}  // namespace epuck2::virtual_robot
