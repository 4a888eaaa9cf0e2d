// Sensor models (lib/models sensors.hpp): the plug-in's hand-checked values of
// the plug-in's source, the encoder's int16 wrap and carried partial steps,
// and every fitted formula instantiated for double, float and fit::Jet with its autodiff checked
// against central differences at the awkward points (distance 0, the cut-off, saturation).
#include "epuck2/fit/jet.hpp"
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

#include "epuck2/models/sensors.hpp"

namespace s = epuck2::models::sensors;

namespace {

// Central differences of a smooth function in double: error ~ h^2 f''' + eps f / h. With h = 1e-6
// relative and f = O(1e3) the error stays below 1e-5 relative; tolerance in relative terms.
constexpr double kDerivativeRelTolerance = 1e-5;
// float carries 24 bits: 6e-8 relative; the formulas lose a few digits in cancellations.
constexpr double kFloatRelTolerance = 1e-5;
// A Jet's value against the double evaluation: a few ulps of cancellation in 1 - r^2.
constexpr double kValueRelTolerance = 1e-14;

// Checks d f / d p_k of f(p) (f written once as a template, called through `eval`) against
// central differences, for every parameter.
template <int N, class F>
void expect_jet_matches_numeric(const F& f, std::array<double, N> p, const char* where) {
  using Jet = epuck2::fit::Jet<N>;
  std::array<Jet, N> pj;
  for (int k = 0; k < N; ++k) pj[k] = Jet(p[k], k);
  const Jet value = f(pj.data());
  for (int k = 0; k < N; ++k) {
    const double h = 1e-6 * std::max(1.0, std::abs(p[k]));
    std::array<double, N> up = p, down = p;
    up[k] += h;
    down[k] -= h;
    const double numeric = (f(up.data()) - f(down.data())) / (2 * h);
    const double scale = std::max({1.0, std::abs(numeric), std::abs(value.v[k])});
    EXPECT_NEAR(value.v[k], numeric, kDerivativeRelTolerance * scale) << where << ", parameter " << k;
  }
  // Jet's division multiplies by a reciprocal: the value may differ from double's in the last bits.
  EXPECT_NEAR(value.a, f(p.data()), kValueRelTolerance * std::max(1.0, std::abs(value.a))) << where;
}

}  // namespace

// ----- Proximity -----------------------------------------------------------------------------

TEST(Proximity, PluginPolynomialMatchesReferenceSampleValues) {
  // the plug-in's source: d -> new (E-Puck2) / old (E-Puck v1) readings.
  struct Row {
    double d_m;
    int new_raw, old_raw;
  };
  const std::vector<Row> rows{{0.005, 3539, 3706}, {0.01, 2976, 3043}, {0.02, 1971, 1899}, {0.03, 1128, 999}, {0.04, 448, 345}};
  for (const Row& r : rows) {
    EXPECT_EQ(s::proximity_reading(s::kPluginProximity, r.d_m), r.new_raw) << "d = " << r.d_m;
    EXPECT_EQ(s::proximity_reading(s::kEpuck1Proximity, r.d_m), r.old_raw) << "d = " << r.d_m;
  }
}

TEST(Proximity, ClampsCutsOffAndSaturates) {
  EXPECT_EQ(s::proximity_reading(s::kPluginProximity, 0.0), 4095);       // poly(0) = 1.0116 > 1
  EXPECT_EQ(s::proximity_reading(s::kPluginProximity, 0.049), 0);        // past the zero crossing 0.04843
  EXPECT_EQ(s::proximity_reading(s::kPluginProximity, 0.0500001), 0);    // beyond the range
  EXPECT_EQ(s::proximity_reading(s::kPluginProximity, std::nullopt), 0); // no hit
  // Zero crossings of the two polynomials (the plug-in's source).
  const double abc_new[3] = {s::kPluginProximity.a_per_m2, s::kPluginProximity.b_per_m, s::kPluginProximity.c};
  const double abc_old[3] = {s::kEpuck1Proximity.a_per_m2, s::kEpuck1Proximity.b_per_m, s::kEpuck1Proximity.c};
  EXPECT_GT(s::proximity_polynomial(abc_new, 0.04842), 0.0);
  EXPECT_LT(s::proximity_polynomial(abc_new, 0.04844), 0.0);
  EXPECT_GT(s::proximity_polynomial(abc_old, 0.04791), 0.0);
  EXPECT_LT(s::proximity_polynomial(abc_old, 0.04793), 0.0);
}

TEST(Proximity, NoiseIsUniformWithinItsLevelAndSeeded) {
  s::UnitUniform a(7), b(7);
  const double level = 0.05;
  int lo = 4095, hi = 0;
  for (int i = 0; i < 2000; ++i) {
    const int ra = s::proximity_reading(s::kPluginProximity, 0.02, level, a);
    const int rb = s::proximity_reading(s::kPluginProximity, 0.02, level, b);
    ASSERT_EQ(ra, rb);  // same seed, same stream
    lo = std::min(lo, ra);
    hi = std::max(hi, ra);
  }
  const double centre = 1971;  // reference 2.1 at 0.02 m
  EXPECT_GE(lo, centre - level * 4095 - 1);
  EXPECT_LE(hi, centre + level * 4095 + 1);
  EXPECT_LT(lo, centre - 0.9 * level * 4095);  // the whole band is used
  EXPECT_GT(hi, centre + 0.9 * level * 4095);
}

// The seeded Gaussian draw (noise.hpp): Box-Muller on UnitUniform's numbers, so the first two
// draws are sqrt(-2 ln(1 - u1)) cos(2 pi u2) and sqrt(-2 ln(1 - u1)) sin(2 pi u2) of the first two
// uniforms (1 - u1 in (0, 1]: no log of 0).
TEST(Noise, StandardNormalIsBoxMullerOnTheSeededUniforms) {
  s::UnitUniform u(42);
  const double u1 = u(), u2 = u(), u3 = u(), u4 = u();
  const double pi = 3.14159265358979323846;
  s::StandardNormal n(42);
  EXPECT_DOUBLE_EQ(n(), std::sqrt(-2 * std::log(1 - u1)) * std::cos(2 * pi * u2));
  EXPECT_DOUBLE_EQ(n(), std::sqrt(-2 * std::log(1 - u1)) * std::sin(2 * pi * u2));
  EXPECT_DOUBLE_EQ(n(), std::sqrt(-2 * std::log(1 - u3)) * std::cos(2 * pi * u4));
  // Same seed, same numbers; another seed, others.
  s::StandardNormal a(9), b(9), c(10);
  for (int i = 0; i < 100; ++i) ASSERT_EQ(a(), b());
  EXPECT_NE(s::StandardNormal(9)(), c());
}

TEST(Noise, StandardNormalHasMeanZeroAndSdOne) {
  s::StandardNormal n(3);
  const int count = 200000;
  double sum = 0, sum2 = 0;
  int beyond2 = 0;
  for (int i = 0; i < count; ++i) {
    const double x = n();
    sum += x;
    sum2 += x * x;
    beyond2 += std::abs(x) > 2.0;
  }
  const double mean = sum / count, sd = std::sqrt(sum2 / count - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.01);  // its standard error is 1 / sqrt(200000) = 0.0022
  EXPECT_NEAR(sd, 1.0, 0.005);   // 0.0016
  // A normal's two-sided 2-sigma tail: 4.55 % (a uniform of the same sd has none).
  EXPECT_NEAR(beyond2 / static_cast<double>(count), 0.0455, 0.002);
}

TEST(Noise, GaussianUnitMakesAReadingAddTheGaussianInItsUnits) {
  // A ground reading at grey 0.5 with offset 0, gain 1000 reads 500; with a Gaussian of 12 counts
  // its readings' sd is sqrt(12^2 + 1/12) (the rounding to whole counts), their mean 500.
  s::StandardNormal n(5);
  s::GaussianUnit g(n, 12.0, s::kPluginNoiseScaleGround_counts);
  const s::GroundCoefficients k{1000.0, 0.0};
  const int count = 50000;
  double sum = 0, sum2 = 0;
  for (int i = 0; i < count; ++i) {
    const double r = s::ground_reading(k, 0.5, 1.0, g);
    sum += r;
    sum2 += r * r;
  }
  const double mean = sum / count, sd = std::sqrt(sum2 / count - mean * mean);
  EXPECT_NEAR(mean, 500.0, 0.25);
  EXPECT_NEAR(sd, std::sqrt(144.0 + 1.0 / 12.0), 0.15);
  // The same for the ToF in mm and a proximity reading in counts.
  s::GaussianUnit t(n, 5.0, s::kPluginNoiseScaleTof_mm);
  sum = sum2 = 0;
  for (int i = 0; i < count; ++i) {
    const double r = s::tof_reading_mm(s::kPluginTof, 0.5, 1.0, t);
    sum += r;
    sum2 += r * r;
  }
  EXPECT_NEAR(sum / count, 500.0, 0.1);
  EXPECT_NEAR(std::sqrt(sum2 / count - (sum / count) * (sum / count)), std::sqrt(25.0 + 1.0 / 12.0), 0.07);
  // The uniform level with the same variance: sqrt(3) sd / scale.
  EXPECT_NEAR(s::uniform_level_with_sd(41.0, 4095.0), 41.0 * std::sqrt(3.0) / 4095.0, 1e-15);
  // sd 0 draws nothing.
  s::StandardNormal m(5), m_copy(5);
  EXPECT_EQ(s::gaussian_noise(m, 0.0), 0.0);
  EXPECT_EQ(m(), m_copy());
}

TEST(Proximity, PolynomialForFloatDoubleAndJet) {
  const float abc_f[3] = {197.8633f, -30.47182f, 1.011635f};
  const double abc_d[3] = {197.8633, -30.47182, 1.011635};
  for (double d : {0.0, 0.02, 0.04843, 0.05}) {
    const double vd = s::proximity_polynomial(abc_d, d);
    const float vf = s::proximity_polynomial(abc_f, d);
    EXPECT_NEAR(vf, vd, kFloatRelTolerance) << d;
    // Awkward points: 0, the zero crossing, the cut-off.
    expect_jet_matches_numeric<3>([d](const auto* p) { return s::proximity_polynomial(p, d); },
                                  {abc_d[0], abc_d[1], abc_d[2]}, "proximity");
  }
}

// ----- Light ---------------------------------------------------------------------------------

TEST(Light, PluginMatchesReferenceValues) {
  // the plug-in's source: intensity 1 saturates at d <= 0.075 m; 0.1 m -> 1792; 0.2 m -> 3519.
  EXPECT_EQ(s::light_reading(s::kPluginLight, 1.0, 0.1), 1792);
  EXPECT_EQ(s::light_reading(s::kPluginLight, 1.0, 0.2), 3519);
  EXPECT_EQ(s::light_reading(s::kPluginLight, 1.0, 0.075), 0);
  EXPECT_EQ(s::light_reading(s::kPluginLight, 1.0, 0.05), 0);
  EXPECT_GT(s::light_reading(s::kPluginLight, 1.0, 0.0751), 0);
  EXPECT_EQ(s::light_reading(s::kPluginLight, 1.0, 0.51), 4095);  // beyond 0.5 m: dark
  EXPECT_EQ(s::light_reading(s::kPluginLight, 0.0, 0.1), 4095);   // I = 0 is ignored
  // Two lights add up: two of intensity 1 at 0.2 m = 1 - 2 * 0.140625.
  s::NoNoise none;
  const std::array<s::LightSource, 2> two{{{0.2, 1.0}, {0.2, 1.0}}};
  EXPECT_EQ(s::light_reading(s::kPluginLight, two, 0.0, none), static_cast<int>(std::round((1 - 2 * 0.140625) * 4095)));
}

TEST(Light, ResponseForFloatDoubleAndJet) {
  for (double d : {0.075, 0.1, 0.5}) {
    const double vd = s::light_response(0.075, 1.0, d);
    const float vf = s::light_response(0.075f, 1.0, d);
    EXPECT_NEAR(vf, vd, kFloatRelTolerance);
    expect_jet_matches_numeric<1>([d](const auto* p) { return s::light_response(p[0], 1.3, d); }, {0.075}, "light");
  }
}

// ----- Ground --------------------------------------------------------------------------------

TEST(Ground, PluginMatchesReference) {
  // the plug-in's source: grey * 4.011764706, rounded, clamped to [0, 1023].
  EXPECT_EQ(s::ground_reading_plugin(0), 0);
  EXPECT_EQ(s::ground_reading_plugin(255), 1023);
  EXPECT_EQ(s::ground_reading_plugin(128), 514);  // 513.506
  EXPECT_EQ(s::ground_reading_plugin(100), 401);  // 401.176
  // The [0, 1] form with the plug-in's coefficients agrees at every grey level.
  for (int g = 0; g <= 255; ++g) EXPECT_EQ(s::ground_reading(s::kPluginGround, g / 255.0), s::ground_reading_plugin(g)) << g;
  // Noise of level 1 moves a mid-grey anywhere, clamped.
  s::UnitUniform u(3);
  for (int i = 0; i < 200; ++i) {
    const int r = s::ground_reading_plugin(128, 1.0, u);
    EXPECT_GE(r, 0);
    EXPECT_LE(r, 1023);
  }
}

TEST(Ground, ResponseForFloatDoubleAndJet) {
  EXPECT_NEAR(s::ground_response(900.0f, 50.0f, 0.5), s::ground_response(900.0, 50.0, 0.5), kFloatRelTolerance * 500);
  for (double g : {0.0, 0.5, 1.0})
    expect_jet_matches_numeric<2>([g](const auto* p) { return s::ground_response(p[0], p[1], g); }, {900.0, 50.0}, "ground");
}

// ----- ToF -----------------------------------------------------------------------------------

TEST(Tof, PluginReadings) {
  EXPECT_EQ(s::tof_reading_mm(s::kPluginTof, 0.3), 300);
  EXPECT_EQ(s::tof_reading_mm(s::kPluginTof, 0.1234), 123);
  EXPECT_EQ(s::tof_reading_mm(s::kPluginTof, std::nullopt), 2000);  // no hit: 2.0 m
  EXPECT_EQ(s::tof_reading_mm(s::kPluginTof, 0.005), 20);           // clamped to the minimum
  EXPECT_EQ(s::tof_reading_mm(s::kPluginTof, 2.5), 2000);
  s::UnitUniform u(11);
  for (int i = 0; i < 200; ++i) {
    const int r = s::tof_reading_mm(s::kPluginTof, 0.5, 0.01, u);  // noise 0.01 * 2.0 m = +-20 mm
    EXPECT_GE(r, 480);
    EXPECT_LE(r, 520);
  }
}

TEST(Tof, ResponseForFloatDoubleAndJet) {
  EXPECT_NEAR(s::tof_response_mm(0.98f, 9.0f, 0.3f), s::tof_response_mm(0.98, 9.0, 0.3), 1e-3);
  expect_jet_matches_numeric<2>([](const auto* p) { return s::tof_response_mm(p[0], p[1], decltype(p[0] + p[1])(0.02)); },
                                {0.98, 9.0}, "tof");
}

// ----- Encoders ------------------------------------------------------------------------------

TEST(Encoder, WrapsAtInt16) {
  s::Encoder e;
  e.set_count(32767.5);
  EXPECT_EQ(e.reading(), 32767);
  e.tick(1.0 / s::kPluginStepsPerMetre, 1.0);  // + 1 step (up to rounding of 1/7763.656 * 7763.656)
  EXPECT_EQ(e.reading(), -32768);
  e.set_count(-32768.0);
  e.tick(-0.5 / s::kPluginStepsPerMetre, 1.0);  // -0.5 step: -32768.5 wraps to +32767.5
  EXPECT_EQ(e.reading(), 32767);
}

TEST(Encoder, NoiseOnTheReadingLeavesTheCountAlone) {
  s::Encoder e;
  e.set_count(100.4);
  EXPECT_EQ(e.reading(0.7), 101);    // floor(101.1)
  EXPECT_EQ(e.reading(-0.5), 99);    // floor(99.9)
  EXPECT_EQ(e.count(), 100.4);       // the count does not accumulate the noise
  e.set_count(32767.5);
  EXPECT_EQ(e.reading(1.0), -32768);  // 32768.5 wraps to -32767.5
  e.set_count(-32768.0);
  EXPECT_EQ(e.reading(-0.25), 32767);  // -32768.25 wraps to 32767.75
}

TEST(Encoder, CarriesPartialSteps) {
  // 0.35 step per tick: floor reads 0, 0, 1, 1, 1, 2, ... not 0 forever (no partial sum lies
  // within rounding of an integer).
  s::Encoder e;
  const double v = 0.35 / s::kPluginStepsPerMetre;  // m/s giving 0.35 step per 1 s tick
  std::vector<int> readings;
  for (int i = 0; i < 10; ++i) {
    e.tick(v, 1.0);
    readings.push_back(e.reading());
  }
  EXPECT_EQ(readings, (std::vector<int>{0, 0, 1, 1, 1, 2, 2, 2, 3, 3}));
  // 1 m at 0.1 m/s over 100 ticks of 0.1 s: 7763 steps (floor of 7763.656 up to summation error).
  s::Encoder f;
  for (int i = 0; i < 100; ++i) f.tick(0.1, 0.1);
  EXPECT_EQ(f.reading(), 7763);
  // Backwards floors towards -infinity.
  s::Encoder g;
  g.tick(-0.3 / s::kPluginStepsPerMetre, 1.0);
  EXPECT_EQ(g.reading(), -1);
}

TEST(Encoder, UnwrapUndoesTheWrap) {
  double u = 32700;
  u = s::unwrap_steps(u, -32700);  // moved +136 through the wrap
  EXPECT_DOUBLE_EQ(u, 32836);
  u = s::unwrap_steps(u, 32700);  // and back
  EXPECT_DOUBLE_EQ(u, 32700);
  EXPECT_DOUBLE_EQ(s::unwrap_steps(-10, -20), -20);
}

// ----- Camera --------------------------------------------------------------------------------

TEST(Camera, ApertureGivesThePapersThirtyDegrees) {
  // the plug-in's source: 18.5 deg on the diagonal = 29.97 deg horizontally (the paper's alpha = 30).
  const double hfov_deg = s::rad_to_deg(s::horizontal_fov_from_aperture_rad(s::deg_to_rad(18.5)));
  EXPECT_NEAR(hfov_deg, 29.97, 0.005);
  EXPECT_NEAR(s::rad_to_deg(s::aperture_from_horizontal_fov_rad(s::deg_to_rad(hfov_deg))), 18.5, 1e-12);
  // Vertical field of view about 22.7 deg.
  const double vfov = 2 * std::atan(0.6 * std::tan(s::deg_to_rad(18.5)));
  EXPECT_NEAR(s::rad_to_deg(vfov), 22.7, 0.05);
}

TEST(Camera, ProjectionMatchesThePluginPixelMapping) {
  // The plug-in: scale the camera-frame vector by f/x, then i = -W/Wm (y' - Wm/2), j = -H/Hm (z' - Hm/2),
  // with Hm = 2 f tan(aperture)/sqrt(1 + AR^2), Wm = Hm AR (the plug-in's source).
  const auto cam = s::plugin_camera();
  const double f = s::kCameraFocal_m, ar = 160.0 / 120.0, ap = s::deg_to_rad(s::kCameraAperture_deg);
  const double hm = 2 * f * std::tan(ap) / std::sqrt(1 + ar * ar), wm = hm * ar;
  for (auto [x, y, z] : std::vector<std::array<double, 3>>{{0.5, 0.1, -0.03}, {0.3, -0.08, 0.05}, {0.9, 0.0, 0.0}}) {
    const double i = -160.0 / wm * (y * f / x - wm / 2), j = -120.0 / hm * (z * f / x - hm / 2);
    double px, py;
    s::camera_projection(cam.horizontal_fov_rad, cam.cx_px, cam.cy_px, 160.0, x, y, z, &px, &py);
    EXPECT_NEAR(px, i, 1e-9);
    EXPECT_NEAR(py, j, 1e-9);
  }
  // A point on the edge of the horizontal field of view lands on column 0.
  double px, py;
  const double x = 0.5, y = x * std::tan(cam.horizontal_fov_rad / 2);
  s::camera_projection(cam.horizontal_fov_rad, cam.cx_px, cam.cy_px, 160.0, x, y, 0.0, &px, &py);
  EXPECT_NEAR(px, 0.0, 1e-9);
  // Visibility: the diagonal cone and the 1 m range.
  EXPECT_TRUE(s::camera_sees(ap, 1.0, 0.5, 0.0, 0.0));
  EXPECT_FALSE(s::camera_sees(ap, 1.0, 1.1, 0.0, 0.0));
  EXPECT_FALSE(s::camera_sees(ap, 1.0, 0.5, 0.5 * std::tan(ap + 0.01), 0.0));
  EXPECT_FALSE(s::camera_sees(ap, 1.0, -0.5, 0.0, 0.0));
}

TEST(Camera, ProjectionForFloatDoubleAndJet) {
  float pxf, pyf;
  double pxd, pyd;
  s::camera_projection(0.523f, 80.0f, 60.0f, 160.0, 0.4, 0.1, -0.02, &pxf, &pyf);
  s::camera_projection(0.523, 80.0, 60.0, 160.0, 0.4, 0.1, -0.02, &pxd, &pyd);
  EXPECT_NEAR(pxf, pxd, 1e-3);
  EXPECT_NEAR(pyf, pyd, 1e-3);
  // Awkward points: on the axis, at the image edge, at a corner.
  for (auto [y, z] : std::vector<std::array<double, 2>>{{0.0, 0.0}, {0.107, 0.0}, {0.107, -0.08}}) {
    for (int out = 0; out < 2; ++out) {
      expect_jet_matches_numeric<3>(
          [y = y, z = z, out](const auto* p) {
            using T = std::remove_const_t<std::remove_reference_t<decltype(p[0])>>;
            T px, py;
            s::camera_projection(p[0], p[1], p[2], 160.0, 0.4, y, z, &px, &py);
            return out == 0 ? px : py;
          },
          {0.523, 81.0, 58.0}, "camera");
    }
  }
}

TEST(Camera, TableFourMethod) {
  // Paper Table 4, read as (x = distance, y = width seen across the image, same unit):
  // alpha = 2 atan(y / (2 x)). An object at the edge sits W/2 = 80 px from the centre.
  auto alpha_deg = [](double x, double y) { return s::rad_to_deg(s::alpha_from_pixel_offset_rad(x, y / 2, 80.0)); };
  EXPECT_NEAR(alpha_deg(263, 141), 30.0, 0.05);  // ARGoS
  EXPECT_NEAR(alpha_deg(143, 77), 30.1, 0.05);   // ARGoS
  EXPECT_NEAR(alpha_deg(250, 144), 32.1, 0.05);  // robot
  // The paper prints 29.5 deg for the robot's (150, 86); the same formula gives 32.0 deg, so that
  // row (and the robot mean 30.8) does not follow from the printed numbers.
  EXPECT_NEAR(alpha_deg(150, 86), 32.0, 0.05);
}

// ----- LEDs ----------------------------------------------------------------------------------

TEST(Leds, TableTwo) {
  ASSERT_EQ(s::kLeds.size(), 10u);
  int red = 0, rgb = 0, green = 0;
  for (const auto& l : s::kLeds) {
    red += l.colour == s::LedColour::red;
    rgb += l.colour == s::LedColour::rgb;
    green += l.colour == s::LedColour::green;
  }
  EXPECT_EQ(red, 5);  // 1, 3, 5, 7 and the front LED 9
  EXPECT_EQ(rgb, 4);
  EXPECT_EQ(green, 1);
  const auto p3 = s::led_position_m(s::kLeds[2]);  // LED 3 at 90 deg
  EXPECT_NEAR(p3[0], 0.0, 1e-12);
  EXPECT_NEAR(p3[1], 0.037, 1e-12);
  EXPECT_NEAR(p3[2], 0.048, 1e-12);
}

// Every LED of the paper's Table 2, one by one (typed from the table: 1..8 on the ring at
// 0, 45, ..., 315 deg, RED and RGB alternating from LED 1; 9 the front LED, red; 10 the body LED,
// green; ring radius 0.037 m, elevation 0.048 m from the plug-in's source), and the colours' names
// as docs/logs.md and the camera logs spell them.
TEST(Leds, EveryLedOfTableTwoAndItsPosition) {
  const char* colour[10] = {"red", "rgb", "red", "rgb", "red", "rgb", "red", "rgb", "red", "green"};
  for (int i = 0; i < 10; ++i) {
    SCOPED_TRACE("LED " + std::to_string(i + 1));
    const auto& l = s::kLeds[static_cast<std::size_t>(i)];
    EXPECT_EQ(l.number, i + 1);
    EXPECT_EQ(std::string(s::to_string(l.colour)), colour[i]);
    EXPECT_EQ(l.on_ring, i < 8);
    if (i >= 8) continue;
    EXPECT_DOUBLE_EQ(l.angle_deg, 45.0 * i);
    const auto p = s::led_position_m(l);
    const double a = 3.14159265358979323846 / 4 * i;  // 45 deg steps, counter-clockwise from +x
    EXPECT_NEAR(p[0], 0.037 * std::cos(a), 1e-15);
    EXPECT_NEAR(p[1], 0.037 * std::sin(a), 1e-15);
    EXPECT_DOUBLE_EQ(p[2], 0.048);
  }
  // LED 2 at 45 deg: x = y = 0.037 / sqrt 2 = 0.026163 m, worked by hand
  EXPECT_NEAR(s::led_position_m(s::kLeds[1])[0], 0.0261630, 1e-7);
  EXPECT_NEAR(s::led_position_m(s::kLeds[1])[1], 0.0261630, 1e-7);
  // LED 7 at 270 deg: (0, -0.037)
  EXPECT_NEAR(s::led_position_m(s::kLeds[6])[1], -0.037, 1e-15);
}

// The body, wheels and sensor positions, typed from the plug-in's source as the reference tables
// give them (body radius 0.035 m, wheels 0.053 m apart and 0.0205 m in radius, proximity ring at
// radius 0.036 m and height 0.043 m with angles -17, -50, -90, -150, 150, 90, 50, 17 deg for
// index 0..7, the ToF at (0.032, 0, 0.036), ground sensors at (0.03, -0.009), (0.03, 0),
// (0.03, 0.009) for right, centre, left).
TEST(Geometry, ThePlugInsBodyWheelsAndSensorPositions) {
  EXPECT_EQ(s::kProximityCount, 8);
  EXPECT_EQ(s::kGroundCount, 3);
  const double angles[8] = {-17, -50, -90, -150, 150, 90, 50, 17};
  for (int i = 0; i < 8; ++i) EXPECT_DOUBLE_EQ(s::kProximityAngles_deg[static_cast<std::size_t>(i)], angles[i]) << i;
  EXPECT_DOUBLE_EQ(s::kProximityRingRadius_m, 0.036);
  EXPECT_DOUBLE_EQ(s::kProximityElevation_m, 0.043);
  EXPECT_DOUBLE_EQ(s::kBodyRadius_m, 0.035);
  EXPECT_DOUBLE_EQ(s::kInterWheel_m, 0.053);
  EXPECT_DOUBLE_EQ(s::kWheelRadius_m, 0.0205);
  EXPECT_DOUBLE_EQ(s::kTofPosition_m[0], 0.032);
  EXPECT_DOUBLE_EQ(s::kTofPosition_m[1], 0.0);
  EXPECT_DOUBLE_EQ(s::kTofPosition_m[2], 0.036);
  const double ground[3][2] = {{0.03, -0.009}, {0.03, 0.0}, {0.03, 0.009}};
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_DOUBLE_EQ(s::kGroundPositions_m[i][0], ground[i][0]) << i;
    EXPECT_DOUBLE_EQ(s::kGroundPositions_m[i][1], ground[i][1]) << i;
  }
  // the plug-in's encoder scale follows from the wheel radius: 1000 / (2 pi 0.0205) = 7763.656 steps/m
  EXPECT_NEAR(1000.0 / (2 * s::kPi * s::kWheelRadius_m), 7763.656, 5e-4);
  // degrees and radians, worked by hand
  EXPECT_NEAR(s::deg_to_rad(180.0), 3.141592653589793, 1e-15);
  EXPECT_NEAR(s::deg_to_rad(-17.0), -0.29670597283903605, 1e-15);
  EXPECT_NEAR(s::rad_to_deg(1.0), 57.29577951308232, 1e-12);
  EXPECT_NEAR(s::rad_to_deg(-3.141592653589793 / 2), -90.0, 1e-12);
}
