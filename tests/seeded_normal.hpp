// A portable seeded Gaussian for the tests' own log generators: splitmix64 bits and Box-Muller,
// independent of lib/virtual_robot (so that a formula changed there or in lib/fit shows).
#pragma once

#include <cmath>
#include <cstdint>

namespace epuck2::testing {

class Normal {
 public:
  explicit Normal(std::uint64_t seed) : state_(seed) {}
  double uniform() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return (static_cast<double>(z >> 11) + 0.5) / 9007199254740992.0;
  }
  double operator()() {
    const double u1 = uniform(), u2 = uniform();
    return std::sqrt(-2 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }

 private:
  std::uint64_t state_;
};

}  // namespace epuck2::testing
