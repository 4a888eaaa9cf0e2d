// The battery models: plug-in compatible arithmetic against the plug-in's observed values
// (as observed when the plug-in runs in ARGoS 3),
// the quirks one by one, and the corrected behaviour's fixes.
#include "epuck2/fit/jet.hpp"
#include <gtest/gtest.h>

#include <cmath>

#include "epuck2/models/battery.hpp"
#include "epuck2/models/battery_simulation.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"

namespace mb = epuck2::models::battery;

namespace {
// Bit-exact: the compatible models must reproduce the plug-in's doubles exactly.
constexpr double kBitExact = 0.0;
// The reference quotes the cubic's later ticks to 5 significant digits.
constexpr double kFiveDigits = 5e-6;

std::vector<mb::ChargeSample> run_battery_models(mb::Model m, mb::Behaviour b, std::vector<mb::ProfilePoint> profile) {
  return mb::simulate_discharge(m, b, mb::plugin_tables(), profile, 0.1, 1.0);
}
}  // namespace

TEST(BatteryCompat, FirstTickMatchesThePluginBitForBit) {
  const std::vector<mb::ProfilePoint> spin7{{0.0, 7.0}, {2.0, 7.0}};
  EXPECT_NEAR(run_battery_models(mb::Model::simple, mb::Behaviour::argos_compatible, spin7)[1].charge, 0.99999493503695103, kBitExact);
  EXPECT_NEAR(run_battery_models(mb::Model::linear, mb::Behaviour::argos_compatible, spin7)[1].charge, 0.99999493503710257, kBitExact);
  EXPECT_NEAR(run_battery_models(mb::Model::approximated, mb::Behaviour::argos_compatible, spin7)[1].charge, 0.99999406068869212, kBitExact);
  EXPECT_NEAR(run_battery_models(mb::Model::cubic, mb::Behaviour::argos_compatible, spin7)[1].charge, 0.98983534873817192, kBitExact);
}

TEST(BatteryCompat, CubicJumpsOnTheFirstMovingTicks) {
  // Reference: 0.98984 -> 0.93657 -> 0.93634 at 7 cm/s.
  const auto s = run_battery_models(mb::Model::cubic, mb::Behaviour::argos_compatible, {{0.0, 7.0}, {2.0, 7.0}});
  EXPECT_NEAR(s[1].charge, 0.98984, kFiveDigits);
  EXPECT_NEAR(s[2].charge, 0.93657, kFiveDigits);
  EXPECT_NEAR(s[3].charge, 0.93634, kFiveDigits);
}

TEST(BatteryCompat, FirstTickAfterAChangeSeesNinetyPercent) {
  // Tick 2 turns 0.9 * 7 + 0.1 * 0 = 6.30 cm/s: the Linear model interpolates L[6] and L[7]
  // with d = 0.3, in float, starting from the smaller value.
  const mb::Tables& t = mb::plugin_tables();
  const auto s = run_battery_models(mb::Model::linear, mb::Behaviour::argos_compatible, {{0.0, 7.0}, {1.0, 7.0}});
  const double c1 = s[1].charge;
  const float mL = static_cast<float>(t.linear_slope_per_s[6]), mH = static_cast<float>(t.linear_slope_per_s[7]);
  const float yL = static_cast<float>(c1 + mL * 0.1), yH = static_cast<float>(c1 + mH * 0.1);
  const float d = static_cast<float>((6.3 - 6) / (7 - 6));
  const float expected = (yH < yL) ? yH + (yL - yH) * d : yL + (yH - yL) * d;
  EXPECT_EQ(s[2].charge, static_cast<double>(expected));
  // From tick 3 on the commanded 7.00 cm/s: no interpolation, slope L[7] as a float.
  EXPECT_EQ(s[3].charge, s[2].charge + static_cast<float>(t.linear_slope_per_s[7]) * 0.1);
}

TEST(BatteryCompat, SpeedIsClampedAndRoundedToHundredths) {
  EXPECT_DOUBLE_EQ(mb::plugin_speed_cm_s(0.00630, 0.1), 6.30);
  EXPECT_DOUBLE_EQ(mb::plugin_speed_cm_s(0.004374, 0.1), 4.37);
  EXPECT_DOUBLE_EQ(mb::plugin_speed_cm_s(0.02, 0.1), 15.0);  // 20 cm/s clamped
  EXPECT_DOUBLE_EQ(mb::plugin_speed_cm_s(-0.01, 0.1), 0.0);
}

TEST(BatteryCompat, InterpolationStartsFromTheSmallerValue) {
  // y_low = 0.5 > y_high = 0.4 at d = 0.3: the plug-in gives 0.4 + 0.1 * 0.3, a lerp 0.47.
  EXPECT_DOUBLE_EQ(mb::argos::interpolate(0.5, 0.4, 0.3), 0.43);
  EXPECT_DOUBLE_EQ(mb::argos::interpolate(0.4, 0.5, 0.3), 0.43);
}

TEST(BatteryCompat, CardanoRootIsClampedAtZeroAndZeroPastTheEnd) {
  const mb::CubicRow& q0 = mb::plugin_tables().cubic[0];
  EXPECT_LT(mb::argos::cardano_root(q0, 1.0), 0.0);  // full charge lies above the intercept
  const double p[4] = {q0.d, q0.c, q0.b, q0.a};
  EXPECT_DOUBLE_EQ(mb::argos::cubic_next(q0, 1.0, 0.1), mb::cubic_charge(p, 0.1) + 0.0 * 1e-300);
  // A charge below the curve's value at the end: the root is past the end, next charge 0.
  EXPECT_EQ(mb::argos::cubic_next(q0, 0.05, 0.1), 0.0);
  // On the curve: the root recovers t, the step advances by dt.
  const double t = 5000.0;
  EXPECT_NEAR(mb::argos::cardano_root(q0, mb::cubic_charge(p, t)), t, 1e-3);
}

TEST(BatteryCompat, ApproximatedPicksTheSegmentByChargeBand) {
  const auto& segs = mb::plugin_tables().segments[0];
  EXPECT_EQ(&mb::argos::segment_for(segs, 0.9), &segs[0]);
  EXPECT_EQ(&mb::argos::segment_for(segs, 0.6), &segs[1]);
  EXPECT_EQ(&mb::argos::segment_for(segs, 0.3), &segs[2]);
  EXPECT_EQ(&mb::argos::segment_for(segs, 0.1), &segs[3]);   // below M3's band: the drop
  EXPECT_EQ(&mb::argos::segment_for(segs, 1.01), &segs[3]);  // above M1's band: also M4 (quirk)
  EXPECT_NEAR(mb::argos::approximated_next(segs, 0.6, 0.1), 0.6 + segs[1].m * 0.1, 1e-15);
}

TEST(BatteryCompat, SimpleUsesTheStaticSlopeOnlyWhenNotMoving) {
  const mb::Tables& t = mb::plugin_tables();
  EXPECT_EQ(mb::argos::step(mb::Model::simple, t, 0.5, 0.0, 0.1), 0.5 + t.simple_static_slope_per_s * 0.1);
  EXPECT_EQ(mb::argos::step(mb::Model::simple, t, 0.5, 1e-6, 0.1), 0.5 + t.simple_moving_slope_per_s * 0.1);
}

TEST(BatteryCorrected, StartsContinuouslyFromFullCharge) {
  // The plug-in's cubic drops to the intercept (0.936 at 7 cm/s) within two ticks; the corrected
  // one falls towards it with the firmware filter's 2.24 s lag: a tick takes 1 - exp(-0.1/2.24)
  // = 4.4 % of the gap, and after 30 s the charge is on the curve.
  const auto s = run_battery_models(mb::Model::cubic, mb::Behaviour::corrected, {{0.0, 7.0}, {40.0, 7.0}});
  const mb::CubicRow& q = mb::plugin_tables().cubic[7];
  const double first_drop = 1.0 - s[1].charge;
  // x' = -x / tau + c for the excess x over d, from x0 = 1 - d: after 0.1 s the charge has fallen
  // by (1 - d - c tau) (1 - exp(-0.1 / tau)).
  const double tau = mb::corrected::kFirmwareFilterTau_s;
  EXPECT_NEAR(first_drop, (1.0 - q.d - q.c * tau) * (1.0 - std::exp(-0.1 / tau)), 1e-12);
  for (std::size_t k = 1; k < s.size(); ++k) EXPECT_LT(s[k - 1].charge - s[k].charge, 0.01) << "tick " << k;
  const double p[4] = {q.d, q.c, q.b, q.a};
  EXPECT_NEAR(s[300].charge, mb::cubic_charge(p, 30.0), 2e-3);
}

TEST(BatteryCorrected, InterpolatesLinearlyBetweenSpeedTables) {
  const mb::Tables& t = mb::plugin_tables();
  const double next = mb::corrected::step(mb::Model::linear, t, 0.8, 0.0063, 0.1);  // 6.3 cm/s
  EXPECT_NEAR(next, 0.8 + (0.7 * t.linear_slope_per_s[6] + 0.3 * t.linear_slope_per_s[7]) * 0.1, 1e-15);
}

TEST(BatteryCorrected, RobustRootAgreesWithCardanoWhereCardanoIsValid) {
  for (int s = 0; s < mb::kSpeedCount; ++s) {
    const mb::CubicRow& q = mb::plugin_tables().cubic[static_cast<std::size_t>(s)];
    const double p[4] = {q.d, q.c, q.b, q.a};
    for (double frac : {0.1, 0.4, 0.7, 0.95}) {
      const double y = mb::cubic_charge(p, frac * q.end_s);
      EXPECT_NEAR(mb::corrected::cubic_time(q, y), frac * q.end_s, 1e-3) << "speed " << s;
      EXPECT_NEAR(mb::argos::cardano_root(q, y), frac * q.end_s, 1e-3) << "speed " << s;
    }
  }
}

TEST(BatteryCorrected, RobustRootNeverNaN) {
  // A cubic that turns back up: Cardano's formula can take the root of a negative number.
  const mb::CubicRow bad{1.0, -3e-4, 5e-8, 1e-12, 10000.0};
  for (double y : {0.99, 0.8, 0.5, 0.2, -0.1}) {
    EXPECT_FALSE(std::isnan(mb::corrected::cubic_next(bad, y, 0.1))) << y;
  }
}

// One formula for double, float and fit::Jet; autodiff against numeric differentiation.
TEST(BatteryFormulas, CubicAndPolylineForDoubleFloatAndJet) {
  const double pd[4] = {0.99, -9e-5, 8e-9, -3e-13};
  const float pf[4] = {0.99f, -9e-5f, 8e-9f, -3e-13f};
  EXPECT_NEAR(mb::cubic_charge(pd, 1000.0), static_cast<double>(mb::cubic_charge(pf, 1000.0)), 1e-6);
  using Jet = epuck2::fit::Jet<4>;
  Jet pj[4];
  for (int i = 0; i < 4; ++i) pj[i] = Jet(pd[i], i);
  const double t = 1234.5;
  const Jet v = mb::cubic_charge(pj, t);
  EXPECT_DOUBLE_EQ(v.a, mb::cubic_charge(pd, t));
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(v.v[i], std::pow(t, i), 1e-9 * std::pow(t, i));

  // Polyline: derivative w.r.t. a knot position against central differences, at a point inside
  // the second segment and at t = 0 (an awkward point: the first knot).
  using Jet2 = epuck2::fit::Jet<2>;
  for (double tt : {0.0, 3000.0, 9000.0}) {
    const double xs[4] = {0.0, 2000.0, 7000.0, 10000.0}, ys[4] = {1.0, 0.7, 0.45, 0.15};
    Jet2 xj[4] = {Jet2(xs[0]), Jet2(xs[1], 0), Jet2(xs[2], 1), Jet2(xs[3])};
    Jet2 yj[4] = {Jet2(ys[0]), Jet2(ys[1]), Jet2(ys[2]), Jet2(ys[3])};
    const Jet2 r = mb::polyline_charge(xj, yj, 4, tt);
    for (int k = 1; k <= 2; ++k) {
      const double h = 1e-3;
      double xp[4], xm[4];
      std::copy(xs, xs + 4, xp);
      std::copy(xs, xs + 4, xm);
      xp[k] += h;
      xm[k] -= h;
      const double numeric = (mb::polyline_charge(xp, ys, 4, tt) - mb::polyline_charge(xm, ys, 4, tt)) / (2 * h);
      EXPECT_NEAR(r.v[k - 1], numeric, 1e-9) << "t " << tt << " knot " << k;
    }
  }
}

TEST(BatterySimulation, StopsAtAnEmptyBatteryAndAtTheProfileEnd) {
  const auto s = run_battery_models(mb::Model::linear, mb::Behaviour::corrected, {{0.0, 4.0}, {1e6, 4.0}});
  EXPECT_EQ(s.back().charge, 0.0);
  EXPECT_NEAR(s.back().time_s, mb::plugin_tables().lifetime_s[4], 0.2);
  const auto short_run = run_battery_models(mb::Model::cubic, mb::Behaviour::argos_compatible, {{0.0, 3.0}, {12.34, 3.0}});
  EXPECT_EQ(short_run.size(), 124u);  // t = 0 and 123 ticks
}
