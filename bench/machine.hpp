// The machine a benchmark ran on: CPU model and hardware threads, printed beside its figures.
#pragma once

#include <fstream>
#include <string>
#include <thread>

namespace epuck2::bench {

inline std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

inline std::string machine() {
  return cpu_model() + ", " + std::to_string(std::thread::hardware_concurrency()) + " hardware threads";
}

}  // namespace epuck2::bench
