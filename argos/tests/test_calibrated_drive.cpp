// The drive as the calibrated ARGoS actuator, encoders and ToF run it (argos/src/calibrated_drive):
// no ARGoS needed. Expected values are worked by hand from the effects' definitions
// (docs/diagnose.md, "drive"), not from lib/models' code.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <string>

#include "../src/applied_effects.hpp"
#include "../src/calibrated_drive.hpp"
#include <epuck2/coefficients/model_file.hpp>

namespace {

namespace ap = epuck2::argos_plugin;
namespace ms = epuck2::models::sensors;
namespace fs = std::filesystem;
namespace fx = epuck2::models::effects;
namespace co = epuck2::coefficients;

std::string write_temp(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("epuck2_argos_drive_test_" + name);
  std::ofstream(p) << text;
  return p.string();
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

ap::DriveConfig config_of(const std::string& name, const std::string& text) {
  return ap::read_drive_config(write_temp(name, text), "the actuator");
}

// A calibration file has no speed_limit: the firmware's 1100 steps/s over its steps_per_m caps a
// 20 cm/s command (1100 / 7760 steps/m = 14.175 cm/s), and the wheels run at the cap at once.
TEST(CalibratedDrive, ACommandAboveTheFirmwareCapRunsAtTheCap) {
  const auto c = config_of("cal.json", R"({"kind":"drive","parameters":{"steps_per_m":7760,"tof_scale":1,"tof_offset_mm":0}})");
  EXPECT_EQ(c.limit_from, "firmware");
  EXPECT_NEAR(c.effects.speed_limit.max_cm_s, 110000.0 / 7760.0, 1e-12);
  ap::CalibratedDrive d(c.effects);
  const auto v = d.step(20, 20, 0.1);
  EXPECT_NEAR(v[0], 11.0 / 77.60, 1e-12);
  EXPECT_NEAR(v[1], 11.0 / 77.60, 1e-12);
  EXPECT_NEAR(d.state().xl, 0.1 * 11.0 / 77.60, 1e-12);
  // Below the cap the command is what the wheels do.
  ap::CalibratedDrive slow(c.effects);
  EXPECT_NEAR(slow.step(10, 10, 0.1)[0], 0.10, 1e-12);
}

// A calibration file whose cap test found the encoders beat the firmware's cap (firmware_cap.kept
// false, docs/coefficient-files.md) runs uncapped, as `simulate --like` and codegen run it: a
// 20 cm/s command turns the wheels at 0.20 m/s. The same file with kept true is capped.
TEST(CalibratedDrive, ACalibrationThatRefutedTheCapRunsUncapped) {
  const auto c = config_of("refuted.json", R"({"kind":"drive","parameters":{"steps_per_m":7760,"tof_scale":1,"tof_offset_mm":0},
                                             "firmware_cap":{"kept":false}})");
  EXPECT_EQ(c.limit_from, "calibration");
  ap::CalibratedDrive d(c.effects);
  EXPECT_NEAR(d.step(20, 20, 0.1)[0], 0.20, 1e-12);
  const auto k = config_of("kept.json", R"({"kind":"drive","parameters":{"steps_per_m":7760,"tof_scale":1,"tof_offset_mm":0},
                                          "firmware_cap":{"kept":true}})");
  EXPECT_EQ(k.limit_from, "firmware");
  EXPECT_NEAR(k.effects.speed_limit.max_cm_s, 110000.0 / 7760.0, 1e-12);
}

// A diagnosis's speed_limit replaces the firmware cap.
TEST(CalibratedDrive, TheDiagnosisSpeedLimitIsTheCap) {
  const auto c = config_of("diag.json", R"({"kind":"drive","parameters":{"steps_per_m":7763.656},
                                          "effects":{"speed_limit":{"max_cm_s":12.5}}})");
  EXPECT_EQ(c.limit_from, "speed_limit");
  ap::CalibratedDrive d(c.effects);
  EXPECT_NEAR(d.step(20, 20, 0.1)[0], 0.125, 1e-12);
  EXPECT_NEAR(d.step(-20, -20, 0.1)[1], -0.125, 1e-12);
}

// accel_limit 50 cm/s^2, a 10 cm/s step from rest: the wheels reach 5 cm/s after 0.1 s (travel
// a t^2 / 2 = 2.5 mm), 10 cm/s after 0.2 s (10 mm), then 10 cm/s (20 mm after 0.3 s).
TEST(CalibratedDrive, AStepReachesSpeedAsTheAccelerationLimitSays) {
  const auto c = config_of("acc.json", R"({"parameters":{"steps_per_m":7763.656},
                                         "effects":{"accel_limit":{"accel_cm_s2":50}}})");
  ap::CalibratedDrive d(c.effects);
  auto v = d.step(10, 10, 0.1);
  EXPECT_NEAR(d.state().vl, 0.05, 1e-12);
  EXPECT_NEAR(d.state().xl, 0.0025, 1e-12);
  EXPECT_NEAR(v[0], 0.025, 1e-12);  // the tick's mean speed: 2.5 mm in 0.1 s
  d.step(10, 10, 0.1);
  EXPECT_NEAR(d.state().vl, 0.10, 1e-12);
  EXPECT_NEAR(d.state().xl, 0.010, 1e-12);
  v = d.step(10, 10, 0.1);
  EXPECT_NEAR(d.state().xl, 0.020, 1e-12);
  EXPECT_NEAR(v[0], 0.10, 1e-12);
}

// wheel_slip tau = 0.1 s: from rest under 10 cm/s the body has travelled u (t - tau (1 - e^-t/tau))
// = 0.1 (0.1 - 0.1 (1 - 1/e)) = 0.01/e m after 0.1 s while the wheels (and the encoders) have
// turned 10 mm; the physics engine is given the body's mean speed over the tick.
TEST(CalibratedDrive, WithSlipTheBodyLagsTheWheels) {
  const auto c = config_of("slip.json", R"({"parameters":{"steps_per_m":7763.656,"slip_time_constant_s":0.1}})");
  EXPECT_DOUBLE_EQ(c.effects.slip.tau_s, 0.1);
  ap::CalibratedDrive d(c.effects);
  const auto v = d.step(10, 10, 0.1);
  EXPECT_NEAR(d.state().xl, 0.010, 1e-12);
  EXPECT_NEAR(d.state().xg, 0.01 / std::exp(1.0), 1e-12);
  EXPECT_NEAR(v[0], 0.1 / std::exp(1.0), 1e-12);
  EXPECT_NEAR(v[1], v[0], 1e-15);
}

// Turning in place: the wheels' difference goes to the physics (times speed_scale's k); the
// body's forward speed stays 0.
TEST(CalibratedDrive, TurningInPlaceWithSpeedScale) {
  const auto c = config_of("turn.json", R"({"parameters":{"steps_per_m":7763.656},"effects":{"speed_scale":{"k":0.9}}})");
  ap::CalibratedDrive d(c.effects);
  const auto v = d.step(5, -5, 0.1);
  EXPECT_NEAR(v[0], 0.045, 1e-12);
  EXPECT_NEAR(v[1], -0.045, 1e-12);
  EXPECT_NEAR(d.state().xl, 0.005, 1e-12);  // the encoders count the wheels, not the body
  EXPECT_NEAR(d.state().xr, -0.005, 1e-12);
}

// After a turn, a command alike on both wheels (here: stop) moves each wheel from where it is: the
// wheels' travels stay as the turn left them, and the body is not turned back. Found in session 14
// (a robot pivoting on its right wheel): the one-wheel fast path for equal commands copied the left
// wheel's travel onto the right on the stop tick, and the actuator turned the body back in one tick.
// Worked by hand: 10 ticks of 0.1 s at (5, 0) cm/s: left 0.05 m, right 0; then stopped.
TEST(CalibratedDrive, AfterATurnAStopKeepsEachWheelsTravel) {
  const auto c = config_of("pivot.json", R"({"parameters":{"steps_per_m":7763.656}})");
  for (const double accel : {0.0, 50.0}) {
    SCOPED_TRACE(accel > 0 ? "accel_limit 50 cm/s^2" : "no accel_limit");
    auto effects = c.effects;
    if (accel > 0) effects.accel_limit.accel_cm_s2 = accel;
    ap::CalibratedDrive d(effects);
    for (int i = 0; i < 10; ++i) d.step(5, 0, 0.1);
    const double xl = d.state().xl, xr = d.state().xr;
    if (accel == 0) {
      EXPECT_NEAR(xl, 0.05, 1e-12);
      EXPECT_NEAR(xr, 0.0, 1e-12);
    }
    for (int i = 0; i < 20; ++i) {
      const auto v = d.step(0, 0, 0.1);
      EXPECT_NEAR(d.state().xr, xr, accel > 0 ? 0.0026 : 1e-12) << "tick " << i;  // a stop ramp of at most 5 cm/s over 0.1 s
      EXPECT_GE(d.state().xl, xl - 1e-12);
      EXPECT_LE(std::abs(v[0]) + std::abs(v[1]), 0.1 + 1e-12) << "the body turned back on tick " << i;
    }
    EXPECT_NEAR(d.state().xl - d.state().xr, xl - xr, accel > 0 ? 0.0026 : 1e-12);
  }
}

// A register standing still reads exactly what it read: no noise on a count that did not move.
TEST(StepRegister, StandingStillTheCountDoesNotChange) {
  ap::StepRegister r(7763.656);
  EXPECT_EQ(r.read(0.0, -0.7), 0);  // not moved: exactly 0 whatever the noise
  EXPECT_FALSE(r.moved(0.0));
  EXPECT_EQ(r.read(0.0, 0.9), 0);
  EXPECT_TRUE(r.moved(0.01));
  EXPECT_EQ(r.read(0.01, 0.3), static_cast<int>(std::floor(77.63656 + 0.3)));
  EXPECT_FALSE(r.moved(0.01));
  EXPECT_EQ(r.read(0.01, -0.9), 77);  // the same travel: the same reading, the new noise unused
  EXPECT_EQ(r.read(0.01, -0.9), 77);
  // int16 wrap: 5 m is 38818.28 steps, read as 38818 - 65536
  EXPECT_EQ(r.read(5.0), 38818 - 65536);
  // backwards: -5 m is floor(-38818.28) = -38819 steps, below -32768: read as -38819 + 65536
  EXPECT_EQ(r.read(-5.0), -38819 + 65536);
  // -1 m: floor(-7763.656) = -7764, inside the register
  EXPECT_EQ(r.read(-1.0), -7764);
}

// latency 0.15 s at 10 ticks/s: the reading at 0.3 s is the distance at 0.15 s, halfway between
// the ticks at 0.1 and 0.2 s.
TEST(DelayLine, TheReadingIsTheDistanceDelayAgo) {
  ap::DelayLine l(0.15);
  EXPECT_DOUBLE_EQ(*l.push_and_read(0.1, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(*l.push_and_read(0.2, 2.0), 1.0);
  EXPECT_DOUBLE_EQ(*l.push_and_read(0.3, 3.0), 1.5);
  EXPECT_DOUBLE_EQ(*l.push_and_read(0.4, 4.0), 2.5);
  ap::DelayLine none(0.0);
  EXPECT_DOUBLE_EQ(*none.push_and_read(0.1, 7.0), 7.0);
}

// A tick without a target cannot be interpolated: the delayed time takes the nearer tick's
// reading, a distance or "no target" (docs/argos.md, effects.latency). Worked by hand, latency 0.12 s at 10
// ticks/s: at 0.3 s the delayed time is 0.18 s, 0.08 s after the 0.1 s tick and 0.02 s before the
// 0.2 s tick, so the 0.2 s tick's; at 0.4 s it is 0.28 s, nearer 0.3 s.
TEST(DelayLine, ATickWithoutTargetGivesWayToTheNearerTick) {
  ap::DelayLine l(0.12);
  EXPECT_FALSE(l.push_and_read(0.1, std::nullopt).has_value());  // before the first tick: the first
  EXPECT_FALSE(l.push_and_read(0.2, 0.3).has_value());           // 0.08 s: on or before the first
  const auto at_03 = l.push_and_read(0.3, 0.29);                   // 0.18 s: the 0.2 s tick's
  ASSERT_TRUE(at_03.has_value());
  EXPECT_DOUBLE_EQ(*at_03, 0.3);
  const auto at_04 = l.push_and_read(0.4, std::nullopt);           // 0.28 s: between 0.2 and 0.3, interpolated
  ASSERT_TRUE(at_04.has_value());
  EXPECT_NEAR(*at_04, 0.3 + 0.8 * (0.29 - 0.3), 1e-12);
  const auto at_05 = l.push_and_read(0.5, 0.25);                   // 0.38 s: 0.3 s tick (0.29) and 0.4 s (none): nearer 0.4
  EXPECT_FALSE(at_05.has_value());
  const auto at_06 = l.push_and_read(0.6, 0.24);                   // 0.48 s: 0.4 s (none) and 0.5 s (0.25): nearer 0.5
  ASSERT_TRUE(at_06.has_value());
  EXPECT_DOUBLE_EQ(*at_06, 0.25);

  // The mirror: the target is lost after the tick the delayed time sits next to.
  ap::DelayLine m(0.12);
  m.push_and_read(0.1, 0.5);
  m.push_and_read(0.2, std::nullopt);
  const auto m_03 = m.push_and_read(0.3, std::nullopt);  // 0.18 s: nearer the 0.2 s tick: no target
  EXPECT_FALSE(m_03.has_value());
  ap::DelayLine n(0.18);
  n.push_and_read(0.1, 0.5);
  n.push_and_read(0.2, std::nullopt);
  const auto n_03 = n.push_and_read(0.3, std::nullopt);  // 0.12 s: nearer the 0.1 s tick: 0.5 m
  ASSERT_TRUE(n_03.has_value());
  EXPECT_DOUBLE_EQ(*n_03, 0.5);
}

// What ARGoS cannot apply stops it at Init, naming the effect and why.
TEST(CalibratedDrive, EffectsArgosCannotApplyAreRefusedByName) {
  // A file otherwise valid: the covariate is refused at its own line:column (the column of its
  // value, counted in the text here).
  static const std::string text = R"({"parameters":{"steps_per_m":7763.656},"effects":{"covariate:temperature_c":{"slope":1,"centre":20}}})";
  const std::string cov = error_of([] { config_of("cov.json", text); });
  const std::string where = "epuck2_argos_drive_test_cov.json:1:" + std::to_string(text.find("{\"slope\"") + 1) + ":";
  EXPECT_NE(cov.find(where), std::string::npos) << cov << " (expected " << where << ")";
  EXPECT_NE(cov.find("covariate:temperature_c"), std::string::npos) << cov;
  EXPECT_NE(cov.find("'temperature_c', which ARGoS does not have"), std::string::npos) << cov;
  const std::string unknown = error_of([] { config_of("unk.json", R"({"parameters":{"steps_per_m":7763.656},"effects":{"ambient_offset":{"offset":3}}})"); });
  EXPECT_NE(unknown.find("ambient_offset"), std::string::npos) << unknown;
  const std::string bad = error_of([] { config_of("bad.json", R"({"parameters":{"steps_per_m":7763.656},"effects":{"accel_limit":{"accel_cm_s2":"x"}}})"); });
  EXPECT_NE(bad.find("accel_limit"), std::string::npos) << bad;
}

// A part refuses at Init a non-neutral effect it does not apply, at the value's line:column (counted
// in the text here), whether the effect lives in "effects" or in "parameters"; the same file passes
// where the effect is applied.
TEST(AppliedEffects, AnEffectThePartDoesNotApplyIsRefusedAtItsValue) {
  const std::string text = R"({"kind":"drive","parameters":{"steps_per_m":7763.656,"tof_scale":1.25},
"effects":{"speed_scale":{"k":0.9}}})";
  const std::string path = write_temp("applied.json", text);
  const auto root = nlohmann::json::parse(text);
  const ms::DriveModel m = co::drive_model_from_json(root, path, "");
  // The wheels do not apply the ToF's scale (a "parameters" effect): its value's position.
  const std::string tof = error_of([&] { ap::refuse_unapplied(m, ap::wheels_apply(), root, path, "", "the wheels"); });
  const std::string at_tof = "epuck2_argos_drive_test_applied.json:1:" + std::to_string(text.find("1.25") + 1) + ":";
  EXPECT_NE(tof.find(at_tof), std::string::npos) << tof << " (expected " << at_tof << ")";
  EXPECT_NE(tof.find("parameters.tof_scale (tof_scale): the wheels does not apply it in ARGoS"), std::string::npos) << tof;
  EXPECT_NE(tof.find("ARGoS applies speed_limit, accel_limit, wheel_slip and speed_scale"), std::string::npos) << tof;
  // The ToF does not apply the speed scale (an "effects" effect): line 2, the object's column.
  const std::string scale = error_of([&] { ap::refuse_unapplied(m, ap::tof_applies(), root, path, "", "the ToF"); });
  const std::size_t line2 = text.find('\n') + 1;
  const std::string at_scale = "epuck2_argos_drive_test_applied.json:2:" + std::to_string(text.find("{\"k\":0.9}") - line2 + 1) + ":";
  EXPECT_NE(scale.find(at_scale), std::string::npos) << scale << " (expected " << at_scale << ")";
  EXPECT_NE(scale.find("effects.speed_scale: the ToF does not apply it in ARGoS"), std::string::npos) << scale;
  // What ARGoS applies of a drive file (wheels and ToF together): accepted, as read_drive_config does.
  EXPECT_EQ(error_of([&] { ap::refuse_unapplied(m, ap::drive_applies(), root, path, "", "ARGoS"); }), "");
  EXPECT_EQ(error_of([&] { config_of("applied.json", text); }), "");
}

/// A model of `Model` with every parameter of every effect away from its neutral value, inside its range.
template <class Model>
Model every_effect_on() {
  Model m;
  const fx::Catalogue& c = fx::catalogue_of(m);
  fx::for_each_param(fx::effects_of(m), [&](std::size_t id, int p, int, double& v) {
    const fx::Param& q = c[id].params[static_cast<std::size_t>(p)];
    v = q.lower + 0.25 * (std::min(q.upper, 1e4) - q.lower);
    if (v == q.neutral) v = q.lower;
  });
  return m;
}

/// Each effect of the kind that its model struct carries is applied by ARGoS (nothing shipped or
/// diagnosed is refused), and taken off the list it is refused by name.
template <class Model>
void check_every_effect_applied(const ap::Applied& applied) {
  const Model m = every_effect_on<Model>();
  const fx::Catalogue& c = fx::catalogue_of(m);
  const std::string path = write_temp("every.json", "{}");
  EXPECT_EQ(error_of([&] { ap::refuse_unapplied(m, applied, nlohmann::json::object(), path, "", "ARGoS"); }), "");
  for (std::size_t id = 0; id < c.size(); ++id) {
    if (c[id].home == fx::Home::base) continue;  // folded into the base coefficients by the reader
    ap::Applied without;
    for (std::size_t a : applied)
      if (a != id) without.push_back(a);
    const std::string e = error_of([&] { ap::refuse_unapplied(m, without, nlohmann::json::object(), path, "", "ARGoS"); });
    EXPECT_NE(e.find("ARGoS does not apply it"), std::string::npos) << c[id].name << ": " << e;
    EXPECT_NE(e.find(std::string("a file whose ") + c[id].name + " is not neutral"), std::string::npos) << c[id].name << ": " << e;
  }
}

TEST(AppliedEffects, ARGoSAppliesEveryEffectOfEveryKindItRuns) {
  check_every_effect_applied<ms::ProximityModel>(ap::proximity_applies());
  check_every_effect_applied<ms::LightModel>(ap::light_applies());
  check_every_effect_applied<ms::GroundModel>(ap::ground_applies());
  check_every_effect_applied<ms::CameraModel>(ap::camera_applies());
  check_every_effect_applied<ms::DriveModel>(ap::drive_applies());
  check_every_effect_applied<ms::BatteryModel>(ap::battery_applies());
}

// The shipped diagnosis of the drive logs: its speed limit, its slip.
TEST(CalibratedDrive, TheShippedDiagnosisLoads) {
  const std::string path = std::string(EPUCK2_SOURCE_DIR) + "/data/fitted/reports/diagnose_drive.json";
  std::ifstream in(path);
  const auto j = nlohmann::json::parse(in);
  const auto c = ap::read_drive_config(path, "the actuator");
  EXPECT_EQ(c.effects.speed_limit.max_cm_s, j.at("effects").at("speed_limit").at("max_cm_s").get<double>());
  EXPECT_EQ(c.effects.slip.tau_s, j.at("parameters").at("slip_time_constant_s").get<double>());
}

}  // namespace
