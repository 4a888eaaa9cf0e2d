// The battery models' fast paths against the straightforward formulas they replace.
//
// argos_compatible: the step reorders independent work (both speed tables' cube roots before
// either table's end) and rounds the speed without a library call; it must still give the
// plug-in's doubles bit for bit. The reference below is the plug-in's arithmetic written the
// plain way (as in the plug-in's source), as battery.hpp had it before.
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

// corrected: the Cubic's root search may start from the time carried from the previous tick
// (CubicHints), and the next charge is taken as an increment from the charge. Both must leave the
// model's values where an exact solution puts them.
namespace {

// cubic(t + dt) with t the first time the cubic reads `charge`, in long double: bisection to the
// last bit of the bracket (the plug-in tables' cubics decrease over their lifetime).
double exact_cubic_next(const mb::CubicRow& q, double charge, double dt_s) {
  auto cubic = [&](long double t) {
    return ((static_cast<long double>(q.a) * t + q.b) * t + q.c) * t + q.d;
  };
  long double lo = 0, hi = q.end_s;
  for (int k = 0; k < 200; ++k) {
    const long double mid = 0.5L * (lo + hi);
    if (cubic(mid) > charge) lo = mid; else hi = mid;
  }
  return static_cast<double>(cubic(0.5L * (lo + hi) + dt_s));
}

}  // namespace

TEST(BatteryFastPaths, CorrectedCubicStepIsWithinRoundingOfTheExactSolution) {
  // Over each table's lifetime, stateless and with a hint a second off: the increment form is
  // within 1e-13 of the exact next charge (the plain cubic(t + dt) was off by up to about
  // |cubic'| * tolerance = 1e-4 * 1e-5 = 1e-9).
  const mb::Tables& t = mb::plugin_tables();
  double worst = 0;
  for (const mb::CubicRow& q : t.cubic) {
    const double p[4] = {q.d, q.c, q.b, q.a};
    for (int k = 1; k < 400; ++k) {
      const double t_true = q.end_s * k / 400.0;
      const double charge = mb::cubic_charge(p, t_true);
      const double exact = exact_cubic_next(q, charge, 0.1);
      double hint = t_true + 1.0;
      const double carried = mb::corrected::cubic_next(q, charge, 0.1, hint);
      const double fresh = mb::corrected::cubic_next(q, charge, 0.1);
      worst = std::max({worst, std::abs(carried - exact), std::abs(fresh - exact)});
      ASSERT_NEAR(carried, exact, 1e-13) << "t " << t_true;
      ASSERT_NEAR(fresh, exact, 1e-13) << "t " << t_true;
      EXPECT_NEAR(hint, t_true + 0.1, 1e-4);  // the hint now holds the time reached
    }
  }
  RecordProperty("worst_error", std::to_string(worst));
}

TEST(BatteryFastPaths, CarriedHintsChangeNothingButWhereTheSearchStarts) {
  // A profile that changes speed (table speeds, between tables, back to a table seen long ago
  // whose hint is stale): at every tick the step with the carried hints, with nonsense hints
  // (NaN, infinities, times beyond the lifetime, another table's times) and without any must
  // agree to 1e-13.
  const mb::Tables& t = mb::plugin_tables();
  const double speeds_cm_s[] = {7.0, 6.37, 6.37, 12.0, 3.5, 0.0, 15.0, 7.0, 9.99};
  mb::corrected::CubicHints carried;
  double charge = 1.0;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-2e4, 4e4);
  long compared = 0;
  for (int k = 0; charge > 0 && k < 400000; ++k) {
    const double speed = speeds_cm_s[(k / 5000) % 9];
    const double dpos = speed / 100.0 * 0.1;
    mb::corrected::CubicHints nonsense;
    for (double& h : nonsense.t_s) {
      const double r = u(rng);
      h = r < -1e4 ? std::numeric_limits<double>::quiet_NaN()
                   : r > 3e4 ? std::numeric_limits<double>::infinity() : r;
    }
    const double fresh = mb::corrected::step(mb::Model::cubic, t, charge, dpos, 0.1);
    const double odd = mb::corrected::step(mb::Model::cubic, t, charge, dpos, 0.1, nonsense);
    const double next = mb::corrected::step(mb::Model::cubic, t, charge, dpos, 0.1, carried);
    ASSERT_NEAR(next, fresh, 1e-13) << "tick " << k;
    ASSERT_NEAR(odd, fresh, 1e-13) << "tick " << k;
    charge = next;
    ++compared;
  }
  EXPECT_EQ(charge, 0.0);  // ran to an empty battery
  EXPECT_GT(compared, 50000);
  // simulate_discharge carries the hints: its ticks are the stateless steps to the same 1e-13.
  const auto s = mb::simulate_discharge(mb::Model::cubic, mb::Behaviour::corrected, t,
                                        {{0.0, 6.37}, {600.0, 11.0}, {1200.0, 11.0}}, 0.1, 1.0);
  for (std::size_t k = 1; k < s.size(); ++k) {
    const double v = s[k - 1].time_s < 600.0 - 1e-9 ? 6.37 : 11.0;
    ASSERT_NEAR(s[k].charge, mb::corrected::step(mb::Model::cubic, t, s[k - 1].charge, v / 100.0 * 0.1, 0.1), 1e-13) << k;
  }
}

TEST(BatteryFastPaths, CorrectedCubicAtATableSpeedSkipsOnlyAZeroWeight) {
  // At w = 0 the step no longer evaluates the next table: the same double as the full lerp.
  // (v / 100 * 0.1 m in 0.1 s is not always exactly v cm/s, e.g. 7.000000000000001: those
  // interpolate with a weight of 1e-15 and are left out.)
  const mb::Tables& t = mb::plugin_tables();
  int table_speeds = 0;
  for (int v = 0; v < mb::kSpeedCount; ++v) {
    const double dpos = v / 100.0 * 0.1;
    if (mb::exact_speed_cm_s(dpos, 0.1) != static_cast<double>(v)) continue;
    ++table_speeds;
    const int hi = std::min(mb::kSpeedCount - 1, v + 1);
    for (double charge = 1.0; charge > 0.0; charge -= 0.0037) {
      const double lo_next = mb::corrected::cubic_next(t.cubic[v], charge, 0.1);
      const double hi_next = mb::corrected::cubic_next(t.cubic[hi], charge, 0.1);
      const double full = std::max(0.0, mb::corrected::lerp(lo_next, hi_next, 0.0));
      ASSERT_TRUE(same_bits(mb::corrected::step(mb::Model::cubic, t, charge, dpos, 0.1), full)) << v << " " << charge;
    }
  }
  EXPECT_GE(table_speeds, 10);
}
