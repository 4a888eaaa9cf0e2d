// Tests written for the third fresh set of planted slips (bench/fresh-slips.md, "Round 3"): one
// or more for each slip the suite let through. Each expected value is worked by hand (the
// arithmetic is in the comments), is a documented boundary or rule, or is computed in the test
// apart from the code under test -- never a number printed by that code.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "epuck2/calibrate/charge_map.hpp"
#include "epuck2/logs/log.hpp"

namespace {

using namespace epuck2;
using nlohmann::json;

// ----- the voltage->charge map -----

json map_file(const std::vector<double>& knots_v, const std::vector<double>& knot_charge) {
  return {{"kind", "charge_map"},
          {"charge_map", {{"form", calibrate::kChargeMapForm}, {"knots_v", knots_v}, {"knot_charge", knot_charge}}}};
}

TEST(RoundThreeChargeMap, AFlatStretchIsAMapAndConvertsByHand) {
  // docs/coefficient-files.md: knot_charge non-decreasing (the fit holds its increments >= 0, so
  // a flat stretch is a fit's possible answer). Knots 3.0, 3.5, 3.7, 4.0 V with charges 0, 0.5,
  // 0.5, 1: flat between 3.5 and 3.7 V.
  const calibrate::ChargeMap m = calibrate::charge_map_from_json(map_file({3.0, 3.5, 3.7, 4.0}, {0.0, 0.5, 0.5, 1.0}), "flat.json");
  // 3.6 V is on the flat stretch: 0.5. 3.85 V is halfway from 3.7 to 4.0: 0.5 + 0.5 x 0.5 = 0.75.
  // 3.25 V halfway from 3.0 to 3.5: 0.25.
  EXPECT_NEAR(calibrate::convert_voltage(m, 3.6, 0.0).charge, 0.5, 1e-12);
  EXPECT_NEAR(calibrate::convert_voltage(m, 3.85, 0.0).charge, 0.75, 1e-12);
  EXPECT_NEAR(calibrate::convert_voltage(m, 3.25, 0.0).charge, 0.25, 1e-12);
  // A decreasing one is refused, at the entry that decreases (knot_charge/2).
  try {
    calibrate::charge_map_from_json(map_file({3.0, 3.5, 3.7, 4.0}, {0.0, 0.5, 0.4, 1.0}), "down.json");
    FAIL() << "a decreasing knot_charge was read";
  } catch (const logs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("knot_charge/2"), std::string::npos) << e.what();
  }
}

/// Rows on charge = voltage - 3 at the voltages 3.0, 3.1, ..., 4.0 (11 values, 3 rows each), one speed.
std::vector<calibrate::ChargeSample> line_rows() {
  std::vector<calibrate::ChargeSample> rows;
  for (int r = 0; r < 3; ++r)
    for (int i = 0; i <= 10; ++i) rows.push_back({3.0 + 0.1 * i, 0.0, 0.1 * i});
  return rows;
}

TEST(RoundThreeChargeMap, KnotsSitAtQuantilesWithTheExtremesFirstAndLast) {
  // docs/coefficient-files.md: "the knots sit at quantiles of the logged voltages (first and last
  // at the extremes)". 33 sorted voltages (each of 3.0..4.0 three times): with 2 knots, the
  // lowest and the highest, 3.0 and 4.0; with 3, also the median (sorted index 16 -> 3.5).
  calibrate::ChargeMapOptions two;
  two.knot_counts = {2};
  const calibrate::ChargeMapFit a = calibrate::fit_charge_map(line_rows(), {"line"}, two);
  ASSERT_TRUE(a.usable) << a.message;
  ASSERT_EQ(a.map.knots_v.size(), 2u);
  EXPECT_NEAR(a.map.knots_v[0], 3.0, 1e-12);
  EXPECT_NEAR(a.map.knots_v[1], 4.0, 1e-12);
  // The line itself: charge 0 and 1 at the knots.
  EXPECT_NEAR(a.map.knot_charge[0], 0.0, 1e-6);
  EXPECT_NEAR(a.map.knot_charge[1], 1.0, 1e-6);
  calibrate::ChargeMapOptions three;
  three.knot_counts = {3};
  const calibrate::ChargeMapFit b = calibrate::fit_charge_map(line_rows(), {"line"}, three);
  ASSERT_TRUE(b.usable) << b.message;
  ASSERT_EQ(b.map.knots_v.size(), 3u);
  EXPECT_NEAR(b.map.knots_v[0], 3.0, 1e-12);
  EXPECT_NEAR(b.map.knots_v[1], 3.5, 1e-12);
  EXPECT_NEAR(b.map.knots_v[2], 4.0, 1e-12);
}

}  // namespace
