// The drive: how the wheels and the body follow the commanded wheel speeds, what the encoders
// count and what the time-of-flight sensor reads while the robot drives towards an obstacle.
// Header-only, standard library only (epuck2::models); units in every name. Umbrella: sensors.hpp.
//
// The plug-in's model (docs/diagnose.md, "drive"): the wheels turn at the commanded speed at once
// (zero-order hold between commands), the body moves with the wheels, the encoders count
// steps_per_m times the wheel's travel and the ToF reads 1000 (D - x) mm. The diagnosis
// catalogue's effects, one parameter struct each and neutral by default, extend it:
//   u_w = clamp(v_c, -max, max)                      speed_limit      [max_cm_s]
//   v_w follows u_w with |dv_w/dt| <= accel          accel_limit      [accel_cm_s2]
//   dv_g/dt = (k v_w - v_g) / tau                    wheel_slip [tau_s], speed_scale [k]
//   tof(t) = k_tof 1000 (D - x_g(t - delay)) + offset  latency [delay_s], tof_scale, tof_offset
// Within an interval of constant command every speed is piecewise linear in time (a ramp, then
// constant), and the lag is integrated exactly over each piece: no time step.
#pragma once

#include <cmath>
#include <type_traits>

#include "epuck2/models/tof.hpp"

namespace epuck2::models::sensors {

/// The number a scalar carries: itself, or an automatic-differentiation scalar's value (member
/// `a`, as fit::Jet has it). Models branch on values, never on derivatives.
template <typename T>
double scalar_of(const T& x) {
  if constexpr (std::is_arithmetic_v<T>) {
    return static_cast<double>(x);
  } else {
    return x.a;
  }
}

/// A limit at or above this is no limit (the neutral values below).
inline constexpr double kDriveNoLimit = 1e6;
inline constexpr double kDriveLimitOn = 1e5;

/// speed_limit: wheel speeds are clamped to +-max_cm_s.
template <typename T = double>
struct DriveSpeedLimit {
  T max_cm_s = T(kDriveNoLimit);
};
/// accel_limit: a wheel's speed changes by at most accel_cm_s2.
template <typename T = double>
struct DriveAccelLimit {
  T accel_cm_s2 = T(kDriveNoLimit);
};
/// wheel_slip: the body's speed over the ground follows the wheels' through a first-order lag.
template <typename T = double>
struct DriveWheelSlip {
  T tau_s = T(0.0);
};
/// speed_scale: the body moves k times what the wheels turn (worn or mis-sized wheels).
template <typename T = double>
struct DriveSpeedScale {
  T k = T(1.0);
};
/// latency: the ToF reading at t is the true one at t - delay_s.
template <typename T = double>
struct TofLatency {
  T delay_s = T(0.0);
};
/// tof_offset and tof_scale: tof = k true + offset_mm.
template <typename T = double>
struct TofOffset {
  T offset_mm = T(0.0);
};
template <typename T = double>
struct TofScale {
  T k = T(1.0);
};

template <typename T = double>
struct DriveEffects {
  DriveSpeedLimit<T> speed_limit;
  DriveAccelLimit<T> accel_limit;
  DriveWheelSlip<T> slip;
  DriveSpeedScale<T> speed_scale;
  TofLatency<T> latency;
  TofOffset<T> tof_offset;
  TofScale<T> tof_scale;
};

/// The state of the drive: each wheel's speed (m/s) and travel (m), the body's speed and travel.
template <typename T = double>
struct DriveState {
  T vl = T(0.0), vr = T(0.0), xl = T(0.0), xr = T(0.0), vg = T(0.0), xg = T(0.0);
};

/// The body over `len_s` seconds whose input (k times the wheels' mean speed) starts at u0 and
/// changes at the rate ag: the first-order lag dv/dt = (u - v)/tau integrated exactly, or
/// followed at once (tau = 0, no slip).
template <typename T>
void body_lag_piece(const DriveWheelSlip<T>& slip, const T& u0_m_s, const T& ag_m_s2, const T& len_s, T& xg_m,
                    T& vg_m_s) {
  using std::exp;
  if (scalar_of(slip.tau_s) > 0) {
    const T& tau = slip.tau_s;
    // e^-50 ~ 2e-22: below it the lag has settled (and exp would underflow slowly).
    const T e = scalar_of(len_s / tau) < 50.0 ? exp(-len_s / tau) : T(0.0);
    const T c = vg_m_s - u0_m_s + ag_m_s2 * tau;
    xg_m += u0_m_s * len_s + 0.5 * ag_m_s2 * len_s * len_s - ag_m_s2 * tau * len_s + c * tau * (1.0 - e);
    vg_m_s = u0_m_s + ag_m_s2 * len_s - ag_m_s2 * tau + c * e;
  } else {
    xg_m += u0_m_s * len_s + 0.5 * ag_m_s2 * len_s * len_s;
    vg_m_s = u0_m_s + ag_m_s2 * len_s;
  }
}

/// Advances the drive by h seconds under the commands (cm/s). `symmetric`: a hint that both
/// wheels are commanded alike, so that one wheel is simulated for both (the same arithmetic). It is
/// taken only when it holds: equal commands and wheels alike (equal travels and speeds). After a
/// turn, a stop's equal commands must move each wheel from its own state, not copy the left's.
template <typename T>
void drive_advance(const DriveEffects<T>& e, double left_cm_s, double right_cm_s, const T& h, DriveState<T>& st,
                   bool symmetric = false) {
  using std::fmax;
  using std::fmin;
  constexpr double kPerCm = 0.01;
  if (!(scalar_of(h) > 0)) return;
  symmetric = symmetric && left_cm_s == right_cm_s && scalar_of(st.xl) == scalar_of(st.xr) &&
              scalar_of(st.vl) == scalar_of(st.vr);
  const T& max = e.speed_limit.max_cm_s;
  const bool accel_limited = scalar_of(e.accel_limit.accel_cm_s2) < kDriveLimitOn;
  if (symmetric) {
    const T u = fmin(fmax(T(left_cm_s), -max), max) * kPerCm;
    T a(0.0), ramp(0.0);
    if (accel_limited) {
      const T dv = u - st.vl;
      if (scalar_of(dv) != 0) {
        a = scalar_of(dv) > 0 ? e.accel_limit.accel_cm_s2 * kPerCm : -e.accel_limit.accel_cm_s2 * kPerCm;
        ramp = dv / a;
      }
    } else {
      st.vl = u;
    }
    if (scalar_of(ramp) > scalar_of(h)) ramp = h;
    T done(0.0);
    for (int piece = 0; piece < 2; ++piece) {
      const T end = piece == 0 ? ramp : h;
      const T len = end - done;
      if (!(scalar_of(len) > 0)) continue;
      const T acc = piece == 0 ? a : T(0.0);
      body_lag_piece(e.slip, T(e.speed_scale.k * st.vl), T(e.speed_scale.k * acc), len, st.xg, st.vg);
      st.xl += st.vl * len + 0.5 * acc * len * len;
      st.vl += acc * len;
      done = end;
    }
    st.xr = st.xl;
    st.vr = st.vl;
    return;
  }
  const T ul = fmin(fmax(T(left_cm_s), -max), max) * kPerCm;
  const T ur = fmin(fmax(T(right_cm_s), -max), max) * kPerCm;
  // Each wheel: a ramp at +-accel for t_w seconds (possibly 0), then constant.
  T al(0.0), ar(0.0), tl(0.0), tr(0.0);
  if (accel_limited) {
    const T accel = e.accel_limit.accel_cm_s2 * kPerCm;
    const T dl = ul - st.vl, dr = ur - st.vr;
    if (scalar_of(dl) != 0) {
      al = scalar_of(dl) > 0 ? accel : -accel;
      tl = dl / al;
    }
    if (scalar_of(dr) != 0) {
      ar = scalar_of(dr) > 0 ? accel : -accel;
      tr = dr / ar;
    }
  } else {
    st.vl = ul;
    st.vr = ur;
  }
  // Pieces: [0, min(tl, tr)], [.., max(tl, tr)], [.., h], each cut at h.
  T first = scalar_of(tl) < scalar_of(tr) ? tl : tr, second = scalar_of(tl) < scalar_of(tr) ? tr : tl;
  if (scalar_of(first) > scalar_of(h)) first = h;
  if (scalar_of(second) > scalar_of(h)) second = h;
  T done(0.0);
  for (const T& end : {first, second, h}) {
    const T len = end - done;
    if (!(scalar_of(len) > 0)) continue;
    const T a_l = scalar_of(done) < scalar_of(tl) ? al : T(0.0);
    const T a_r = scalar_of(done) < scalar_of(tr) ? ar : T(0.0);
    body_lag_piece(e.slip, T(e.speed_scale.k * 0.5 * (st.vl + st.vr)), T(e.speed_scale.k * 0.5 * (a_l + a_r)), len,
                   st.xg, st.vg);
    st.xl += st.vl * len + 0.5 * a_l * len * len;
    st.xr += st.vr * len + 0.5 * a_r * len * len;
    st.vl += a_l * len;
    st.vr += a_r * len;
    done = end;
  }
}

/// The ToF reading's mean in mm before the clamp to [20, 2000] and the rounding, with the body
/// `travel_m` from where the obstacle was `obstacle_m` away: k 1000 (D - x) + offset.
template <typename T>
T drive_tof_mean_mm(const DriveEffects<T>& e, double obstacle_m, const T& travel_m) {
  return e.tof_scale.k * (1000.0 * (obstacle_m - travel_m)) + e.tof_offset.offset_mm;
}

/// An encoder register's mean (unwrapped steps) after a wheel travel of `wheel_m`: the register is
/// floor(steps_per_m x), whose mean is steps_per_m x - 1/2 once the wheel has moved, and exactly 0
/// before. Either may be the scalar a fit differentiates (the calibration fits steps_per_m, the
/// diagnosis the travel); the result has that type.
template <typename S, typename T>
auto encoder_mean_steps(const S& steps_per_m, const T& wheel_m) {
  using R = std::conditional_t<std::is_arithmetic_v<S>, T, S>;
  if (scalar_of(wheel_m) == 0.0) return R(0.0);
  return R(steps_per_m * wheel_m - 0.5);
}

/// The body's travel (m) at each of `n` sample times when the wheels' travel between samples is
/// known (encoders: constant speed between samples) and the body follows through the lag: what
/// the drive calibration fits (tof against travel). `time_s` and `wheel_m` have n entries.
template <typename T, class Times, class Travel>
void lagged_body_travel_m(const DriveWheelSlip<T>& slip, const Times& time_s, const Travel& wheel_m, T* out) {
  T speed(0.0), travel(0.0);
  const std::size_t n = time_s.size();
  for (std::size_t k = 0; k + 1 < n; ++k) {
    out[k] = travel;
    const double dt = time_s[k + 1] - time_s[k];
    if (!(dt > 0)) continue;
    const T wheel(((wheel_m[k + 1] - wheel_m[k]) / dt));
    body_lag_piece(slip, wheel, T(0.0), T(dt), travel, speed);
  }
  if (n) out[n - 1] = travel;
}

}  // namespace epuck2::models::sensors
