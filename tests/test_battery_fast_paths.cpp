// The battery models' fast paths against the straightforward formulas they replace.
//
// argos_compatible: the step reorders independent work (both speed tables' cube roots before
// either table's end) and rounds the speed without a library call; it must still give the
// plug-in's doubles bit for bit. The reference below is the plug-in's arithmetic written the
// plain way (shared/reference/epuck2-plugin.md section 3), as battery.hpp had it before.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>

#include "epuck2/models/battery.hpp"
#include "epuck2/models/battery_simulation.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"

namespace mb = epuck2::models::battery;

namespace {

bool same_bits(double x, double y) { return std::memcmp(&x, &y, sizeof x) == 0; }

namespace plain {
double speed_cm_s(double delta_pos_m, double dt_s) {
  const double v = std::clamp(delta_pos_m / dt_s, 0.0, mb::kMaxSpeed_m_s);
  return std::round(v * 10000.0) / 100.0;
}
double cardano_root(const mb::CubicRow& q, double y) {
  const double a = q.a, b = q.b, c = q.c, d = q.d;
  const double new_d = d - y;
  const double d0 = b * b - 3 * a * c;
  const double d1 = 2 * b * b * b - 9 * a * b * c + 27 * a * a * new_d;
  const double C = std::cbrt((d1 + std::sqrt(d1 * d1 - 4 * d0 * d0 * d0)) / 2);
  return (-1 / (3 * a) * (b + C + d0 / C));
}
double cubic_next(const mb::CubicRow& q, double charge, double dt_s) {
  double x = std::max(0.0, cardano_root(q, charge));
  if (x >= q.end_s) return 0.0;
  x += dt_s;
  return q.a * x * x * x + q.b * x * x + q.c * x + q.d;
}
double cubic_step(const mb::Tables& t, double charge, double delta_pos_m, double dt_s) {
  const double speed = speed_cm_s(delta_pos_m, dt_s);
  const int lo = std::min(mb::kSpeedCount - 1, static_cast<int>(std::floor(speed)));
  const int hi = std::max(0, static_cast<int>(std::ceil(speed)));
  const double yL = cubic_next(t.cubic[lo], charge, dt_s);
  if (lo == hi) return std::max(0.0, yL);
  const double yH = cubic_next(t.cubic[hi], charge, dt_s);
  return std::max(0.0, mb::argos::interpolate(yL, yH, (speed - lo) / (hi - lo)));
}
}  // namespace plain

}  // namespace

TEST(BatteryFastPaths, RoundingWithoutTheLibraryCallIsStdRound) {
  // Halves, their neighbours, integers, zeros of both signs, the 2^52 boundary, NaN, infinity.
  std::vector<double> xs = {0.0, -0.0, 0.5, 1.5, 2.5, 1499.5, 1500.0, 0.49999999999999994,
                            std::nextafter(0.5, 1.0), std::nextafter(1499.5, 0.0),
                            4503599627370495.5, 4503599627370496.0, 1e300,
                            std::numeric_limits<double>::infinity(),
                            std::numeric_limits<double>::quiet_NaN()};
  for (int k = 0; k <= 15000; ++k) {
    const double h = k / 10.0;
    xs.insert(xs.end(), {h, std::nextafter(h, 0.0), std::nextafter(h, 2e4), h + 0.5});
  }
  std::mt19937_64 rng(20260521);
  std::uniform_real_distribution<double> u(0.0, 1500.0);
  for (int k = 0; k < 1000000; ++k) xs.push_back(u(rng));
  for (double x : xs) {
    const double expected = std::round(x);
    const double got = mb::round_non_negative(x);
    EXPECT_TRUE(same_bits(got, expected) || (std::isnan(got) && std::isnan(expected))) << x;
  }
  // The plug-in's speed over every distance a 0.1 s tick can cover to 1e-7 m, and beyond.
  for (int k = 0; k <= 200000; ++k) {
    const double dpos = k * 1e-7;
    ASSERT_TRUE(same_bits(mb::plugin_speed_cm_s(dpos, 0.1), plain::speed_cm_s(dpos, 0.1))) << dpos;
  }
}

TEST(BatteryFastPaths, CompatibleCubicIsTheSourceArithmeticBitForBit) {
  // Whole discharges from a full battery at table speeds and between tables (every 0.19 cm/s up
  // to 15.39, clamped beyond 15), ticks of 0.1 s and 0.25 s: every tick's double must be equal.
  const mb::Tables& t = mb::plugin_tables();
  long ticks = 0;
  for (int centi = 0; centi <= 1540; centi += 19) {
    for (double dt : {0.1, 0.25}) {
      const double dpos = centi / 10000.0 * dt;
      double fast = 1.0, ref = 1.0;
      for (int k = 0; k < 400000 && ref > 0; ++k, ++ticks) {
        fast = mb::argos::step(mb::Model::cubic, t, fast, dpos, dt);
        ref = plain::cubic_step(t, ref, dpos, dt);
        ASSERT_TRUE(same_bits(fast, ref)) << centi / 100.0 << " cm/s, dt " << dt << ", tick " << k
                                          << ": " << fast << " vs " << ref;
      }
    }
  }
  EXPECT_GT(ticks, 5000000);
  // Single cube roots too (the tests elsewhere call cardano_root and cubic_next directly).
  for (const mb::CubicRow& q : t.cubic) {
    for (double y = 1.0; y > -0.05; y -= 0.001) {
      ASSERT_TRUE(same_bits(mb::argos::cardano_root(q, y), plain::cardano_root(q, y))) << y;
      ASSERT_TRUE(same_bits(mb::argos::cubic_next(q, y, 0.1), plain::cubic_next(q, y, 0.1))) << y;
    }
  }
}
