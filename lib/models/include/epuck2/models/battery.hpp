// E-Puck2 battery discharge models: Simple, Linear, Cubic and Approximated (paper Appendix,
// Algorithms 1-4), driven by coefficient tables, in two behaviours:
//
//  * Behaviour::argos_compatible reproduces the E-Puck2 ARGoS plug-in's arithmetic to the last bit
//    (as in the plug-in's source, its battery discharge code): speed rounded to 0.01 cm/s, floor/ceil
//    tables, the interpolation that always starts from the smaller value, Cardano's root clamped
//    at 0, the drop on the first tick from a full charge, the Linear model's interpolation in
//    float, the Approximated update m*(x + dt) + h.
//  * Behaviour::corrected is the project's fix of each quirk: a true linear interpolation between
//    the speed tables, a continuous start from full charge (with the firmware filter's lag), a
//    robust root. docs/battery-models.md
//    lists every difference and what it changes on the reference logs.
//
// Header-only, no dependency: usable from an ARGoS plug-in. The formulas that a fit needs
// derivatives of (cubic_charge, line_charge, polyline_charge) are templated on the scalar so that
// lib/fit uses the very same code with fit::Jet.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace epuck2::models::battery {

inline constexpr int kSpeedCount = 16;    ///< tables for 0, 1, ..., 15 cm/s
inline constexpr int kSegmentCount = 4;   ///< Approximated model: M1..M4 (M4 = the final drop)
inline constexpr double kMaxSpeed_m_s = 0.150;  ///< the plug-in clamps the speed to [0, 0.15] m/s
/// Half the inter-wheel distance; the plug-in converts an in-place rotation angle to wheel
/// travel with it (the plug-in's source). The plug-in writes the literal as the float 0.0265f.
inline constexpr double kHalfAxle_m = 0.0265;
inline constexpr float kHalfAxleFloat_m = 0.0265f;

/// One speed's cubic: charge(t) = a t^3 + b t^2 + c t + d for t in [0, end_s].
struct CubicRow {
  double d = 0, c = 0, b = 0, a = 0;
  double end_s = 0;  ///< the measured lifetime at this speed: past it the model reads 0
};

/// One straight segment of the Approximated model: charge = m t + h on [x1_s, x2_s], valid while
/// the charge is in the band [y2, y1].
struct Segment {
  double h = 0, m = 0, x1_s = 0, x2_s = 0, y1 = 0, y2 = 0;
};

/// Every coefficient the four models need, per speed 0..15 cm/s.
struct Tables {
  std::array<CubicRow, kSpeedCount> cubic{};
  std::array<std::array<Segment, kSegmentCount>, kSpeedCount> segments{};
  std::array<double, kSpeedCount> linear_slope_per_s{};  ///< Linear model: -1/lifetime
  std::array<double, kSpeedCount> lifetime_s{};
  double simple_static_slope_per_s = 0;  ///< Simple model's m0 (robot not moving)
  double simple_moving_slope_per_s = 0;  ///< Simple model's m1 (robot moving)
};

enum class Model { simple, linear, cubic, approximated };
enum class Behaviour { argos_compatible, corrected };

inline constexpr std::array<Model, 4> kAllModels{Model::simple, Model::linear, Model::cubic,
                                                 Model::approximated};

inline constexpr std::string_view to_string(Model m) {
  switch (m) {
    case Model::simple: return "simple";
    case Model::linear: return "linear";
    case Model::cubic: return "cubic";
    case Model::approximated: return "approximated";
  }
  return "?";
}

/// Parses "simple", "linear", "cubic", "approximated"; returns false on anything else.
inline bool parse_model(std::string_view name, Model& out) {
  for (Model m : kAllModels) {
    if (name == to_string(m)) {
      out = m;
      return true;
    }
  }
  return false;
}

// ---------------------------------------------------------------------------------------------
// Formulas shared with the fitting layer (templated on the scalar, no branch on a parameter).
// ---------------------------------------------------------------------------------------------

/// charge(t) = a t^3 + b t^2 + c t + d with coefficients p = {d, c, b, a}; Horner form.
template <typename T>
T cubic_charge(const T* p, double t_s) {
  return ((p[3] * t_s + p[2]) * t_s + p[1]) * t_s + p[0];
}

/// A straight discharge line through charge0 at t = 0: charge(t) = charge0 + slope t.
template <typename T>
T line_charge(const T& charge0, const T& slope_per_s, double t_s) {
  return charge0 + slope_per_s * t_s;
}

/// Continuous piecewise line through the knots (x_k, y_k), k = 0..n-1, evaluated at t
/// (linear extrapolation beyond the ends). The knots' positions may be fitted parameters: the
/// segment is chosen with a hinge formulation (y_0 + slope_0 (t - x_0) + sum of slope changes
/// times max(0, t - x_k)), whose derivative with respect to each knot is the exact one-sided
/// derivative, never an artificial zero.
template <typename T>
T polyline_charge(const T* x, const T* y, int n, double t_s) {
  using std::max;
  T slope_prev = (y[1] - y[0]) / (x[1] - x[0]);
  T value = y[0] + slope_prev * (T(t_s) - x[0]);
  for (int k = 1; k + 1 < n; ++k) {
    const T slope = (y[k + 1] - y[k]) / (x[k + 1] - x[k]);
    const T over = T(t_s) - x[k];
    // max(0, t - x_k): a branch on the data point against the knot, the standard segmented
    // regression form; its gradient w.r.t. x_k is -(slope change) where t > x_k.
    if (over > T(0)) value += (slope - slope_prev) * over;
    slope_prev = slope;
  }
  return value;
}

// ---------------------------------------------------------------------------------------------
// Speed handling
// ---------------------------------------------------------------------------------------------

/// std::round(x) for x >= 0 (or -0) without the library call that std::round is on x86-64
/// without SSE4.1 (it cost about a tenth of a Cubic step). Same value bit for bit: below 2^52,
/// x - trunc(x) is exact, so "fraction >= 0.5" is exactly round-half-away-from-zero; the sign
/// of a zero is kept; NaN and larger values go to std::round.
inline double round_non_negative(double x) {
  constexpr double kTwoPow52 = 4503599627370496.0;  // from here on every double is an integer
  if (!(x < kTwoPow52)) return std::round(x);
  const double t = static_cast<double>(static_cast<long long>(x));
  return std::copysign(x - t >= 0.5 ? t + 1.0 : t, x);
}

/// The plug-in's speed: round(clamp(delta_pos/dt, 0, 0.15) * 10000) / 100, in cm/s. A step of
/// no length (a repeated time stamp, dt = 0) has no speed: 0, not 0/0.
inline double plugin_speed_cm_s(double delta_pos_m, double dt_s) {
  if (!(dt_s > 0)) return 0.0;
  const double v = std::clamp(delta_pos_m / dt_s, 0.0, kMaxSpeed_m_s);
  return round_non_negative(v * 10000.0) / 100.0;
}

/// The corrected behaviour's speed: clamp(delta_pos/dt, 0, 0.15) in cm/s, not rounded; 0 for a
/// step of no length.
inline double exact_speed_cm_s(double delta_pos_m, double dt_s) {
  if (!(dt_s > 0)) return 0.0;
  return std::clamp(delta_pos_m / dt_s, 0.0, kMaxSpeed_m_s) * 100.0;
}

// ---------------------------------------------------------------------------------------------
// Plug-in compatible arithmetic (the plug-in's source); every expression in the source's order.
// ---------------------------------------------------------------------------------------------
namespace argos {

/// The plug-in's "interpolation": starts from the smaller value, so when y_low > y_high the
/// weights are swapped with respect to a linear interpolation.
inline double interpolate(double y_low, double y_high, double d) {
  return (y_low < y_high) ? y_low + (y_high - y_low) * d : y_high + (y_low - y_high) * d;
}

// Cardano's single real root of cubic(t) = y, exactly as the source writes it:
//   new_d = d - y;  d0 = b*b - 3*a*c;  d1 = 2*b*b*b - 9*a*b*c + 27*a*a*new_d;
//   C = cbrt((d1 + sqrt(d1*d1 - 4*d0*d0*d0)) / 2);  root = -1 / (3*a) * (b + C + d0 / C)
// split at the cube root, so that step() can start both speed tables' cube roots before finishing
// either: the two evaluations then overlap instead of running one after the other (every
// operation, and its order, is the source's; only independent work is reordered).

/// The cube root's argument, (d1 + sqrt(d1*d1 - 4*d0*d0*d0)) / 2, for charge y.
inline double cardano_cbrt_argument(const CubicRow& q, double y) {
  const double a = q.a, b = q.b, c = q.c, d = q.d;
  const double new_d = d - y;
  const double d0 = b * b - 3 * a * c;
  const double d1 = 2 * b * b * b - 9 * a * b * c + 27 * a * a * new_d;
  return (d1 + std::sqrt(d1 * d1 - 4 * d0 * d0 * d0)) / 2;
}

/// The root from the cube root C: -1 / (3*a) * (b + C + d0 / C).
inline double cardano_from_cbrt(const CubicRow& q, double C) {
  const double a = q.a, b = q.b, c = q.c;
  const double d0 = b * b - 3 * a * c;
  return (-1 / (3 * a) * (b + C + d0 / C));
}

inline double cardano_root(const CubicRow& q, double y) {
  return cardano_from_cbrt(q, std::cbrt(cardano_cbrt_argument(q, y)));
}

/// One speed table's next charge for the Cubic model, from the Cardano root of the charge.
inline double cubic_next_from_root(const CubicRow& q, double root, double dt_s) {
  double x = std::max(0.0, root);
  if (x >= q.end_s) return 0.0;
  x += dt_s;
  return q.a * x * x * x + q.b * x * x + q.c * x + q.d;
}

/// One speed table's next charge for the Cubic model.
inline double cubic_next(const CubicRow& q, double charge, double dt_s) {
  return cubic_next_from_root(q, cardano_root(q, charge), dt_s);
}

/// The segment whose charge band holds the charge (M1, then M2, M3, else M4).
inline const Segment& segment_for(const std::array<Segment, kSegmentCount>& segs, double charge) {
  for (int k = 0; k + 1 < kSegmentCount; ++k) {
    if (charge <= segs[k].y1 && charge >= segs[k].y2) return segs[k];
  }
  return segs[kSegmentCount - 1];
}

inline double approximated_next(const std::array<Segment, kSegmentCount>& segs, double charge,
                                double dt_s) {
  const Segment& s = segment_for(segs, charge);
  const double x = (charge - s.h) / s.m;
  return s.m * (x + dt_s) + s.h;
}

/// One tick of a model as the plug-in computes it, from the distance the robot moved in the
/// tick (an in-place rotation already converted to angle * 0.0265f). A step of no length
/// (dt = 0: a log's repeated time stamp) discharges nothing: the charge is returned unchanged.
inline double step(Model model, const Tables& t, double charge, double delta_pos_m, double dt_s) {
  if (dt_s == 0) return charge;
  if (model == Model::simple) {
    return charge + (delta_pos_m == 0 ? t.simple_static_slope_per_s : t.simple_moving_slope_per_s) *
                        dt_s;
  }
  const double speed = plugin_speed_cm_s(delta_pos_m, dt_s);
  if (model == Model::linear) {
    const int lo = static_cast<int>(std::floor(speed));
    const int hi = static_cast<int>(std::ceil(speed));
    if (lo == hi) {
      const float m = static_cast<float>(t.linear_slope_per_s[lo]);
      return std::max(0.0, charge + m * dt_s);
    }
    const float mL = static_cast<float>(t.linear_slope_per_s[lo]);
    const float mH = static_cast<float>(t.linear_slope_per_s[hi]);
    const float yL = static_cast<float>(charge + mL * dt_s);
    const float yH = static_cast<float>(charge + mH * dt_s);
    const float d = static_cast<float>((speed - lo) / (hi - lo));
    const float y = (yH < yL) ? yH + (yL - yH) * d : yL + (yH - yL) * d;
    return std::max(0.0, static_cast<double>(y));
  }
  if (model == Model::cubic) {
    const int lo = std::min(kSpeedCount - 1, static_cast<int>(std::floor(speed)));
    const int hi = std::max(0, static_cast<int>(std::ceil(speed)));
    const CubicRow& qL = t.cubic[lo];
    if (lo == hi) return std::max(0.0, cubic_next(qL, charge, dt_s));
    // Both cube roots before either table's end (see cardano_cbrt_argument): same values.
    const CubicRow& qH = t.cubic[hi];
    const double argL = cardano_cbrt_argument(qL, charge);
    const double argH = cardano_cbrt_argument(qH, charge);
    const double cL = std::cbrt(argL);
    const double cH = std::cbrt(argH);
    const double yL = cubic_next_from_root(qL, cardano_from_cbrt(qL, cL), dt_s);
    const double yH = cubic_next_from_root(qH, cardano_from_cbrt(qH, cH), dt_s);
    return std::max(0.0, interpolate(yL, yH, (speed - lo) / (hi - lo)));
  }
  // approximated
  const int lo = std::max(0, static_cast<int>(std::floor(speed)));
  const int hi = std::min(kSpeedCount - 1, static_cast<int>(std::ceil(speed)));
  const double yL = approximated_next(t.segments[lo], charge, dt_s);
  if (lo == hi) return std::max(0.0, yL);
  const double yH = approximated_next(t.segments[hi], charge, dt_s);
  return std::max(0.0, interpolate(yL, yH, (speed - lo) / (hi - lo)));
}

}  // namespace argos

// ---------------------------------------------------------------------------------------------
// Does the plug-in's arithmetic discharge a Cubic table? (docs/battery-models.md)
// ---------------------------------------------------------------------------------------------

/// What the plug-in's Cubic arithmetic does with one speed's table from full charge, at that
/// table's own speed (argos::step there is max(0, argos::cubic_next) on that row), in ticks of dt_s.
struct ArgosCubicRun {
  bool discharges = true;  ///< the charge fell below `below` within two lifetimes (2 end_s)
  bool stays = false;      ///< it did not, and a tick left it unchanged: it stays there for good
  double charge = 1.0;     ///< the charge where the run stopped (below `below`, or where it stuck)
  double time_s = 0.0;     ///< when it got there
};

/// Runs the plug-in's arithmetic (argos::cubic_next, unchanged) from charge 1 until the charge is
/// below `below` (it discharges), a tick leaves it unchanged (a fixed point: every later tick
/// returns it again), or two lifetimes have passed. Cardano's closed form gives a root of the
/// wrong sign, or NaN, for some fitted coefficient sets (e.g. b < 0 at every speed, as a pooled
/// fit of two robots 35 % apart gives): the root is clamped to 0 and every tick returns the
/// cubic's value at dt, P(dt), again -- a battery that never empties.
inline ArgosCubicRun argos_cubic_run(const CubicRow& q, double dt_s = 0.1, double below = 0.05) {
  ArgosCubicRun r;
  if (!(dt_s > 0)) return r;
  double charge = 1.0;
  for (long long k = 1;; ++k) {
    const double t = static_cast<double>(k) * dt_s;
    const double next = std::max(0.0, argos::cubic_next(q, charge, dt_s));
    r.charge = next;
    r.time_s = t;
    if (next < below) return r;
    if (next == charge || t >= 2.0 * q.end_s) {
      r.discharges = false;
      r.stays = next == charge;
      return r;
    }
    charge = next;
  }
}

/// One speed whose Cubic table the plug-in's arithmetic does not discharge.
struct ArgosCubicStall {
  double speed_cm_s = 0;
  ArgosCubicRun run;
};

/// The speeds 0..15 of `t` whose Cubic table argos_cubic_run does not discharge.
inline std::vector<ArgosCubicStall> argos_cubic_stalls(const Tables& t, double dt_s = 0.1, double below = 0.05) {
  std::vector<ArgosCubicStall> out;
  for (int s = 0; s < kSpeedCount; ++s) {
    const ArgosCubicRun r = argos_cubic_run(t.cubic[static_cast<std::size_t>(s)], dt_s, below);
    if (!r.discharges) out.push_back({static_cast<double>(s), r});
  }
  return out;
}

/// The words every reader of such tables says (battery, table5, codegen, the ARGoS battery at
/// Init): "" when every table discharges.
inline std::string argos_cubic_stall_text(const std::vector<ArgosCubicStall>& stalls, double dt_s = 0.1) {
  if (stalls.empty()) return "";
  std::string speeds, where;
  char buf[160];
  for (std::size_t i = 0; i < stalls.size(); ++i) {
    const ArgosCubicStall& s = stalls[i];
    std::snprintf(buf, sizeof buf, "%s%g", i == 0 ? "" : ", ", s.speed_cm_s);
    speeds += buf;
    if (s.run.stays)
      std::snprintf(buf, sizeof buf, "%sat %g cm/s it stays at %.7g from %g s on", i == 0 ? "" : "; ", s.speed_cm_s, s.run.charge,
                    s.run.time_s);
    else
      std::snprintf(buf, sizeof buf, "%sat %g cm/s it is still %.7g after two lifetimes (%g s)", i == 0 ? "" : "; ",
                    s.speed_cm_s, s.run.charge, s.run.time_s);
    if (i < 4) where += buf;
  }
  if (stalls.size() > 4) where += "; ...";
  std::snprintf(buf, sizeof buf, "%g", dt_s);
  return "the plug-in's arithmetic (behaviour \"argos\": Cardano's root, clamped at 0) never empties the Cubic table at " + speeds +
         " cm/s: from full charge, in ticks of " + buf + " s, the charge stops falling: " + where +
         " (the root of the charge comes out below 0 or not a number and is clamped to t = 0); a battery with these "
         "tables in behaviour \"argos\" and model cubic never runs down: use behaviour \"corrected\" or another model";
}


// ---------------------------------------------------------------------------------------------
// Corrected behaviour
// ---------------------------------------------------------------------------------------------
namespace corrected {

/// The firmware's battery reading is an exponential moving average, 0.8 old + 0.2 new every
/// 500 ms (the e-puck2 firmware): a time constant of 0.5 / ln(1.25) = 2.24 s. A full battery
/// reads 1 and falls to the curve's intercept d (the voltage under load) with that lag, instead of
/// jumping there in one tick as the plug-in's Cubic does.
inline constexpr double kFirmwareFilterTau_s = 2.2407;

/// The cubic before its intercept: charge above d decays towards d with the firmware filter's
/// time constant while discharging at the curve's initial slope c, x' = -x / tau + c for the
/// excess x = charge - d. Continuous from 1.0, and it does not delay the curve by the (1 - d)/|c|
/// seconds a straight-line start would. Solved exactly over the step, whatever its length:
/// x(dt) = c tau + (x0 - c tau) e^(-dt/tau), and when that reaches d within the step (at
/// t_c = tau ln((x0 - c tau) / (-c tau)); from full charge the curve starts t_c late) the rest of
/// the step runs on the curve from its intercept, P(dt - t_c). So a run's charge at a time does not
/// depend on how the time was cut into steps (a log's row spacing, a simulation's tick): one step
/// of 10 s gives what 100 steps of 0.1 s give, to rounding.
inline double start_transient_next(const CubicRow& q, double charge, double dt_s) {
  const double c_tau = q.c * kFirmwareFilterTau_s;
  const double x0 = charge - q.d;
  const double x = c_tau + (x0 - c_tau) * std::exp(-dt_s / kFirmwareFilterTau_s);
  if (x > 0 || !(c_tau < 0)) return q.d + x;
  const double t_c = kFirmwareFilterTau_s * std::log((x0 - c_tau) / -c_tau);
  const double rest_s = std::max(0.0, dt_s - t_c);
  if (rest_s >= q.end_s) return 0.0;
  const double p[4] = {q.d, q.c, q.b, q.a};
  return cubic_charge(p, rest_s);
}

/// True when the cubic decreases over all of [0, end] (its derivative, a quadratic, stays < 0).
inline bool decreasing_on_lifetime(const CubicRow& q) {
  auto slope = [&](double t) { return (3 * q.a * t + 2 * q.b) * t + q.c; };
  double worst = std::max(slope(0.0), slope(q.end_s));
  if (q.a != 0) {
    const double vertex = -q.b / (3 * q.a);
    if (vertex > 0 && vertex < q.end_s) worst = std::max(worst, slope(vertex));
  }
  return worst < 0;
}

/// The time at which the cubic reads `charge` (d > charge): the first crossing on [0, end], by
/// Newton steps safeguarded by bisection inside a bracket; never NaN, whatever the coefficients.
/// Returns end_s when the charge is below the curve over the whole of [0, end].
/// `guess_s`, when strictly inside the bracket, is where the Newton steps start (otherwise the
/// secant through the bracket's ends): it changes how many steps are taken, not the tolerance
/// the root is found to.
inline double cubic_time(const CubicRow& q, double charge, double guess_s) {
  const double p[4] = {q.d, q.c, q.b, q.a};
  double lo = 0.0;
  double hi = q.end_s;
  if (decreasing_on_lifetime(q)) {
    if (cubic_charge(p, hi) > charge) return q.end_s;
  } else {
    // A fitted cubic may turn back up: bracket the first crossing by scanning.
    constexpr int kScan = 16;
    bool found = false;
    for (int i = 1; i <= kScan; ++i) {
      const double t = q.end_s * i / kScan;
      if (cubic_charge(p, t) <= charge) {
        hi = t;
        lo = q.end_s * (i - 1) / kScan;
        found = true;
        break;
      }
    }
    if (!found) return q.end_s;
  }
  // f(lo) > 0 >= f(hi) with f(t) = cubic(t) - charge. Start from the guess, else the secant.
  double t = guess_s;
  if (!(t > lo && t < hi)) {
    const double f_lo = cubic_charge(p, lo) - charge, f_hi = cubic_charge(p, hi) - charge;
    t = f_lo != f_hi ? lo + (hi - lo) * f_lo / (f_lo - f_hi) : 0.5 * (lo + hi);
  }
  const double tolerance_s = 1e-9 * (1.0 + q.end_s);
  for (int it = 0; it < 100; ++it) {
    const double f = cubic_charge(p, t) - charge;
    if (f > 0) lo = t; else hi = t;
    if (hi - lo <= tolerance_s || f == 0) break;
    const double df = (3 * q.a * t + 2 * q.b) * t + q.c;
    double next = df != 0 ? t - f / df : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // Newton left the bracket: bisect
    if (std::abs(next - t) <= tolerance_s) {
      t = next;
      break;
    }
    t = next;
  }
  return t;
}

inline double cubic_time(const CubicRow& q, double charge) { return cubic_time(q, charge, -1.0); }

/// Where one battery's Cubic root searches start, carried from tick to tick (simulate_discharge
/// does): per speed table, the time the previous tick reached on that table's curve, or a
/// negative value for none. The next tick's root on the same table is then within a fraction of a
/// second (exactly there at a constant table speed), and the safeguarded Newton steps take 1-2
/// iterations instead of about 5 from the secant. It is only a starting point: results match the
/// stateless step to the root's tolerance, whatever it holds (even another Tables' times).
struct CubicHints {
  std::array<double, kSpeedCount> t_s;
  CubicHints() { t_s.fill(-1.0); }
};

/// The cubic's value dt later than the time t at which it reads `charge`, as an increment:
/// cubic(t + dt) = charge + dt (cubic'(t) + dt (3 a t + b + a dt)), exact for a cubic when
/// cubic(t) = charge. Written so because t is only known to the root's tolerance: an error e in t
/// moves this by about cubic''(t) e dt (1e-8 e at dt = 0.1 s), where cubic(t + dt) moves by
/// cubic'(t) e (1e-4 e).
inline double cubic_advance(const CubicRow& q, double charge, double t_s, double dt_s) {
  const double slope = (3 * q.a * t_s + 2 * q.b) * t_s + q.c;
  return charge + dt_s * (slope + dt_s * (3 * q.a * t_s + q.b + q.a * dt_s));
}

/// One speed table's next charge; `hint_s` is that table's entry in CubicHints (read, then set to
/// the time reached).
inline double cubic_next(const CubicRow& q, double charge, double dt_s, double& hint_s) {
  if (charge > q.d) return start_transient_next(q, charge, dt_s);
  const double t = cubic_time(q, charge, hint_s);
  if (t >= q.end_s) return 0.0;
  hint_s = t + dt_s;
  return cubic_advance(q, charge, t, dt_s);
}

inline double cubic_next(const CubicRow& q, double charge, double dt_s) {
  double no_hint = -1.0;
  return cubic_next(q, charge, dt_s, no_hint);
}

/// The segment whose band holds the charge; above the first band the first segment, below the
/// last band the last one.
inline const Segment& segment_for(const std::array<Segment, kSegmentCount>& segs, double charge) {
  if (charge > segs[0].y1) return segs[0];
  for (int k = 0; k + 1 < kSegmentCount; ++k) {
    if (charge <= segs[k].y1 && charge >= segs[k].y2) return segs[k];
  }
  return segs[kSegmentCount - 1];
}

inline double lerp(double a, double b, double w) { return a + (b - a) * w; }

/// One tick of a model in the corrected behaviour, from the distance moved in the tick; `hints`
/// carries the Cubic model's root searches from tick to tick (see CubicHints).
inline double step(Model model, const Tables& t, double charge, double delta_pos_m, double dt_s,
                   CubicHints& hints) {
  if (dt_s == 0) return charge;  // a step of no length: no discharge (and no speed to look up)
  const double speed = exact_speed_cm_s(delta_pos_m, dt_s);
  const int lo = std::min(kSpeedCount - 1, static_cast<int>(std::floor(speed)));
  const int hi = std::min(kSpeedCount - 1, lo + 1);
  const double w = speed - lo;  // 0 at table lo, 1 at table hi
  double next = charge;
  switch (model) {
    case Model::simple:
      next = charge + (speed == 0 ? t.simple_static_slope_per_s : t.simple_moving_slope_per_s) * dt_s;
      break;
    case Model::linear:
      next = charge + lerp(t.linear_slope_per_s[lo], t.linear_slope_per_s[hi], w) * dt_s;
      break;
    case Model::cubic: {
      const double y_lo = cubic_next(t.cubic[lo], charge, dt_s, hints.t_s[lo]);
      // At a table speed (w = 0) lerp adds (y_hi - y_lo) * 0, a zero, to y_lo for any finite
      // y_hi (the max below makes a -0 +0): the other table is not needed.
      next = w == 0 ? y_lo : lerp(y_lo, cubic_next(t.cubic[hi], charge, dt_s, hints.t_s[hi]), w);
      break;
    }
    case Model::approximated:
      next = charge + lerp(segment_for(t.segments[lo], charge).m,
                           segment_for(t.segments[hi], charge).m, w) * dt_s;
      break;
  }
  return std::max(0.0, next);
}

/// The same tick without carried hints: every root search starts from the secant.
inline double step(Model model, const Tables& t, double charge, double delta_pos_m, double dt_s) {
  CubicHints fresh;
  return step(model, t, charge, delta_pos_m, dt_s, fresh);
}

}  // namespace corrected

/// One tick of `model` in `behaviour`.
inline double step(Model model, Behaviour behaviour, const Tables& t, double charge,
                   double delta_pos_m, double dt_s) {
  return behaviour == Behaviour::argos_compatible ? argos::step(model, t, charge, delta_pos_m, dt_s)
                                                  : corrected::step(model, t, charge, delta_pos_m, dt_s);
}

/// One tick with the corrected Cubic's root searches carried in `hints` (the plug-in compatible
/// arithmetic has no state and ignores them).
inline double step(Model model, Behaviour behaviour, const Tables& t, double charge,
                   double delta_pos_m, double dt_s, corrected::CubicHints& hints) {
  return behaviour == Behaviour::argos_compatible
             ? argos::step(model, t, charge, delta_pos_m, dt_s)
             : corrected::step(model, t, charge, delta_pos_m, dt_s, hints);
}

/// capacity_scale (docs/diagnose.md): a battery that holds k times the capacity of the
/// calibration batteries discharges as the model does with time running 1/k times as fast.
struct CapacityScale {
  double k = 1.0;
};

/// One tick of `model` in the corrected behaviour for a battery of scaled capacity: the tick of
/// dt_s seconds at the speed delta_pos_m / dt_s is the model's tick of dt_s / k at the same speed.
inline double step(Model model, const Tables& t, const CapacityScale& capacity, double charge, double delta_pos_m,
                   double dt_s) {
  return corrected::step(model, t, charge, delta_pos_m / capacity.k, dt_s / capacity.k);
}

/// What the plug-in's Linear and Simple models are defined by: lines from 1 at t = 0 to 0 at the
/// lifetime (the plug-in's source).
inline double lifetime_slope_per_s(double lifetime_s) { return -1.0 / lifetime_s; }

}  // namespace epuck2::models::battery
