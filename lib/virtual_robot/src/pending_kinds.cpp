// TEMPORARY (development): kinds whose virtual-robot protocol is not written yet. Each function is
// removed from this file when its kind's own source file defines it; the file goes when empty.
#include <stdexcept>

#include "epuck2/virtual_robot/reference_logs.hpp"

namespace epuck2::virtual_robot {

namespace {
[[noreturn]] void not_yet(const char* kind) {
  throw std::runtime_error(std::string("the virtual robot does not record ") + kind + " logs yet");
}
}  // namespace

std::vector<GeneratedFile> proximity_reference_logs(std::uint64_t) { not_yet("proximity"); }
std::vector<GeneratedFile> light_reference_logs(std::uint64_t) { not_yet("light"); }
std::vector<GeneratedFile> ground_reference_logs(std::uint64_t) { not_yet("ground"); }
std::vector<GeneratedFile> camera_reference_logs(std::uint64_t) { not_yet("camera"); }
std::vector<GeneratedFile> drive_reference_logs(std::uint64_t) { not_yet("drive"); }

}  // namespace epuck2::virtual_robot
