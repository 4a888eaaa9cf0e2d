// Every formula of lib/models that is templated on the scalar, and every effect of the diagnosis
// catalogue that lib/models holds, evaluated in double, float and fit::Jet (the issue: "each
// formula is tested in double, float and Jet"). For each formula, at ordinary and awkward points:
//   1. double against a value computed here from the documented formula (docs/diagnose.md or the
//      header's comment), written out with std:: functions, never by calling the function itself;
//   2. float against double, to a float tolerance (and that the template instantiates for float);
//   3. fit::Jet: the value part equal to double's (bit for bit, except where the Jet divides: see
//      Check::divides), and every derivative against central differences of the double function
//      with a step chosen per parameter, to 1e-6 relative;
//   4. the neutral (default-constructed) effect struct gives the base reading exactly.
// Where a formula is deliberately not differentiable (a clamp's kink, the cut-off, a switch on a
// value) the points sit on both sides of it, never on it, and a comment says so.
//
// Coverage, header by header (D = double vs hand, F = float, J = Jet value + derivatives,
// N = neutral struct gives the base exactly):
//   proximity.hpp  proximity_polynomial (base Eq. 1)                                  D F J
//                  proximity_tail_raw (long_tail)                                     D F J N
//                  proximity_incidence_factor (incidence_angle)                       D F J N
//                  proximity_mean_raw<T> (base + ambient_offset, sensor_gain,
//                    long_tail, incidence_angle, saturation, each and together)       D F J N
//                  proximity_mean_raw(ProximityCoefficients, ...) double wrapper      D     N
//   light.hpp      light_contribution, light_response (base Eq. 2)                   D F J
//                  light_mean_raw<T> (base + ambient_offset, falloff_exponent,
//                    sensor_gain, each and together)                                  D F J N
//                  light_mean_raw(LightCoefficients, ...) double wrapper              D     N
//   ground.hpp     ground_response (base)                                            D F J
//                  ground_mean_raw<T> (nonlinear_response; black_offset, white_level
//                    and sensor_gain through its offset and gain, as lib/diagnose
//                    maps them)                                                       D F J N
//                  ground_mean_raw(GroundCoefficients, ...) double wrapper            D     N
//   tof.hpp        tof_response_mm (base; the calibration's scale and offset)         D F J N
//   camera.hpp     camera_projection (base pinhole, principal_offset through cx/cy,
//                    radial_distortion)                                               D F J N
//   drive.hpp      scalar_of                                                          D F J
//                  body_lag_piece (wheel_slip's exact lag)                            D F J N
//                  drive_advance, both wheels and `symmetric` (speed_limit,
//                    accel_limit, wheel_slip, speed_scale; latency's partial
//                    advance through its step h)                                      D F J N
//                  drive_tof_mean_mm (tof_offset, tof_scale)                          D F J N
//                  encoder_mean_steps (base)                                          D F J
//                  lagged_body_travel_m (wheel_slip in the drive calibration)         D F J N*
//   battery.hpp    cubic_charge, line_charge, polyline_charge (base formulas)         D F J
//                  step(Model, Tables, CapacityScale, ...) (capacity_scale)           D     N
//   kinds.hpp      mean_raw / mean_px / DriveSimulation (the models the simulation
//                    runs; latency's delayed ToF)                                     D     N
// Not covered in float or Jet, because they are not templated on the scalar: the battery's
// step() with CapacityScale (double only: lib/diagnose differentiates it by central differences),
// kinds.hpp's wrappers and DriveSimulation (double only), and noise.hpp (templated on the random
// source, not on the scalar; tested in test_sensor_models.cpp).
// N*: with tau = 0 lagged_body_travel_m gives the wheels' travel through the speeds
// (delta / dt) * dt, which equals the travel to within an ulp per interval, not bit for bit.
#include "epuck2/fit/jet.hpp"
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "epuck2/models/battery.hpp"
#include "epuck2/models/kinds.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"
#include "epuck2/models/sensors.hpp"

namespace s = epuck2::models::sensors;
namespace mb = epuck2::models::battery;

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kFull = 4095.0;
/// Values below this are compared absolutely: float's smallest normal number is 1.2e-38, below it
/// (a tail of e^-100, cos^7.5 of 1e-6) float keeps few digits or none.
constexpr double kTiny = 1e-30;  // proximity and light full scale, written out (paper: 12-bit ADC)

/// How one point is checked.
struct Check {
  /// The double result against the hand value, relative to mag() below. The hand formula is
  /// written differently (pow for exp-log, a d^2 + b d + c for Horner), so a few ulps differ.
  double expected_rel = 1e-13;
  /// float against double, relative to mag(): float carries 24 bits (6e-8); the inputs' own
  /// rounding to float and a few operations make about 1e-6, cancellations more (scale below).
  double float_rel = 1e-5;
  /// The size of the terms that make up a value (cancellations): tolerances are relative to
  /// max(|value|, scale). 0: the value's own size.
  double scale = 0;
  /// fit::Jet divides by multiplying by the reciprocal, as Ceres 2.1's jet.h does (a = f.a * (1 / g.a)), so where
  /// a formula divides a Jet its value part may differ from double's division in the last bits:
  /// then it is checked to 8 ulps of mag() instead of bit for bit.
  bool jet_divides = false;
  double derivative_rel = 1e-6;

  Check& with_scale(double v) { scale = v; return *this; }
  Check& with_float_rel(double v) { float_rel = v; return *this; }
  Check& with_expected_rel(double v) { expected_rel = v; return *this; }
  Check& divides() { jet_divides = true; return *this; }
  double mag(double v) const { return std::max(std::abs(v), scale); }
};

/// Steps for central differences, one per parameter: 1e-6 of the parameter's size, or of `floor`
/// when the parameter is near 0 (its natural unit). h^2 truncation ~1e-12 relative, rounding
/// ~eps f / h (the tolerance adds it).
template <std::size_t N>
std::array<double, N> steps_formulas(const std::array<double, N>& p, const std::array<double, N>& floor) {
  std::array<double, N> h{};
  for (std::size_t k = 0; k < N; ++k) h[k] = 1e-6 * std::max(std::abs(p[k]), floor[k]);
  return h;
}

/// Checks a formula f (a generic lambda: const T* parameters -> std::array<T, M> outputs) at the
/// parameters p against the hand values `expected` in double, in float against double, and with
/// Jets (value and every derivative whose step h[k] is not 0; h[k] = 0 marks a parameter at a
/// point where the function is deliberately not differentiable in it, whose Jet derivative must
/// still be finite).
template <std::size_t N, std::size_t M, class F>
void check_formulas(const std::string& where, const F& f, const std::array<double, N>& p, const std::array<double, M>& expected,
           const std::array<double, N>& h, const Check& c = Check{}) {
  SCOPED_TRACE(where);
  const std::array<double, M> vd = f(p.data());
  for (std::size_t m = 0; m < M; ++m)
    EXPECT_NEAR(vd[m], expected[m], c.expected_rel * c.mag(expected[m])) << "double against the hand value, output " << m;

  std::array<float, N> pf{};
  for (std::size_t k = 0; k < N; ++k) pf[k] = static_cast<float>(p[k]);
  const std::array<float, M> vf = f(pf.data());
  for (std::size_t m = 0; m < M; ++m)
    EXPECT_NEAR(static_cast<double>(vf[m]), vd[m], c.float_rel * c.mag(vd[m])) << "float against double, output " << m;

  using J = epuck2::fit::Jet<static_cast<int>(N)>;
  std::array<J, N> pj;
  for (std::size_t k = 0; k < N; ++k) pj[k] = J(p[k], static_cast<int>(k));
  const std::array<J, M> vj = f(pj.data());
  for (std::size_t m = 0; m < M; ++m) {
    if (c.jet_divides)
      EXPECT_NEAR(vj[m].a, vd[m], 8 * kEps * c.mag(vd[m])) << "Jet value against double, output " << m;
    else
      EXPECT_EQ(vj[m].a, vd[m]) << "Jet value against double, output " << m;
    for (std::size_t k = 0; k < N; ++k) {
      const double jet = vj[m].v[static_cast<int>(k)];
      EXPECT_TRUE(std::isfinite(jet)) << "Jet derivative, output " << m << ", parameter " << k;
      if (h[k] == 0) continue;
      std::array<double, N> up = p, down = p;
      up[k] += h[k];
      down[k] -= h[k];
      const double numeric = (f(up.data())[m] - f(down.data())[m]) / (2 * h[k]);
      const double rounding = 64 * kEps * c.mag(vd[m]) / h[k];
      const double tol = c.derivative_rel * std::max(std::abs(jet), std::abs(numeric)) + rounding;
      EXPECT_NEAR(jet, numeric, tol) << "Jet derivative against central differences, output " << m << ", parameter "
                                     << k << " (step " << h[k] << ")";
    }
  }
}

std::string at_formulas(const char* name, double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%s = %.9g", name, v);
  return b;
}
std::string at_formulas(const std::string& what, const char* name, double v) { return what + ", " + at_formulas(name, v); }

// ----- the documented formulas, written out ---------------------------------------------------

/// cos(theta)^k, the incidence_angle effect (docs/diagnose.md); the header's conventions where the
/// power is not defined: a surface at or past grazing incidence (cos <= 0) reflects nothing,
/// except at k = 0, the neutral value, which is the plug-in's model: no dependence on the angle.
double incidence_by_hand(double k, double cos_incidence) {
  if (cos_incidence > 0) return std::pow(cos_incidence, k);
  return k == 0 ? 1.0 : 0.0;
}

/// Proximity, docs/diagnose.md with every effect (the combination as proximity.hpp's comment
/// writes it): min(g_s cos^k 4095 clamp01(a d^2 + b d + c) [d <= range] + offset
/// + amplitude exp(-d/length), level). p = {a, b, c, offset, g_s, amplitude, length, k, level}.
/// The incidence_angle factor multiplies the clamped polynomial (docs/diagnose.md since session 12:
/// it wrote 4095 clamp01(cos^k poly) before, which differs only where poly > 1, d < 0.4 mm for the
/// plug-in's coefficients, and biased a diagnosis of logs with readings at 0 m made that way).
double proximity_by_hand(const std::array<double, 9>& p, double range, double d, double cos_incidence) {
  const double poly = p[0] * d * d + p[1] * d + p[2];
  const double hit = d <= range ? p[4] * incidence_by_hand(p[7], cos_incidence) * kFull * std::min(std::max(poly, 0.0), 1.0) : 0.0;
  const double tail = std::isfinite(d) ? p[5] * std::exp(-d / p[6]) : 0.0;
  return std::min(hit + p[3] + tail, p[8]);
}

/// Light, docs/diagnose.md: 4095 (1 - g_s (gamma I / d)^p) - offset for d <= range and I > 0, else
/// 4095 - offset. p = {gamma, offset, g_s, exponent}.
double light_by_hand(const std::array<double, 4>& p, double range, double intensity, double d) {
  if (d <= range && intensity > 0) return kFull * (1.0 - p[2] * std::pow(p[0] * intensity / d, p[3])) - p[1];
  return kFull - p[1];
}

/// Ground, docs/diagnose.md / ground.hpp: offset + gain grey^p, grey in [0, 1].
double ground_by_hand(double offset, double gain, double exponent, double grey) {
  return offset + gain * (grey > 0 ? std::pow(grey, exponent) : 0.0);
}

/// Camera, docs/diagnose.md: f = (W/2) / tan(h/2); x = lateral/forward, y = vertical/forward,
/// both scaled by (1 + k1 (x^2 + y^2)); px = cx - f x', py = cy - f y'.
std::array<double, 2> camera_by_hand(double hfov, double cx, double cy, double k1, double forward, double lateral,
                                     double vertical) {
  const double f = 80.0 / std::tan(hfov / 2.0);
  const double x = lateral / forward, y = vertical / forward;
  const double scale = 1.0 + k1 * (x * x + y * y);
  return {cx - f * x * scale, cy - f * y * scale};
}

/// The first-order lag of wheel_slip (docs/diagnose.md: dv_g/dt = (u(t) - v_g)/tau) integrated
/// numerically by RK4 from t0 to t1 with an input u(t) smooth on the interval: an integration
/// independent of the closed forms in drive.hpp. Steps of tau / 400 at most (the lag's scale):
/// RK4's error (dt/tau)^4 ~ 4e-11 of the transient.
template <class U>
void lag_by_rk4(const U& u, double tau, double t0, double t1, double& x, double& v) {
  if (!(t1 > t0)) return;
  const int n = static_cast<int>(std::clamp(std::ceil(400.0 * (t1 - t0) / tau), 2000.0, 4e6));
  const double dt = (t1 - t0) / n;
  auto dv = [&](double t, double vv) { return (u(t) - vv) / tau; };
  for (int i = 0; i < n; ++i) {
    const double t = t0 + i * dt;
    const double k1v = dv(t, v), k1x = v;
    const double k2v = dv(t + dt / 2, v + dt / 2 * k1v), k2x = v + dt / 2 * k1v;
    const double k3v = dv(t + dt / 2, v + dt / 2 * k2v), k3x = v + dt / 2 * k2v;
    const double k4v = dv(t + dt, v + dt * k3v), k4x = v + dt * k3v;
    x += dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    v += dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
  }
}

/// The same lag solved by hand: with u(t) = u0 + a t, v(t) = u(t) - a tau + C e^{-t/tau},
/// C = v0 - u0 + a tau (substitute: v' = a - C e/tau = (u - v)/tau), and x the integral of v.
std::array<double, 2> lag_closed_form(double tau, double u0, double a, double t, double x0, double v0) {
  if (tau == 0) return {x0 + u0 * t + a * t * t / 2, u0 + a * t};
  const double C = v0 - u0 + a * tau, e = std::exp(-t / tau);
  return {x0 + u0 * t + a * t * t / 2 - a * tau * t + C * tau * (1 - e), u0 + a * t - a * tau + C * e};
}

/// The drive by hand (docs/diagnose.md "drive" and drive.hpp's header): each wheel's command
/// clamped to +-max, reached at +-accel (a ramp, then constant; at once when accel >= 1e5, "no
/// limit"); the body's input k times the wheels' mean speed, through the lag (none at tau = 0).
/// Returns {xl, xr, vl, vr, xg, vg}.
struct DriveStart {
  double vl = 0, vr = 0, xl = 0, xr = 0, vg = 0, xg = 0;
};
std::array<double, 6> drive_by_hand(double max_cm_s, double accel_cm_s2, double tau, double k, double h, double left_cm_s,
                                    double right_cm_s, const DriveStart& st0) {
  const double u[2] = {std::clamp(left_cm_s, -max_cm_s, max_cm_s) / 100.0, std::clamp(right_cm_s, -max_cm_s, max_cm_s) / 100.0};
  const double v0[2] = {st0.vl, st0.vr}, x0[2] = {st0.xl, st0.xr};
  const bool limited = accel_cm_s2 < 1e5;
  const double A = accel_cm_s2 / 100.0;
  double ramp[2], sign[2];
  for (int w = 0; w < 2; ++w) {
    ramp[w] = limited ? std::abs(u[w] - v0[w]) / A : 0.0;
    sign[w] = u[w] > v0[w] ? 1.0 : -1.0;
  }
  auto speed = [&](int w, double t) { return limited && t < ramp[w] ? v0[w] + sign[w] * A * t : u[w]; };
  auto travel = [&](int w, double t) {
    if (!limited) return x0[w] + u[w] * t;
    const double r = std::min(t, ramp[w]);
    return x0[w] + v0[w] * r + sign[w] * A * r * r / 2 + u[w] * (t - r);
  };
  std::array<double, 6> out{travel(0, h), travel(1, h), speed(0, h), speed(1, h), st0.xg, st0.vg};
  if (tau == 0) {
    out[4] = st0.xg + k * ((out[0] - st0.xl) + (out[1] - st0.xr)) / 2;
    out[5] = k * (out[2] + out[3]) / 2;
    return out;
  }
  // The input is smooth between the ramps' ends: integrate piece by piece.
  std::vector<double> cuts{0.0};
  for (double r : ramp)
    if (r > 0 && r < h) cuts.push_back(r);
  cuts.push_back(h);
  std::sort(cuts.begin(), cuts.end());
  auto input = [&](double t) { return k * (speed(0, t) + speed(1, t)) / 2; };
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) lag_by_rk4(input, tau, cuts[i], cuts[i + 1], out[4], out[5]);
  return out;
}

}  // namespace

// =============================================================================================
// proximity.hpp
// =============================================================================================

TEST(ModelFormulas, ProximityPolynomial) {
  // Eq. 1 without its clamp: a d^2 + b d + c. Awkward points: d = 0, a tiny d, the cut-off 0.05.
  const std::array<double, 3> p{197.8633, -30.47182, 1.011635};
  for (double d : {0.0, 1e-7, 0.02, 0.04843, 0.05, 0.3}) {
    auto f = [d](const auto* q) {
      using T = std::decay_t<decltype(q[0])>;
      return std::array<T, 1>{s::proximity_polynomial(q, d)};
    };
    const double terms = std::abs(p[0] * d * d) + std::abs(p[1] * d) + std::abs(p[2]);
    check_formulas<3, 1>(at_formulas("proximity_polynomial", "d", d), f, p, {p[0] * d * d + p[1] * d + p[2]}, steps_formulas(p, {1.0, 1.0, 1.0}),
                Check().with_scale(terms));
  }
}

TEST(ModelFormulas, ProximityLongTail) {
  // long_tail: amplitude exp(-d / length). p = {amplitude, length}. Awkward: d = 0, tiny d, the
  // cut-off, a short length, far beyond (exp underflows towards 0), amplitude 0 (neutral).
  struct Point {
    double amplitude, length, d;
  };
  for (const Point& q : {Point{150.0, 0.02, 0.03}, Point{150.0, 0.02, 0.0}, Point{150.0, 0.02, 1e-9},
                         Point{80.0, 0.015, 0.05}, Point{80.0, 0.001, 0.004}, Point{80.0, 0.02, 2.0},
                         Point{0.0, 0.02, 0.03}, Point{3000.0, 1.0, 0.05}}) {
    auto f = [d = q.d](const auto* p) {
      using T = std::decay_t<decltype(p[0])>;
      return std::array<T, 1>{s::proximity_tail_raw(s::ProximityLongTail<T>{p[0], p[1]}, d)};
    };
    const std::array<double, 2> p{q.amplitude, q.length};
    check_formulas<2, 1>(at_formulas(at_formulas("proximity_tail_raw", "d", q.d), "length", q.length), f, p, {q.amplitude * std::exp(-q.d / q.length)},
                steps_formulas(p, {1.0, 1e-3}), Check().with_scale(kTiny));
  }
}

TEST(ModelFormulas, ProximityLongTailWithNoHitIsZeroWithFiniteDerivatives) {
  // No hit (kinds.hpp passes +inf; proximity_response treats inf and NaN as no hit): the tail's
  // limit is 0, and so are its derivatives (d/dlength of A e^{-d/L} = A d/L^2 e^{-d/L} -> 0).
  // A Jet used to compute -inf / length with derivative 0 * inf = NaN and poison every gradient.
  using J = epuck2::fit::Jet<2>;
  for (double d : {kInf, std::numeric_limits<double>::quiet_NaN()}) {
    EXPECT_EQ(s::proximity_tail_raw(s::ProximityLongTail<double>{150.0, 0.02}, d), 0.0);
    EXPECT_EQ(s::proximity_tail_raw(s::ProximityLongTail<float>{150.0f, 0.02f}, d), 0.0f);
    const J v = s::proximity_tail_raw(s::ProximityLongTail<J>{J(150.0, 0), J(0.02, 1)}, d);
    EXPECT_EQ(v.a, 0.0);
    EXPECT_EQ(v.v[0], 0.0);
    EXPECT_EQ(v.v[1], 0.0);
    // The whole mean: a no-hit row reads the offset, with derivative 1 in it and finite elsewhere.
    s::ProximityEffects<J> e;
    e.ambient.offset_raw = J(12.0, 0);
    e.tail.amplitude_raw = J(150.0, 1);
    const J abc[3] = {J(197.8633), J(-30.47182), J(1.011635)};
    const J m = s::proximity_mean_raw(abc, 0.05, e, 2, d, 1.0);
    EXPECT_EQ(m.a, 12.0);
    EXPECT_EQ(m.v[0], 1.0);
    EXPECT_EQ(m.v[1], 0.0);
  }
}

TEST(ModelFormulas, ProximityIncidenceFactor) {
  // incidence_angle: cos(theta)^k. p = {k}. Awkward: k = 0 (neutral), k near 1 and 2, cos = 1
  // exactly (log 0 in the derivative: d/dk = ln(1) = 0), a tiny cos (near grazing incidence).
  for (double k : {0.0, 1e-6, 0.5, 1.0, 1.0 + 1e-6, 2.0 - 1e-6, 2.0, 7.5}) {
    for (double c : {1.0, 1.0 - 1e-9, 0.9, 0.3, 1e-6}) {
      auto f = [c](const auto* p) {
        using T = std::decay_t<decltype(p[0])>;
        return std::array<T, 1>{s::proximity_incidence_factor(s::ProximityIncidence<T>{p[0]}, c)};
      };
      const std::array<double, 1> p{k};
      check_formulas<1, 1>(at_formulas(at_formulas("proximity_incidence_factor", "k", k), "cos", c), f, p, {std::pow(c, k)}, steps_formulas(p, {1e-2}),
                  Check().with_scale(kTiny));
    }
  }
}

TEST(ModelFormulas, ProximityIncidenceAtAndPastGrazing) {
  // cos <= 0 (90 degrees and beyond): the header's "0 at grazing incidence" for k > 0, but the
  // neutral k = 0 must leave the plug-in's model alone (it has no angle): cos^0 = 1. The
  // diagnosis evaluates the base model with the logged angle's cos when a log has angle_deg.
  // Not differentiable in k there (0^k jumps at k = 0): only the values and finite derivatives.
  using J = epuck2::fit::Jet<1>;
  for (double c : {0.0, -1e-12, -0.5, -1.0}) {
    EXPECT_EQ(s::proximity_incidence_factor(s::ProximityIncidence<double>{}, c), 1.0) << c;
    EXPECT_EQ(s::proximity_incidence_factor(s::ProximityIncidence<float>{}, c), 1.0f) << c;
    EXPECT_EQ(s::proximity_incidence_factor(s::ProximityIncidence<J>{}, c).a, 1.0) << c;
    for (double k : {1e-6, 1.0, 3.0}) {
      EXPECT_EQ(s::proximity_incidence_factor(s::ProximityIncidence<double>{k}, c), 0.0) << c << " " << k;
      EXPECT_EQ(s::proximity_incidence_factor(s::ProximityIncidence<float>{static_cast<float>(k)}, c), 0.0f);
      const J v = s::proximity_incidence_factor(s::ProximityIncidence<J>{J(k, 0)}, c);
      EXPECT_EQ(v.a, 0.0);
      EXPECT_TRUE(std::isfinite(v.v[0]));
    }
  }
}

namespace {

/// proximity_mean_raw with p = {a, b, c, offset, g_s, amplitude, length, k, level} for `sensor`
/// (the other sensors' gains 0.7, so that a wrong index shows).
auto proximity_formula(int sensor, double range, double d, double cos_incidence) {
  return [=](const auto* p) {
    using T = std::decay_t<decltype(p[0])>;
    s::ProximityEffects<T> e;
    e.ambient.offset_raw = p[3];
    for (auto& g : e.gains.gain) g = T(0.7);
    e.gains.gain[static_cast<std::size_t>(sensor)] = p[4];
    e.tail.amplitude_raw = p[5];
    e.tail.length_m = p[6];
    e.incidence.k = p[7];
    e.saturation.level_raw = p[8];
    return std::array<T, 1>{s::proximity_mean_raw(p, range, e, sensor, d, cos_incidence)};
  };
}

void check_proximity(const std::string& where, std::array<double, 9> p, double d, double cos_incidence = 1.0,
                     double range = 0.05, std::array<double, 9> h = {}) {
  if (h == std::array<double, 9>{}) h = steps_formulas(p, {1.0, 1.0, 1.0, 1e3, 1.0, 1e3, 1e-2, 1e-2, 1e3});
  const double terms = std::abs(p[3]) + std::abs(p[4]) * kFull + std::abs(p[5]);
  check_formulas<9, 1>(where, proximity_formula(5, range, d, cos_incidence), p, {proximity_by_hand(p, range, d, cos_incidence)}, h,
              Check().with_scale(terms));
}

constexpr double kA = 197.8633, kB = -30.47182, kC = 1.011635;  // the plug-in's Eq. 1 (docs/diagnose.md)

/// The distance at which the plug-in's polynomial equals v (the smaller root of a d^2 + b d + c = v).
double plugin_distance_at(double v) { return (-kB - std::sqrt(kB * kB - 4 * kA * (kC - v))) / (2 * kA); }

}  // namespace

TEST(ModelFormulas, ProximityMeanRawEveryEffect) {
  const double no_level = 1e9;
  // Ordinary: every effect on, the saturation not reached.
  check_proximity("all effects, d = 0.02", {kA, kB, kC, 35.0, 1.2, 150.0, 0.02, 1.5, no_level}, 0.02, 0.9);
  // Each effect alone (the others at their neutral values).
  check_proximity("ambient_offset alone", {kA, kB, kC, -42.0, 1.0, 0.0, 0.02, 0.0, no_level}, 0.02);
  check_proximity("sensor_gain alone", {kA, kB, kC, 0.0, 0.83, 0.0, 0.02, 0.0, no_level}, 0.02);
  check_proximity("long_tail alone", {kA, kB, kC, 0.0, 1.0, 220.0, 0.03, 0.0, no_level}, 0.04);
  check_proximity("incidence_angle alone", {kA, kB, kC, 0.0, 1.0, 0.0, 0.02, 2.0, no_level}, 0.02, 0.7);
  check_proximity("incidence_angle near k = 1", {kA, kB, kC, 0.0, 1.0, 0.0, 0.02, 1.0 + 1e-6, no_level}, 0.02, 0.7);
  check_proximity("incidence_angle at its neutral k = 0", {kA, kB, kC, 0.0, 1.0, 0.0, 0.02, 0.0, no_level}, 0.02, 0.7);
  // Zero offset with everything else on.
  check_proximity("zero offset", {kA, kB, kC, 0.0, 1.3, 90.0, 0.02, 0.8, no_level}, 0.01, 0.95);
  // saturation: the min's kink at v = level; both sides, 10 counts away (steps move v by < 1e-2).
  std::array<double, 9> p{kA, kB, kC, 35.0, 1.2, 150.0, 0.02, 1.5, no_level};
  const double v = proximity_by_hand(p, 0.05, 0.02, 0.9);
  p[8] = v - 10.0;
  check_proximity("saturated (level just below the reading)", p, 0.02, 0.9);
  p[8] = v + 10.0;
  check_proximity("not saturated (level just above the reading)", p, 0.02, 0.9);
}

TEST(ModelFormulas, ProximityMeanRawAtTheClampsAndTheCutOff) {
  const double no_level = 1e9;
  const std::array<double, 9> e{kA, kB, kC, 20.0, 1.1, 100.0, 0.02, 0.0, no_level};
  // clamp01's kinks at poly = 1 and poly = 0: just inside each (poly = 1 - 1e-3, 1e-3), and just
  // outside (poly = 1 + 1e-3 near d = 0, where a, b, c have no effect; poly < 0 past 0.04843).
  check_proximity("poly just below 1", e, plugin_distance_at(1.0 - 1e-3));
  check_proximity("poly just above 0", e, plugin_distance_at(1e-3));
  check_proximity("poly just below 0", e, 0.049);
  check_proximity("poly above 1 (d = 1e-6)", e, 1e-6);
  // poly > 1 with the incidence effect: cos^k times the clamped polynomial (proximity.hpp's
  // comment, docs/diagnose.md): 4095 * 0.92^2 * 1 = 4095 * 0.846 (not clamp01(cos^k poly), 0.856).
  std::array<double, 9> tilted = e;
  tilted[7] = 2.0;
  check_proximity("poly above 1, incidence (header's formula)", tilted, 1e-6, 0.92);
  // The cut-off d <= range (a jump: the polynomial's term vanishes beyond it). Coefficients whose
  // polynomial is inside (0, 1) there: 100 d^2 - 25 d + 1.8 = 0.8 at 0.05. At the cut-off (included),
  // and 1e-9 either side. The steps are in a, b, c and the effects, not in d: the jump is in d.
  const std::array<double, 9> cut{100.0, -25.0, 1.8, 20.0, 1.1, 100.0, 0.02, 0.0, no_level};
  for (double d : {0.05 - 1e-9, 0.05, 0.05 + 1e-9}) check_proximity(at_formulas("cut-off", "d", d), cut, d);
  // A tiny distance inside the clamps: 100 d^2 - 25 d + 0.9 at d = 1e-7.
  check_proximity("tiny distance", {100.0, -25.0, 0.9, 20.0, 1.1, 100.0, 0.02, 0.5, no_level}, 1e-7, 0.8);
  // Far beyond the range: offset and tail only.
  check_proximity("beyond the range", e, 0.3);
}

TEST(ModelFormulas, ProximityMeanRawEachEffectAtItsDefaultWithTheOthersOn) {
  // Each effect's struct default-constructed while every other effect is on: the formula without
  // that effect (its neutral value in the hand formula).
  const std::array<double, 9> on{kA, kB, kC, 35.0, 1.2, 150.0, 0.03, 1.5, 2000.0};
  for (int which = 0; which < 5; ++which) {
    for (double d : {0.0, 0.01, 0.02, 0.045, 0.06}) {
      s::ProximityEffects<double> e;
      std::array<double, 9> p = on;
      e.ambient.offset_raw = on[3];
      e.gains.gain.fill(on[4]);
      e.tail = {on[5], on[6]};
      e.incidence.k = on[7];
      e.saturation.level_raw = on[8];
      switch (which) {
        case 0: e.ambient = s::ProximityAmbientOffset<double>{}; p[3] = 0.0; break;
        case 1: e.gains = s::ProximitySensorGain<double>{}; p[4] = 1.0; break;
        case 2: e.tail = s::ProximityLongTail<double>{}; p[5] = 0.0; break;
        case 3: e.incidence = s::ProximityIncidence<double>{}; p[7] = 0.0; break;
        default: e.saturation = s::ProximitySaturation<double>{}; p[8] = 1e9; break;
      }
      const double abc[3] = {kA, kB, kC};
      EXPECT_NEAR(s::proximity_mean_raw(abc, 0.05, e, 3, d, 0.8), proximity_by_hand(p, 0.05, d, 0.8), 1e-9)
          << "effect " << which << " neutral, d = " << d;
    }
  }
}

TEST(ModelFormulas, ProximityNeutralEffectsGiveThePluginReadingExactly) {
  // Default effects: exactly 4095 clamp01(poly) for d <= range, 0 beyond or without a hit (the
  // base, proximity_response), at every angle (k = 0 ignores it), for every sensor, for double,
  // float (its own base: 4095 clamp01(poly) in float) and Jet (value).
  using J = epuck2::fit::Jet<3>;
  const double abc[3] = {kA, kB, kC};
  const float abcf[3] = {static_cast<float>(kA), static_cast<float>(kB), static_cast<float>(kC)};
  const J abcj[3] = {J(kA, 0), J(kB, 1), J(kC, 2)};
  const s::ProximityEffects<double> e;
  const s::ProximityEffects<float> ef;
  const s::ProximityEffects<J> ej;
  for (double d : {0.0, 1e-7, 0.005, 0.02, 0.045, 0.0484, 0.049, 0.05, 0.0500001, 0.3, kInf}) {
    for (double c : {1.0, 0.8, 1e-6, 0.0, -0.4}) {
      for (int sensor = 0; sensor < s::kProximityCount; ++sensor) {
        const double base = kFull * s::proximity_response(s::kPluginProximity, d);
        EXPECT_EQ(s::proximity_mean_raw(abc, 0.05, e, sensor, d, c), base) << d << " " << c << " " << sensor;
        EXPECT_EQ(s::proximity_mean_raw(s::kPluginProximity, e, sensor, d, c), base);
        const J vj = s::proximity_mean_raw(abcj, 0.05, ej, sensor, d, c);
        EXPECT_EQ(vj.a, base);
        const float polyf = s::proximity_polynomial(abcf, d);
        const float basef = d <= 0.05 ? static_cast<float>(kFull) * std::min(std::max(polyf, 0.0f), 1.0f) : 0.0f;
        EXPECT_EQ(s::proximity_mean_raw(abcf, 0.05, ef, sensor, d, c), basef) << d << " " << c;
      }
    }
  }
}

// =============================================================================================
// light.hpp
// =============================================================================================

TEST(ModelFormulas, LightContributionAndResponse) {
  // Eq. 2: (gamma I / d)^2 and 1 - (gamma I / d)^2. p = {gamma}. Awkward: a tiny distance, ratio 1
  // (the rail at 0), I = 0, a ratio near 0 (the rail at 4095).
  struct Point {
    double intensity, d;
  };
  for (const Point& q : {Point{1.0, 0.1}, Point{1.3, 0.2}, Point{1.0, 0.075}, Point{1.0, 1e-4}, Point{0.0, 0.1},
                         Point{0.01, 0.5}}) {
    const std::array<double, 1> p{0.075};
    const double r = p[0] * q.intensity / q.d;
    auto contribution = [q](const auto* g) {
      using T = std::decay_t<decltype(g[0])>;
      return std::array<T, 1>{s::light_contribution(g[0], q.intensity, q.d)};
    };
    auto response = [q](const auto* g) {
      using T = std::decay_t<decltype(g[0])>;
      return std::array<T, 1>{s::light_response(g[0], q.intensity, q.d)};
    };
    const std::string where = at_formulas(at_formulas("light", "I", q.intensity), "d", q.d);
    check_formulas<1, 1>(where + " contribution", contribution, p, {r * r}, steps_formulas(p, {1e-2}), Check().divides());
    check_formulas<1, 1>(where + " response", response, p, {1.0 - r * r}, steps_formulas(p, {1e-2}), Check().divides().with_scale(1.0 + r * r));
  }
}

namespace {

/// light_mean_raw with p = {gamma, offset, g_s, exponent} for sensor 2 (the others' gains 0.5).
auto light_formula(double range, double intensity, double d) {
  return [=](const auto* p) {
    using T = std::decay_t<decltype(p[0])>;
    s::LightEffects<T> e;
    e.ambient.offset_raw = p[1];
    for (auto& g : e.gains.gain) g = T(0.5);
    e.gains.gain[2] = p[2];
    e.falloff.exponent = p[3];
    return std::array<T, 1>{s::light_mean_raw(p[0], range, e, 2, intensity, d)};
  };
}

void check_light(const std::string& where, const std::array<double, 4>& p, double intensity, double d, double range = 0.5) {
  const double ratio_term = d <= range && intensity > 0 ? std::abs(p[2]) * std::pow(p[0] * intensity / d, p[3]) : 0.0;
  const double terms = kFull * (1.0 + ratio_term) + std::abs(p[1]);
  check_formulas<4, 1>(where, light_formula(range, intensity, d), p, {light_by_hand(p, range, intensity, d)},
              steps_formulas(p, {1e-2, 1e3, 1.0, 1.0}), Check().divides().with_scale(terms));
}

}  // namespace

TEST(ModelFormulas, LightMeanRawEveryEffect) {
  const double g = 0.075;
  check_light("all effects", {g, 20.0, 1.1, 2.3}, 1.2, 0.3);
  check_light("ambient_offset alone", {g, 35.0, 1.0, 2.0}, 1.0, 0.2);
  check_light("sensor_gain alone", {g, 0.0, 0.9, 2.0}, 1.0, 0.2);
  check_light("falloff_exponent alone", {g, 0.0, 1.0, 1.7}, 1.0, 0.2);
  // The exponent near 2 (its neutral value) and near 1, and exactly 2.
  for (double e : {2.0 - 1e-3, 2.0 - 1e-6, 2.0, 2.0 + 1e-6, 1.0, 1.0 + 1e-6})
    check_light(at_formulas("falloff near 1 or 2", "exponent", e), {g, 10.0, 1.05, e}, 1.0, 0.15);
  // gamma I / d = 1 exactly: ln 1 = 0 in the exponent's derivative.
  check_light("ratio 1", {g, 10.0, 1.05, 2.4}, 1.0, g);
  // Near the rails: a reading of about 1 count (ratio^2 = 1 - 1/4095) and of about 4094.
  const double d_low = g / std::sqrt(1.0 - 1.0 / kFull), d_high = g / std::sqrt(1.0 / kFull);
  check_light("reading near 0", {g, 0.0, 1.0, 2.0}, 1.0, d_low);
  check_light("reading near 4095", {g, 0.0, 1.0, 2.0}, 1.0, d_high);
  // A tiny distance (a reading far below 0: the mean is not clamped).
  check_light("tiny distance", {g, 5.0, 1.0, 2.2}, 0.001, 1e-4);
  // The cut-off d <= 0.5 (included) and just beyond it (a jump: 4095 - offset), and I = 0.
  for (double d : {0.5 - 1e-9, 0.5, 0.5 + 1e-9}) check_light(at_formulas("cut-off", "d", d), {g, 15.0, 1.1, 2.3}, 1.0, d);
  check_light("no intensity", {g, 15.0, 1.1, 2.3}, 0.0, 0.2);
}

TEST(ModelFormulas, LightNeutralEffectsGiveThePluginReadingExactly) {
  // Default effects: exactly 4095 (1 - (gamma I / d)^2) (light_response, the plug-in's Eq. 2
  // before its clamp) within range with I > 0, 4095 otherwise; double, float (against float's own
  // light_response) and Jet (value; its gamma divides, so against the Jet's light_response).
  using J = epuck2::fit::Jet<1>;
  const s::LightEffects<double> e;
  const s::LightEffects<float> ef;
  const s::LightEffects<J> ej;
  const double g = s::kPluginLight.gamma_m;
  for (double d : {1e-4, 0.05, 0.075, 0.1, 0.123, 0.2, 0.37, 0.5, 0.5000001, 3.0}) {
    for (double intensity : {0.0, 0.3, 1.0, 1.7}) {
      for (int sensor = 0; sensor < s::kProximityCount; ++sensor) {
        const bool lit = d <= 0.5 && intensity > 0;
        const double base = lit ? kFull * s::light_response(g, intensity, d) : kFull;
        EXPECT_EQ(s::light_mean_raw(g, 0.5, e, sensor, intensity, d), base) << d << " " << intensity;
        EXPECT_EQ(s::light_mean_raw(s::kPluginLight, e, sensor, intensity, d), base);
        const float gf = static_cast<float>(g);
        const float basef = lit ? static_cast<float>(kFull) * s::light_response(gf, intensity, d) : static_cast<float>(kFull);
        EXPECT_EQ(s::light_mean_raw(gf, 0.5, ef, sensor, intensity, d), basef) << d << " " << intensity;
        const J gj(g, 0);
        const J basej = lit ? kFull * s::light_response(gj, intensity, d) : J(kFull);
        EXPECT_EQ(s::light_mean_raw(gj, 0.5, ej, sensor, intensity, d).a, basej.a) << d << " " << intensity;
      }
    }
  }
}

// =============================================================================================
// ground.hpp
// =============================================================================================

TEST(ModelFormulas, GroundResponse) {
  // offset + gain grey. p = {gain, offset}. Awkward: grey 0 and 1 (the rails of a 0..1023
  // reading), a tiny grey, zero offset.
  for (double grey : {0.0, 1e-6, 0.25, 0.999, 1.0}) {
    for (const std::array<double, 2>& p : {std::array<double, 2>{1023.0, 0.0}, std::array<double, 2>{900.0, 61.4}}) {
      auto f = [grey](const auto* q) {
        using T = std::decay_t<decltype(q[0])>;
        return std::array<T, 1>{s::ground_response(q[0], q[1], grey)};
      };
      check_formulas<2, 1>(at_formulas(at_formulas("ground_response", "grey", grey), "offset", p[1]), f, p, {p[1] + p[0] * grey},
                  steps_formulas(p, {1e3, 1e3}), Check());
    }
  }
}

TEST(ModelFormulas, GroundMeanRawNonlinearResponse) {
  // offset + gain grey^p. p = {offset, gain, exponent}. Awkward: exponent 1 (neutral) and near
  // it, grey 0 (0 whatever the exponent: no log 0) and 1 (ln 1 = 0), a tiny grey, near 1023.
  for (double exponent : {1.0, 1.0 - 1e-6, 1.0 + 1e-6, 0.7, 1.6}) {
    for (double grey : {0.0, 1e-6, 0.4, 0.999, 1.0}) {
      for (const std::array<double, 3>& base : {std::array<double, 3>{61.4, 950.0, 0.0}, std::array<double, 3>{0.0, 1023.0, 0.0}}) {
        std::array<double, 3> p = base;
        p[2] = exponent;
        auto f = [grey](const auto* q) {
          using T = std::decay_t<decltype(q[0])>;
          return std::array<T, 1>{s::ground_mean_raw(q[0], q[1], s::GroundNonlinear<T>{q[2]}, grey)};
        };
        check_formulas<3, 1>(at_formulas(at_formulas(at_formulas("ground_mean_raw", "grey", grey), "exponent", exponent), "offset", p[0]), f, p,
                    {ground_by_hand(p[0], p[1], p[2], grey)}, steps_formulas(p, {1e3, 1e3, 1.0}),
                    Check());
      }
    }
  }
}

TEST(ModelFormulas, GroundCatalogueEffectsThroughOffsetAndGain) {
  // docs/diagnose.md's ground effects, each alone, through ground_mean_raw's offset and gain as
  // lib/diagnose maps them (offset, (level - offset) g_s):
  //   black_offset  v = offset + (1023 - offset) grey        p = {offset}
  //   white_level   v = level grey                           p = {level}
  //   sensor_gain   v = g_s 1023 grey                        p = {g_s}
  //   nonlinear     v = 1023 grey^p                          p = {p}
  for (double grey : {0.0, 1e-6, 0.3, 0.999, 1.0}) {
    const std::string g = at_formulas("grey", grey);
    auto black = [grey](const auto* q) {
      using T = std::decay_t<decltype(q[0])>;
      return std::array<T, 1>{s::ground_mean_raw(q[0], T(1023.0) - q[0], s::GroundNonlinear<T>{}, grey)};
    };
    check_formulas<1, 1>("black_offset " + g, black, std::array<double, 1>{61.4}, {61.4 + (1023.0 - 61.4) * grey},
                std::array<double, 1>{1e-3}, Check().with_scale(1023.0));
    check_formulas<1, 1>("black_offset 0 " + g, black, std::array<double, 1>{0.0}, {1023.0 * grey}, std::array<double, 1>{1e-3},
                Check().with_scale(1023.0));
    auto white = [grey](const auto* q) {
      using T = std::decay_t<decltype(q[0])>;
      return std::array<T, 1>{s::ground_mean_raw(T(0.0), q[0], s::GroundNonlinear<T>{}, grey)};
    };
    check_formulas<1, 1>("white_level " + g, white, std::array<double, 1>{880.0}, {880.0 * grey}, std::array<double, 1>{1e-3},
                Check());
    auto gain = [grey](const auto* q) {
      using T = std::decay_t<decltype(q[0])>;
      return std::array<T, 1>{s::ground_mean_raw(T(0.0), T(1023.0) * q[0], s::GroundNonlinear<T>{}, grey)};
    };
    check_formulas<1, 1>("sensor_gain " + g, gain, std::array<double, 1>{0.9512}, {0.9512 * 1023.0 * grey},
                std::array<double, 1>{1e-6}, Check());
    auto nonlinear = [grey](const auto* q) {
      using T = std::decay_t<decltype(q[0])>;
      return std::array<T, 1>{s::ground_mean_raw(T(0.0), T(1023.0), s::GroundNonlinear<T>{q[0]}, grey)};
    };
    check_formulas<1, 1>("nonlinear_response " + g, nonlinear, std::array<double, 1>{1.25},
                {grey > 0 ? 1023.0 * std::pow(grey, 1.25) : 0.0}, std::array<double, 1>{1e-6}, Check());
  }
}

TEST(ModelFormulas, GroundNeutralNonlinearGivesTheLinearReadingExactly) {
  // GroundNonlinear{} (exponent 1): exactly ground_response, offset + gain grey, in double,
  // float and Jet, and through the double wrapper.
  using J = epuck2::fit::Jet<2>;
  for (double grey : {0.0, 1e-9, 1e-6, 0.1, 1.0 / 3.0, 0.5, 0.7, 0.999, 1.0}) {
    for (const s::GroundCoefficients& k : {s::kPluginGround, s::GroundCoefficients{950.0, 61.4}, s::GroundCoefficients{1000.3, -7.25}}) {
      const double base = s::ground_response(k.gain_raw, k.offset_raw, grey);
      EXPECT_EQ(s::ground_mean_raw(k.offset_raw, k.gain_raw, s::GroundNonlinear<double>{}, grey), base) << grey;
      EXPECT_EQ(s::ground_mean_raw(k, s::GroundNonlinear<double>{}, grey), base) << grey;
      const float of = static_cast<float>(k.offset_raw), gf = static_cast<float>(k.gain_raw);
      EXPECT_EQ(s::ground_mean_raw(of, gf, s::GroundNonlinear<float>{}, grey), s::ground_response(gf, of, grey)) << grey;
      const J oj(k.offset_raw, 0), gj(k.gain_raw, 1);
      EXPECT_EQ(s::ground_mean_raw(oj, gj, s::GroundNonlinear<J>{}, grey).a, base) << grey;
    }
  }
}

// =============================================================================================
// tof.hpp
// =============================================================================================

TEST(ModelFormulas, TofResponse) {
  // scale 1000 d + offset. p = {scale, offset, d}. Awkward: near the rails 20 and 2000 mm, d = 0,
  // a tiny d, zero offset, scale 1 (the plug-in's).
  struct Point {
    double scale, offset, d;
  };
  for (const Point& q : {Point{1.02, 15.0, 0.5}, Point{0.98, -9.0, 0.3}, Point{1.0, 0.0, 0.0205}, Point{1.0, 0.0, 1.999},
                         Point{1.01, 0.0, 0.0}, Point{1.01, 3.0, 1e-7}, Point{1.0, 0.0, 0.123}}) {
    auto f = [](const auto* p) {
      using T = std::decay_t<decltype(p[0])>;
      return std::array<T, 1>{s::tof_response_mm(p[0], p[1], p[2])};
    };
    const std::array<double, 3> p{q.scale, q.offset, q.d};
    check_formulas<3, 1>(at_formulas(at_formulas("tof_response_mm", "d", q.d), "offset", q.offset), f, p, {q.scale * 1000.0 * q.d + q.offset},
                steps_formulas(p, {1.0, 1e3, 1.0}), Check().with_scale(std::abs(q.scale * 1000.0 * q.d) + std::abs(q.offset)));
  }
  // The plug-in's scale 1 and offset 0: exactly 1000 d.
  for (double d : {0.0, 0.0205, 0.1, 0.123, 0.777, 1.999}) EXPECT_EQ(s::tof_response_mm(1.0, 0.0, d), 1000.0 * d);
}

// =============================================================================================
// camera.hpp
// =============================================================================================

TEST(ModelFormulas, CameraProjection) {
  // px = cx - f x (1 + k1 r^2), py = cy - f y (1 + k1 r^2), f = 80 / tan(h/2). p = {h, cx, cy, k1}.
  struct Point {
    double hfov_deg, cx, cy, k1, forward, lateral, vertical;
  };
  const double edge = 0.4 * std::tan(s::deg_to_rad(30.0) / 2.0) * 79.5 / 80.0;  // px = 0.5: near the image's edge
  for (const Point& q : {Point{30.0, 81.5, 58.0, 0.05, 0.4, 0.05, -0.03},   // ordinary, every effect
                         Point{29.97, 80.0, 60.0, 0.0, 0.4, 0.05, -0.03},   // the plug-in's (neutral effects)
                         Point{30.0, 80.0, 60.0, -0.2, 0.3, -0.06, 0.02},  // barrel distortion alone
                         Point{30.0, 78.0, 63.0, 0.0, 0.3, -0.06, 0.02},   // principal_offset alone
                         Point{30.0, 81.5, 58.0, 0.05, 0.5, 0.0, 0.0},     // on the axis (r = 0)
                         Point{30.0, 81.5, 58.0, 0.05, 0.5, 1e-7, -1e-7},  // a tiny offset from the axis
                         Point{30.0, 80.0, 60.0, 0.0, 0.4, edge, 0.0},     // at the image's edge
                         Point{170.0, 80.0, 60.0, 0.01, 0.2, 0.3, 0.1},    // a field of view near pi
                         Point{1.0, 80.0, 60.0, 0.01, 1.0, 0.001, 0.002}}) {  // a narrow one
    auto f = [q](const auto* p) {
      using T = std::decay_t<decltype(p[0])>;
      std::array<T, 2> out;
      s::camera_projection(p[0], p[1], p[2], 160.0, q.forward, q.lateral, q.vertical, &out[0], &out[1],
                           s::CameraRadialDistortion<T>{p[3]});
      return out;
    };
    const std::array<double, 4> p{s::deg_to_rad(q.hfov_deg), q.cx, q.cy, q.k1};
    const auto expected = camera_by_hand(p[0], p[1], p[2], p[3], q.forward, q.lateral, q.vertical);
    const double size = 80.0 / std::tan(p[0] / 2.0) * (std::abs(q.lateral) + std::abs(q.vertical)) / q.forward + 160.0;
    check_formulas<4, 2>(at_formulas(at_formulas("camera_projection", "hfov_deg", q.hfov_deg), "lateral", q.lateral), f, p, expected,
                steps_formulas(p, {1.0, 1e2, 1e2, 1e-1}), Check().divides().with_scale(size));
  }
}

TEST(ModelFormulas, CameraNeutralDistortionGivesThePinholeExactly) {
  // CameraRadialDistortion{} (k1 = 0) and the default argument: exactly the pinhole cx - f x,
  // f = (W/2) / tan(h/2), in double; and the Jet's value equals double's with the default argument.
  using J = epuck2::fit::Jet<3>;
  const s::CameraCoefficients c = s::plugin_camera();
  for (const std::array<double, 3>& point : {std::array<double, 3>{0.4, 0.05, -0.03}, std::array<double, 3>{0.9, -0.1, 0.07},
                                             std::array<double, 3>{0.3, 0.0, 0.0}, std::array<double, 3>{1.0, 1e-7, 2e-7}}) {
    const double f = 80.0 / std::tan(c.horizontal_fov_rad / 2.0);
    const double x = point[1] / point[0], y = point[2] / point[0];
    double px = 0, py = 0, px_default = 0, py_default = 0;
    s::camera_projection(c.horizontal_fov_rad, c.cx_px, c.cy_px, 160.0, point[0], point[1], point[2], &px, &py,
                         s::CameraRadialDistortion<double>{});
    s::camera_projection(c.horizontal_fov_rad, c.cx_px, c.cy_px, 160.0, point[0], point[1], point[2], &px_default, &py_default);
    EXPECT_EQ(px, 80.0 - f * x);
    EXPECT_EQ(py, 60.0 - f * y);
    EXPECT_EQ(px_default, px);
    EXPECT_EQ(py_default, py);
    const s::CameraModel m;
    EXPECT_EQ(s::mean_px(m, point[0], point[1], point[2])[0], px);
    EXPECT_EQ(s::mean_px(m, point[0], point[1], point[2])[1], py);
    J pxj, pyj, pxd, pyd;
    s::camera_projection(J(c.horizontal_fov_rad, 0), J(c.cx_px, 1), J(c.cy_px, 2), 160.0, point[0], point[1], point[2], &pxj, &pyj,
                         s::CameraRadialDistortion<J>{});
    s::camera_projection(J(c.horizontal_fov_rad, 0), J(c.cx_px, 1), J(c.cy_px, 2), 160.0, point[0], point[1], point[2], &pxd, &pyd);
    EXPECT_EQ(pxj.a, pxd.a);
    EXPECT_EQ(pyj.a, pyd.a);
  }
}

// =============================================================================================
// drive.hpp
// =============================================================================================

TEST(ModelFormulas, ScalarOf) {
  EXPECT_EQ(s::scalar_of(0.25), 0.25);
  EXPECT_EQ(s::scalar_of(0.1f), static_cast<double>(0.1f));
  EXPECT_EQ(s::scalar_of(epuck2::fit::Jet<2>(-3.5, 1)), -3.5);
}

namespace {

/// body_lag_piece with p = {tau, u0, ag, len, xg0, vg0} -> {xg, vg}.
auto body_lag_formula() {
  return [](const auto* p) {
    using T = std::decay_t<decltype(p[0])>;
    T x = p[4], v = p[5];
    s::body_lag_piece(s::DriveWheelSlip<T>{p[0]}, p[1], p[2], p[3], x, v);
    return std::array<T, 2>{x, v};
  };
}

}  // namespace

TEST(ModelFormulas, BodyLagPiece) {
  struct Point {
    const char* what;
    double tau, u0, ag, len, x0, v0;
    double float_rel;
  };
  // Awkward points: tau near 0 (len/tau = 1000 takes the settled branch e = 0; len/tau 49.9 and
  // 50.1 either side of that switch, which changes the value by e^-50 ~ 2e-22, below rounding),
  // a long tau (the closed form cancels: x = ... - ag tau len + C tau (1 - e), terms of ag tau len
  // for a result of ag len^2: float keeps 1e-5 of the terms' size, see `size` below), tiny len,
  // no acceleration, deceleration.
  for (const Point& q : {Point{"ordinary", 0.2, 0.05, 0.3, 0.1, 0.01, 0.02, 1e-5},
                         Point{"decelerating", 0.15, 0.08, -0.4, 0.12, 0.3, 0.1, 1e-5},
                         Point{"no acceleration", 0.1, 0.06, 0.0, 0.25, 0.0, 0.0, 1e-5},
                         Point{"tau near 0 (settled branch)", 1e-4, 0.05, 0.3, 0.1, 0.01, 0.02, 1e-5},
                         Point{"tau 3 ms", 3e-3, 0.05, 0.3, 0.1, 0.01, 0.02, 1e-5},
                         Point{"len/tau just below 50", 0.1 / 49.9, 0.05, 0.3, 0.1, 0.01, 0.02, 1e-5},
                         Point{"len/tau just above 50", 0.1 / 50.1, 0.05, 0.3, 0.1, 0.01, 0.02, 1e-5},
                         Point{"long tau", 5.0, 0.05, 0.3, 0.1, 0.01, 0.02, 1e-5},
                         Point{"tiny len", 0.2, 0.05, 0.3, 1e-7, 0.01, 0.02, 1e-5}}) {
    const std::array<double, 6> p{q.tau, q.u0, q.ag, q.len, q.x0, q.v0};
    // Expected: the closed form solved by hand (tight), and the documented ODE integrated by RK4
    // (independent of any closed form; to its own accuracy).
    const auto expected = lag_closed_form(q.tau, q.u0, q.ag, q.len, q.x0, q.v0);
    double x = q.x0, v = q.v0;
    lag_by_rk4([&](double t) { return q.u0 + q.ag * t; }, q.tau, 0.0, q.len, x, v);
    const auto got = body_lag_formula()(p.data());
    EXPECT_NEAR(got[0], x, 1e-11) << q.what << ": x against RK4 of dv/dt = (u - v)/tau";
    EXPECT_NEAR(got[1], v, 1e-10) << q.what << ": v against RK4";
    // The terms' size, x's and v's (the closed form's): float keeps 1e-5 of it.
    const double C = std::abs(q.v0 - q.u0 + q.ag * q.tau), ramp = -std::expm1(-q.len / std::max(q.tau, 1e-300));
    const double size = std::max(std::abs(q.x0) + std::abs(q.u0 * q.len) + std::abs(q.ag) * (q.len * q.len + q.tau * q.len) + C * q.tau * ramp,
                                 std::abs(q.u0) + std::abs(q.ag) * (q.len + q.tau) + C);
    check_formulas<6, 2>(std::string("body_lag_piece, ") + q.what, body_lag_formula(), p, expected,
                steps_formulas(p, {1e-3, 1e-2, 1e-2, 1e-3, 1e-2, 1e-2}),
                Check().divides().with_scale(size).with_float_rel(q.float_rel).with_expected_rel(1e-12));
  }
}

TEST(ModelFormulas, BodyLagPieceNeutralSlipFollowsTheWheelsExactly) {
  // tau = 0 (DriveWheelSlip{}): the body follows its input at once, x += u0 len + len^2 ag / 2,
  // v = u0 + ag len, exactly; its derivative in tau there is one-sided (tau >= 0 is the effect's
  // domain): only values here, and the Jet's value part.
  using J = epuck2::fit::Jet<1>;
  for (const std::array<double, 5>& q : {std::array<double, 5>{0.05, 0.3, 0.1, 0.01, 0.02}, std::array<double, 5>{-0.03, 0.0, 0.37, 0.0, 0.0},
                                         std::array<double, 5>{0.08, -0.4, 1e-7, 0.3, 0.1}}) {
    double x = q[3], v = q[4];
    s::body_lag_piece(s::DriveWheelSlip<double>{}, q[0], q[1], q[2], x, v);
    EXPECT_EQ(x, q[3] + (q[0] * q[2] + 0.5 * q[1] * q[2] * q[2]));
    EXPECT_EQ(v, q[0] + q[1] * q[2]);
    J xj(q[3]), vj(q[4]);
    s::body_lag_piece(s::DriveWheelSlip<J>{}, J(q[0]), J(q[1]), J(q[2], 0), xj, vj);
    EXPECT_EQ(xj.a, x);
    EXPECT_EQ(vj.a, v);
  }
}

namespace {

/// drive_advance with p = {max_cm_s, accel_cm_s2, tau_s, k, h_s} -> {xl, xr, vl, vr, xg, vg}.
auto drive_formula(double left, double right, bool symmetric, const DriveStart& st0) {
  return [=](const auto* p) {
    using T = std::decay_t<decltype(p[0])>;
    s::DriveEffects<T> e;
    e.speed_limit.max_cm_s = p[0];
    e.accel_limit.accel_cm_s2 = p[1];
    e.slip.tau_s = p[2];
    e.speed_scale.k = p[3];
    s::DriveState<T> st;
    st.vl = T(st0.vl);
    st.vr = T(st0.vr);
    st.xl = T(st0.xl);
    st.xr = T(st0.xr);
    st.vg = T(st0.vg);
    st.xg = T(st0.xg);
    s::drive_advance(e, left, right, p[4], st, symmetric);
    return std::array<T, 6>{st.xl, st.xr, st.vl, st.vr, st.xg, st.vg};
  };
}

void check_drive(const std::string& where, const std::array<double, 5>& p, double left, double right, bool symmetric,
                 const DriveStart& st0, std::array<double, 5> h = {}, double scale = 0) {
  if (h == std::array<double, 5>{}) h = steps_formulas(p, {1.0, 1.0, 1e-3, 1.0, 1e-3});
  // At tau = 0 the lag is off (a switch on tau's value, its domain's edge): no derivative in tau.
  if (p[2] == 0) h[2] = 0;
  // Symmetric: both wheels commanded `left` (drive_advance takes the hint only when it holds).
  if (symmetric) right = left;
  const auto expected = drive_by_hand(p[0], p[1], p[2], p[3], p[4], left, right, st0);
  // The body against RK4 to 1e-9 of each output; the wheels are exact piecewise formulas.
  check_formulas<5, 6>(where, drive_formula(left, right, symmetric, st0), p, expected, h,
              Check().divides().with_expected_rel(1e-9).with_scale(scale));
}

}  // namespace

TEST(ModelFormulas, DriveAdvanceEveryEffect) {
  const DriveStart rest;
  const double no_limit = s::kDriveNoLimit;
  // Both wheels, every effect: the left command (8) clamped at 7, ramps at 20 cm/s^2 (left 0.35 s,
  // right 0.25 s); at h = 0.3 the left wheel still ramps, at 0.5 both are done.
  check_drive("all effects, h = 0.3", {7.0, 20.0, 0.1, 0.95, 0.3}, 8.0, 5.0, false, rest);
  check_drive("all effects, h = 0.5", {7.0, 20.0, 0.1, 0.95, 0.5}, 8.0, 5.0, false, rest);
  // Each effect alone.
  check_drive("speed_limit alone", {7.0, no_limit, 0.0, 1.0, 0.4}, 8.0, -9.0, false, rest);
  check_drive("accel_limit alone", {no_limit, 25.0, 0.0, 1.0, 0.4}, 8.0, 5.0, false, rest);
  check_drive("wheel_slip alone", {no_limit, no_limit, 0.12, 1.0, 0.4}, 8.0, 5.0, false, rest);
  check_drive("speed_scale alone", {no_limit, no_limit, 0.0, 0.93, 0.4}, 8.0, 5.0, false, rest);
  // Moving already, backwards commands, deceleration on one wheel.
  DriveStart moving;
  moving.vl = 0.02;
  moving.vr = -0.01;
  moving.xl = 0.1;
  moving.xr = 0.05;
  moving.vg = 0.005;
  moving.xg = 0.07;
  check_drive("moving, backwards", {7.0, 25.0, 0.2, 0.9, 0.35}, -9.0, -4.0, false, moving);
  // Symmetric (both wheels alike, one simulated), decelerating from 10 cm/s to 6.
  DriveStart fast;
  fast.vl = fast.vr = 0.1;
  fast.xl = fast.xr = 0.2;
  fast.vg = 0.09;
  fast.xg = 0.19;
  check_drive("symmetric, decelerating", {12.0, 30.0, 0.05, 1.1, 0.4}, 6.0, 6.0, true, fast);
  check_drive("symmetric, from rest", {7.0, 20.0, 0.1, 0.95, 0.3}, 8.0, 8.0, true, rest);
}

TEST(ModelFormulas, DriveAdvanceAtItsKinks) {
  const DriveStart rest;
  const double no_limit = s::kDriveNoLimit;
  // speed_limit's clamp: command 8 with max 1e-3 above it (not clamped: no derivative in max) and
  // 1e-3 below (clamped); the steps in max (8e-6) stay on their side.
  for (bool sym : {false, true}) {
    check_drive("speed limit just above the command", {8.0 + 1e-3, no_limit, 0.1, 1.0, 0.3}, 8.0, 5.0, sym, rest);
    check_drive("speed limit just below the command", {8.0 - 1e-3, no_limit, 0.1, 1.0, 0.3}, 8.0, 5.0, sym, rest);
    check_drive("speed limit just below, ramping", {8.0 - 1e-3, 40.0, 0.1, 1.0, 0.3}, 8.0, 5.0, sym, rest);
  }
  // accel_limit: the ramp (8 cm/s at 20 cm/s^2: 0.4 s) ending 1e-4 s before and after h.
  for (bool sym : {false, true}) {
    check_drive("ramp ends just before h", {no_limit, 20.0, 0.1, 1.0, 0.4 + 1e-4}, 8.0, 3.0, sym, rest);
    check_drive("ramp ends just after h", {no_limit, 20.0, 0.1, 1.0, 0.4 - 1e-4}, 8.0, 3.0, sym, rest);
  }
  // wheel_slip's tau near 0 (the settled branch in every piece), and a few ms.
  check_drive("tau near 0", {7.0, 20.0, 1e-4, 0.95, 0.3}, 8.0, 5.0, false, rest);
  check_drive("tau 2 ms", {7.0, 20.0, 2e-3, 0.95, 0.3}, 8.0, 5.0, false, rest);
  check_drive("tau near 0, symmetric", {7.0, 20.0, 1e-4, 0.95, 0.3}, 8.0, 8.0, true, rest);
  // A tiny step h (latency's partial advance can be any length), mid-run: every output to its own
  // size.
  DriveStart cruising;
  cruising.vl = 0.04;
  cruising.vr = 0.045;
  cruising.xl = 0.2;
  cruising.xr = 0.21;
  cruising.vg = 0.041;
  cruising.xg = 0.2;
  check_drive("tiny h, moving", {7.0, 20.0, 0.1, 0.95, 1e-6}, 8.0, 5.0, false, cruising, {7e-6, 2e-5, 1e-7, 1e-6, 1e-12});
  // A tiny h from rest: the body has moved ag h^3 / (6 tau) = 3e-19 m, which the closed form gets
  // as the difference of terms of ag tau h = 2e-8 m (x = ... - ag tau h + C tau (1 - e^{-h/tau}),
  // C = ag tau): it keeps them to double's (float's) precision, not the 3e-19 m to its own
  // digits. Checked relative to the terms' size ag tau (the speed's, 0.019 m/s; all of it far
  // below anything a ToF or an encoder sees); the moving case above checks the derivatives.
  check_drive("tiny h, from rest (relative to the lag's terms)", {7.0, 20.0, 0.1, 0.95, 1e-6}, 8.0, 5.0, false, rest,
              {7e-6, 2e-5, 1e-7, 1e-6, 1e-12}, 0.2 * 0.95 * 0.1);
}

TEST(ModelFormulas, DriveAdvanceNeutralEffectsGiveThePluginDriveExactly) {
  // DriveEffects{}: the wheels at the commanded speeds at once, the body with them (the base of
  // docs/diagnose.md: v_w = v_c, v_g = v_w): x_w += (c / 100) h exactly, the body by the mean.
  for (bool sym : {false, true}) {
    for (const std::array<double, 3>& q : {std::array<double, 3>{8.0, 5.0, 0.3}, std::array<double, 3>{-3.3, 7.1, 0.125},
                                           std::array<double, 3>{12.0, 12.0, 1e-6}}) {
      const double right = sym ? q[0] : q[1];
      s::DriveState<double> st;
      st.vl = 0.03;
      st.vr = sym ? 0.03 : -0.02;
      st.xl = 0.1;
      st.xr = sym ? 0.1 : 0.2;
      st.vg = 0.01;
      st.xg = 0.15;
      const s::DriveState<double> st0 = st;
      s::drive_advance(s::DriveEffects<double>{}, q[0], right, q[2], st, sym);
      const double ul = q[0] * 0.01, ur = right * 0.01;
      EXPECT_EQ(st.vl, ul);
      EXPECT_EQ(st.vr, ur);
      EXPECT_EQ(st.xl, st0.xl + ul * q[2]);
      EXPECT_EQ(st.xr, st0.xr + ur * q[2]);
      if (sym) {
        EXPECT_EQ(st.vg, ul);
        EXPECT_EQ(st.xg, st0.xg + ul * q[2]);
      } else {
        EXPECT_EQ(st.vg, 0.5 * (ul + ur));
        EXPECT_EQ(st.xg, st0.xg + 0.5 * (ul + ur) * q[2]);
      }
      // float and Jet: the same, in their own arithmetic.
      // float: the command's speed rounded to float once (c * 0.01 in double, as kPerCm is), then
      // x = u h in float.
      s::DriveState<float> sf;
      s::drive_advance(s::DriveEffects<float>{}, q[0], right, static_cast<float>(q[2]), sf, sym);
      const float ulf = static_cast<float>(static_cast<float>(q[0]) * 0.01);
      const float urf = static_cast<float>(static_cast<float>(right) * 0.01);
      EXPECT_EQ(sf.vl, ulf);
      EXPECT_EQ(sf.xl, ulf * static_cast<float>(q[2]));
      EXPECT_EQ(sf.xr, urf * static_cast<float>(q[2]));
      using J = epuck2::fit::Jet<1>;
      s::DriveState<J> sj;
      s::drive_advance(s::DriveEffects<J>{}, q[0], right, J(q[2], 0), sj, sym);
      EXPECT_EQ(sj.xl.a, ul * q[2]);
      EXPECT_EQ(sj.xl.v[0], ul);  // d x / d h = v
    }
  }
  // h <= 0: nothing moves.
  s::DriveState<double> st;
  st.xl = 0.3;
  s::drive_advance(s::DriveEffects<double>{}, 5.0, 5.0, 0.0, st);
  EXPECT_EQ(st.xl, 0.3);
  EXPECT_EQ(st.vl, 0.0);
}

TEST(ModelFormulas, DriveAdvanceTakesTheSymmetricHintOnlyWhenItHolds) {
  // After a turn the left wheel has run 0.10 m at 0.05 m/s, the right 0.02 m and stands. A stop
  // (0, 0) for 1 s, hinted symmetric because the commands are equal, must move each wheel from
  // its own state. Without limits: both stop at once, travels unchanged (0.10, 0.02), the body
  // at once at the wheels' mean 0. With a 10 cm/s^2 limit: the left slows from 0.05 m/s to 0 in
  // 0.5 s and runs 0.05 * 0.5 - 0.1 * 0.5^2 / 2 = 0.0125 m more; the right stays.
  for (bool sym : {false, true}) {
    s::DriveState<double> st;
    st.xl = 0.10, st.vl = 0.05, st.xr = 0.02, st.vr = 0.0, st.xg = 0.06, st.vg = 0.025;
    s::drive_advance(s::DriveEffects<double>{}, 0.0, 0.0, 1.0, st, sym);
    EXPECT_EQ(st.xl, 0.10) << sym;
    EXPECT_EQ(st.xr, 0.02) << sym;
    EXPECT_EQ(st.vl, 0.0) << sym;
    EXPECT_EQ(st.vr, 0.0) << sym;
    s::DriveEffects<double> limited;
    limited.accel_limit.accel_cm_s2 = 10.0;
    s::DriveState<double> sl;
    sl.xl = 0.10, sl.vl = 0.05, sl.xr = 0.02, sl.vr = 0.0, sl.xg = 0.06, sl.vg = 0.025;
    s::drive_advance(limited, 0.0, 0.0, 1.0, sl, sym);
    EXPECT_NEAR(sl.xl, 0.1125, 1e-15) << sym;
    EXPECT_EQ(sl.xr, 0.02) << sym;
    EXPECT_EQ(sl.vl, 0.0) << sym;
    // Unequal commands hinted symmetric: each wheel gets its own command (no limits).
    s::DriveState<double> su;
    s::drive_advance(s::DriveEffects<double>{}, 6.0, 2.0, 0.5, su, sym);
    EXPECT_EQ(su.xl, 0.06 * 0.5) << sym;
    EXPECT_EQ(su.xr, 0.02 * 0.5) << sym;
  }
}

TEST(ModelFormulas, DriveTofMean) {
  // tof_scale and tof_offset: k 1000 (D - x) + offset. p = {k, offset, x}. Awkward: near the
  // rails (20 mm and 2000 mm), zero offset, k = 1, a tiny range D - x.
  struct Point {
    double k, offset, obstacle, travel;
  };
  for (const Point& q : {Point{1.02, -12.0, 0.8, 0.3}, Point{0.97, 8.0, 0.5, 0.4795}, Point{1.0, 0.0, 2.1, 0.1005},
                         Point{1.0, 0.0, 0.5, 0.5 - 1e-6}, Point{1.03, 0.0, 0.8, 0.0}, Point{1.0 + 1e-6, 4.0, 0.8, 0.2}}) {
    auto f = [D = q.obstacle](const auto* p) {
      using T = std::decay_t<decltype(p[0])>;
      s::DriveEffects<T> e;
      e.tof_scale.k = p[0];
      e.tof_offset.offset_mm = p[1];
      return std::array<T, 1>{s::drive_tof_mean_mm(e, D, p[2])};
    };
    const std::array<double, 3> p{q.k, q.offset, q.travel};
    const double expected = q.k * 1000.0 * (q.obstacle - q.travel) + q.offset;
    check_formulas<3, 1>(at_formulas(at_formulas("drive_tof_mean_mm", "travel", q.travel), "offset", q.offset), f, p, {expected},
                steps_formulas(p, {1.0, 1e3, 1.0}), Check().with_scale(1000.0 * q.k * (q.obstacle + q.travel) + std::abs(q.offset)));
  }
  // Neutral tof_scale and tof_offset (and every other effect): exactly 1000 (D - x).
  for (double x : {0.0, 0.1005, 0.3, 0.4795})
    for (double D : {0.5, 0.8, 2.1}) EXPECT_EQ(s::drive_tof_mean_mm(s::DriveEffects<double>{}, D, x), 1000.0 * (D - x));
}

TEST(ModelFormulas, EncoderMeanSteps) {
  // steps_per_m x - 1/2 once the wheel has moved, exactly 0 before (a jump at x = 0, by design:
  // the register reads 0 before any motion). p = {x}; both sides of 0, never at it.
  for (double x : {-0.05, -1e-9, 1e-9, 1e-4, 0.05, 0.3}) {
    auto f = [](const auto* p) {
      using T = std::decay_t<decltype(p[0])>;
      return std::array<T, 1>{s::encoder_mean_steps(7763.656, p[0])};
    };
    const std::array<double, 1> p{x};
    check_formulas<1, 1>(at_formulas("encoder_mean_steps", "x", x), f, p, {7763.656 * x - 0.5}, std::array<double, 1>{std::abs(x) * 1e-6},
                Check().with_scale(7763.656 * std::abs(x) + 0.5));
  }
  EXPECT_EQ(s::encoder_mean_steps(7763.656, 0.0), 0.0);
  EXPECT_EQ(s::encoder_mean_steps(7763.656, 0.0f), 0.0f);
  const auto j = s::encoder_mean_steps(7763.656, epuck2::fit::Jet<1>(0.0, 0));
  EXPECT_EQ(j.a, 0.0);
  EXPECT_EQ(j.v[0], 0.0);
}

TEST(ModelFormulas, LaggedBodyTravel) {
  // The body's travel through the lag when the wheels move at constant speed between samples.
  // p = {tau}. Expected: RK4 of dv/dt = (u - v)/tau with u the wheels' speed on each interval,
  // from rest (a repeated time stamp is skipped). Awkward: tau near 0.
  const std::vector<double> time{0.0, 0.1, 0.2, 0.2, 0.35, 0.5, 0.62};
  const std::vector<double> wheel{0.0, 0.004, 0.011, 0.011, 0.02, 0.026, 0.0262};
  auto f = [&](const auto* p) {
    using T = std::decay_t<decltype(p[0])>;
    std::array<T, 7> out;
    s::lagged_body_travel_m(s::DriveWheelSlip<T>{p[0]}, time, wheel, out.data());
    return out;
  };
  for (double tau : {0.15, 0.03, 2e-3, 1e-4, 2.0}) {
    std::array<double, 7> expected{};
    double x = 0, v = 0;
    for (std::size_t k = 0; k + 1 < time.size(); ++k) {
      expected[k] = x;
      const double dt = time[k + 1] - time[k];
      if (!(dt > 0)) continue;
      const double u = (wheel[k + 1] - wheel[k]) / dt;
      lag_by_rk4([u](double) { return u; }, tau, 0.0, dt, x, v);
    }
    expected.back() = x;
    const std::array<double, 1> p{tau};
    check_formulas<1, 7>(at_formulas("lagged_body_travel_m", "tau", tau), f, p, expected, std::array<double, 1>{tau * 1e-6},
                Check().divides().with_scale(0.03).with_expected_rel(1e-9));
  }
  // tau = 0 (DriveWheelSlip{}): the wheels' travel, through (delta / dt) dt per interval: equal to
  // wheel[k] - wheel[0] to rounding (not bit for bit: the speed is rounded). Its tau derivative at
  // 0 is one-sided (the effect's domain edge): values only.
  std::array<double, 7> out{};
  s::lagged_body_travel_m(s::DriveWheelSlip<double>{}, time, wheel, out.data());
  for (std::size_t k = 0; k < time.size(); ++k) EXPECT_NEAR(out[k], wheel[k] - wheel[0], 8 * kEps * 0.03) << k;
}

// =============================================================================================
// battery.hpp
// =============================================================================================

TEST(ModelFormulas, BatteryCubicAndLineCharge) {
  // a t^3 + b t^2 + c t + d, p = {d, c, b, a}; charge0 + slope t. Awkward: t = 0, the end of a
  // lifetime (terms that cancel to near 0).
  const std::array<double, 4> cubic{0.95, -1e-4, 2e-9, -3e-13};
  for (double t : {0.0, 1.0, 1500.0, 6000.0, 9000.0}) {
    auto f = [t](const auto* p) {
      using T = std::decay_t<decltype(p[0])>;
      return std::array<T, 1>{mb::cubic_charge(p, t)};
    };
    const double terms = std::abs(cubic[0]) + std::abs(cubic[1] * t) + std::abs(cubic[2] * t * t) + std::abs(cubic[3] * t * t * t);
    check_formulas<4, 1>(at_formulas("cubic_charge", "t", t), f, cubic,
                {cubic[3] * t * t * t + cubic[2] * t * t + cubic[1] * t + cubic[0]}, steps_formulas(cubic, {1.0, 1e-4, 1e-8, 1e-12}),
                Check().with_scale(terms));
    auto g = [t](const auto* p) {
      using T = std::decay_t<decltype(p[0])>;
      return std::array<T, 1>{mb::line_charge(p[0], p[1], t)};
    };
    const std::array<double, 2> line{0.93, -1.1e-4};
    check_formulas<2, 1>(at_formulas("line_charge", "t", t), g, line, {line[0] + line[1] * t}, steps_formulas(line, {1.0, 1e-4}),
                Check().with_scale(std::abs(line[0]) + std::abs(line[1] * t)));
  }
}

TEST(ModelFormulas, BatteryPolylineCharge) {
  // The continuous piecewise line through (x_k, y_k), extrapolated beyond the ends. p = {x0..x3,
  // y0..y3}. The kinks are at the knots: points on both sides of each (0.1 s away; the steps in
  // x are 2e-3 s at most), before the first and after the last.
  const std::array<double, 8> p{0.0, 2000.0, 6000.0, 9000.0, 1.0, 0.8, 0.5, 0.0};
  auto f = [](double t) {
    return [t](const auto* q) {
      using T = std::decay_t<decltype(q[0])>;
      return std::array<T, 1>{mb::polyline_charge(q, q + 4, 4, t)};
    };
  };
  auto by_hand = [&](double t) {
    int j = 0;
    while (j < 2 && t > p[static_cast<std::size_t>(j + 1)]) ++j;
    const double x0 = p[static_cast<std::size_t>(j)], x1 = p[static_cast<std::size_t>(j + 1)];
    const double y0 = p[static_cast<std::size_t>(4 + j)], y1 = p[static_cast<std::size_t>(5 + j)];
    return y0 + (y1 - y0) * (t - x0) / (x1 - x0);
  };
  for (double t : {-100.0, 0.1, 1000.0, 1999.9, 2000.1, 4000.0, 5999.9, 6000.1, 8999.9, 9000.1, 9500.0}) {
    check_formulas<8, 1>(at_formulas("polyline_charge", "t", t), f(t), p, {by_hand(t)}, steps_formulas(p, {1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0}),
                Check().divides().with_scale(1.0).with_expected_rel(1e-12));
  }
}

TEST(ModelFormulas, BatteryCapacityScale) {
  // capacity_scale (docs/diagnose.md): a battery of k times the capacity discharges as the model
  // does with time running 1/k as fast. Linear model by hand: at 5.5 cm/s (between the 5 and 6
  // cm/s tables) the corrected slope is the mean of theirs, and a tick of dt moves the charge by
  // slope dt / k. Double only: step() is not templated (lib/diagnose takes its k derivative by
  // central differences).
  mb::Tables t{};
  for (int v = 0; v < mb::kSpeedCount; ++v) t.linear_slope_per_s[static_cast<std::size_t>(v)] = -1e-4 * (1.0 + v);
  t.simple_static_slope_per_s = -2e-5;
  t.simple_moving_slope_per_s = -9e-5;
  const double dt = 0.1, charge = 0.8;
  for (double k : {0.8, 1.0, 1.009, 1.25}) {
    const double slope = (-1e-4 * 6.0 + -1e-4 * 7.0) / 2.0;
    EXPECT_NEAR(mb::step(mb::Model::linear, t, mb::CapacityScale{k}, charge, 0.055 * dt, dt), charge + slope * dt / k, 1e-15)
        << k;
    EXPECT_NEAR(mb::step(mb::Model::simple, t, mb::CapacityScale{k}, charge, 0.055 * dt, dt), charge - 9e-5 * dt / k, 1e-15);
    EXPECT_NEAR(mb::step(mb::Model::simple, t, mb::CapacityScale{k}, charge, 0.0, dt), charge - 2e-5 * dt / k, 1e-15);
  }
  // Neutral: CapacityScale{} gives the corrected model's tick exactly, for every model.
  const mb::Tables& plugin = mb::plugin_tables();
  for (mb::Model m : mb::kAllModels)
    for (double c : {1.0, 0.97, 0.6, 0.2})
      for (double speed : {0.0, 0.03, 0.055, 0.12}) {
        EXPECT_EQ(mb::step(m, plugin, mb::CapacityScale{}, c, speed * dt, dt), mb::corrected::step(m, plugin, c, speed * dt, dt))
            << mb::to_string(m) << " " << c << " " << speed;
        EXPECT_EQ(mb::step(m, plugin, mb::CapacityScale{}, c, speed * dt, dt),
                  mb::step(m, mb::Behaviour::corrected, plugin, c, speed * dt, dt));
      }
}

// =============================================================================================
// kinds.hpp: the models the simulation runs (double)
// =============================================================================================

TEST(ModelFormulas, DefaultModelsGiveThePluginReadings) {
  const s::ProximityModel prox;
  const s::LightModel light;
  const s::GroundModel ground;
  for (int sensor = 0; sensor < s::kProximityCount; ++sensor) {
    for (double d : {0.0, 0.01, 0.03, 0.05, 0.07}) {
      EXPECT_EQ(s::mean_raw(prox, sensor, d), kFull * s::proximity_response(s::kPluginProximity, d));
      EXPECT_EQ(s::mean_raw(prox, sensor, d, -0.2), kFull * s::proximity_response(s::kPluginProximity, d));
      EXPECT_EQ(s::mean_raw(light, sensor, 1.0, d + 0.08), kFull * s::light_response(s::kPluginLight.gamma_m, 1.0, d + 0.08));
    }
    EXPECT_EQ(s::mean_raw(prox, sensor, std::nullopt), 0.0);
    EXPECT_EQ(s::mean_raw(light, sensor, 1.0, 0.6), kFull);
  }
  for (int sensor = 0; sensor < s::kGroundCount; ++sensor)
    for (double grey : {0.0, 0.2, 1.0 / 3.0, 1.0}) EXPECT_EQ(s::mean_raw(ground, sensor, grey), 1023.0 * grey);
}

TEST(ModelFormulas, DriveSimulationLatencyAndItsNeutralValue) {
  // latency: the ToF reading at t is the true one at t - delay (docs/diagnose.md), in the
  // simulation (DriveSimulation, double). From rest at 5 cm/s towards an obstacle 0.5 m away,
  // sampled every 0.1 s: tof = round(1000 (0.5 - 0.05 max(0, t - delay))), and the encoders
  // floor(7763.656 * 0.05 t). The delay 0.123 s keeps every rounding away from a half.
  s::StandardNormal normal(1);
  for (double delay : {0.0, 0.123}) {
    s::DriveModel m;
    m.effects.latency.delay_s = delay;
    s::DriveSimulation sim(m, 0.5);
    for (int i = 0; i <= 10; ++i) {
      const double t = 0.1 * i;
      const auto r = sim.sample(t, 5.0, 5.0, normal);
      const double travelled = 0.05 * std::max(0.0, t - delay);
      EXPECT_EQ(r.tof_mm, static_cast<int>(std::round(1000.0 * (0.5 - travelled)))) << delay << " " << t;
      EXPECT_EQ(r.left_steps, static_cast<int>(std::floor(7763.656 * 0.05 * t))) << t;
      EXPECT_EQ(r.right_steps, r.left_steps);
    }
  }
}
