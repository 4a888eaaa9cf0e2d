// The engine's automatic-differentiation scalar: a model templated on its scalar (lib/models'
// formulas, the diagnosis's kinds, the NIST models) is evaluated with `epuck2::fit::Jet<N>` (a
// value and its derivatives over N parameters) wherever a fit needs its derivatives.
//
// lib/fit's own forward-mode dual number, so that no unit outside lib/fit compiles a Ceres header
// (CTest `ceres_in_lib_fit_alone`). Every formula below is the same arithmetic as Ceres 2.1's Jet
// (include/ceres/jet.h of Ceres Solver 2.1.0, Copyright 2022 Google Inc., BSD 3-clause licence:
// "Redistribution and use in source and binary forms, with or without modification, are permitted
// provided that ... Neither the name of Google Inc. nor the names of its contributors may be used
// to endorse or promote products derived from this software without specific prior written
// permission."), operation for operation and in the same order (division by the reciprocal,
// sqrt's 1 / (2 sqrt a), pow's three forms and their special cases, ...), on the same Eigen
// vector type: what lib/fit differentiated with ceres::Jet it differentiates with this to the
// last bit, so every fitted number stays as it was (data/fitted regenerates byte for byte, NIST's
// log relative errors are unchanged). Only the double scalar is kept (Ceres' Jet<T, N> with
// T = double); jet.h's Bessel functions, lerp and midpoint, which no model uses, are left out.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <ostream>
#include <type_traits>

namespace epuck2::fit {

// The dual number and its functions live in their own namespace, found by argument-dependent
// lookup (a model writes `using std::exp; exp(x)`), with std's functions pulled in beside them as
// Ceres does, so that the same name serves doubles and Jets inside the formulas below.
namespace dual {

using std::abs;
using std::acos;
using std::asin;
using std::atan;
using std::atan2;
using std::cbrt;
using std::ceil;
using std::copysign;
using std::cos;
using std::cosh;
using std::erf;
using std::erfc;
using std::exp;
using std::exp2;
using std::expm1;
using std::fdim;
using std::floor;
using std::fma;
using std::fmax;
using std::fmin;
using std::fpclassify;
using std::hypot;
using std::isfinite;
using std::isgreater;
using std::isgreaterequal;
using std::isinf;
using std::isless;
using std::islessequal;
using std::islessgreater;
using std::isnan;
using std::isnormal;
using std::isunordered;
using std::log;
using std::log10;
using std::log1p;
using std::log2;
using std::pow;
using std::signbit;
using std::sin;
using std::sinh;
using std::sqrt;
using std::tan;
using std::tanh;

/// A value `a` and its derivatives `v` with respect to N parameters.
template <int N>
struct Jet {
  enum { DIMENSION = N };
  using Scalar = double;

  Jet() : a() { v.setConstant(0.0); }
  /// A constant: value, no derivatives.
  explicit Jet(const double& value) {
    a = value;
    v.setConstant(0.0);
  }
  /// Parameter k at `value`: derivative 1 in slot k.
  Jet(const double& value, int k) {
    a = value;
    v.setConstant(0.0);
    v[k] = 1.0;
  }
  template <typename Derived>
  EIGEN_STRONG_INLINE Jet(const double& value, const Eigen::DenseBase<Derived>& derivatives) : a(value), v(derivatives) {}

  Jet& operator+=(const Jet& y) { return *this = *this + y; }
  Jet& operator-=(const Jet& y) { return *this = *this - y; }
  Jet& operator*=(const Jet& y) { return *this = *this * y; }
  Jet& operator/=(const Jet& y) { return *this = *this / y; }
  Jet& operator+=(const double& s) { return *this = *this + s; }
  Jet& operator-=(const double& s) { return *this = *this - s; }
  Jet& operator*=(const double& s) { return *this = *this * s; }
  Jet& operator/=(const double& s) { return *this = *this / s; }

  double a;
  Eigen::Matrix<double, N, 1> v;

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

// ----- Arithmetic -------------------------------------------------------------------------------

template <int N>
inline const Jet<N>& operator+(const Jet<N>& f) {
  return f;
}
template <int N>
inline Jet<N> operator-(const Jet<N>& f) {
  return Jet<N>(-f.a, -f.v);
}
template <int N>
inline Jet<N> operator+(const Jet<N>& f, const Jet<N>& g) {
  return Jet<N>(f.a + g.a, f.v + g.v);
}
template <int N>
inline Jet<N> operator+(const Jet<N>& f, double s) {
  return Jet<N>(f.a + s, f.v);
}
template <int N>
inline Jet<N> operator+(double s, const Jet<N>& f) {
  return Jet<N>(f.a + s, f.v);
}
template <int N>
inline Jet<N> operator-(const Jet<N>& f, const Jet<N>& g) {
  return Jet<N>(f.a - g.a, f.v - g.v);
}
template <int N>
inline Jet<N> operator-(const Jet<N>& f, double s) {
  return Jet<N>(f.a - s, f.v);
}
template <int N>
inline Jet<N> operator-(double s, const Jet<N>& f) {
  return Jet<N>(s - f.a, -f.v);
}
template <int N>
inline Jet<N> operator*(const Jet<N>& f, const Jet<N>& g) {
  return Jet<N>(f.a * g.a, f.a * g.v + f.v * g.a);
}
template <int N>
inline Jet<N> operator*(const Jet<N>& f, double s) {
  return Jet<N>(f.a * s, f.v * s);
}
template <int N>
inline Jet<N> operator*(double s, const Jet<N>& f) {
  return Jet<N>(f.a * s, f.v * s);
}
// (a + u) / (b + v) = (a + u)(b - v) / b^2, as v^2 = 0: by the reciprocal of b, as Ceres does.
template <int N>
inline Jet<N> operator/(const Jet<N>& f, const Jet<N>& g) {
  const double g_a_inverse = 1.0 / g.a;
  const double f_a_by_g_a = f.a * g_a_inverse;
  return Jet<N>(f_a_by_g_a, (f.v - f_a_by_g_a * g.v) * g_a_inverse);
}
template <int N>
inline Jet<N> operator/(double s, const Jet<N>& g) {
  const double minus_s_g_a_inverse2 = -s / (g.a * g.a);
  return Jet<N>(s / g.a, g.v * minus_s_g_a_inverse2);
}
template <int N>
inline Jet<N> operator/(const Jet<N>& f, double s) {
  const double s_inverse = 1.0 / s;
  return Jet<N>(f.a * s_inverse, f.v * s_inverse);
}

// ----- Comparisons: on the values ---------------------------------------------------------------

#define EPUCK2_FIT_JET_COMPARISON(op)                                                          \
  template <int N>                                                                             \
  constexpr bool operator op(const Jet<N>& f, const Jet<N>& g) noexcept {                      \
    return f.a op g.a;                                                                         \
  }                                                                                            \
  template <int N>                                                                             \
  constexpr bool operator op(const Jet<N>& f, double g) noexcept {                             \
    return f.a op g;                                                                           \
  }                                                                                            \
  template <int N>                                                                             \
  constexpr bool operator op(double f, const Jet<N>& g) noexcept {                             \
    return f op g.a;                                                                           \
  }
EPUCK2_FIT_JET_COMPARISON(<)
EPUCK2_FIT_JET_COMPARISON(<=)
EPUCK2_FIT_JET_COMPARISON(>)
EPUCK2_FIT_JET_COMPARISON(>=)
EPUCK2_FIT_JET_COMPARISON(==)
EPUCK2_FIT_JET_COMPARISON(!=)
#undef EPUCK2_FIT_JET_COMPARISON

// ----- Functions: f(a + h) ~= f(a) + f'(a) h ----------------------------------------------------

template <int N>
inline Jet<N> abs(const Jet<N>& f) {
  return Jet<N>(abs(f.a), copysign(1.0, f.a) * f.v);
}
template <int N>
inline Jet<N> fabs(const Jet<N>& f) {
  return abs(f);
}
// copysign(a, b) = sgn(b)|a|: d/da = sgn(a) sgn(b), d/db = 2|a| delta(b) (infinite at b = 0).
template <int N>
inline Jet<N> copysign(const Jet<N>& f, const Jet<N> g) {
  double d = fpclassify(g.a) == FP_ZERO ? std::numeric_limits<double>::infinity() : 0.0;
  double sa = copysign(1.0, f.a);
  double sb = copysign(1.0, g.a);
  return Jet<N>(copysign(f.a, g.a), sa * sb * f.v + abs(f.a) * d * g.v);
}
template <int N>
inline Jet<N> log(const Jet<N>& f) {
  const double a_inverse = 1.0 / f.a;
  return Jet<N>(log(f.a), f.v * a_inverse);
}
template <int N>
inline Jet<N> log10(const Jet<N>& f) {
  const double a_inverse = 1.0 / (f.a * log(10.0));
  return Jet<N>(log10(f.a), f.v * a_inverse);
}
template <int N>
inline Jet<N> log1p(const Jet<N>& f) {
  const double a_inverse = 1.0 / (1.0 + f.a);
  return Jet<N>(log1p(f.a), f.v * a_inverse);
}
template <int N>
inline Jet<N> exp(const Jet<N>& f) {
  const double tmp = exp(f.a);
  return Jet<N>(tmp, tmp * f.v);
}
template <int N>
inline Jet<N> expm1(const Jet<N>& f) {
  const double tmp = expm1(f.a);
  const double expa = tmp + 1.0;
  return Jet<N>(tmp, expa * f.v);
}
template <int N>
inline Jet<N> sqrt(const Jet<N>& f) {
  const double tmp = sqrt(f.a);
  const double two_a_inverse = 1.0 / (2.0 * tmp);
  return Jet<N>(tmp, f.v * two_a_inverse);
}
template <int N>
inline Jet<N> cos(const Jet<N>& f) {
  return Jet<N>(cos(f.a), -sin(f.a) * f.v);
}
template <int N>
inline Jet<N> acos(const Jet<N>& f) {
  const double tmp = -1.0 / sqrt(1.0 - f.a * f.a);
  return Jet<N>(acos(f.a), tmp * f.v);
}
template <int N>
inline Jet<N> sin(const Jet<N>& f) {
  return Jet<N>(sin(f.a), cos(f.a) * f.v);
}
template <int N>
inline Jet<N> asin(const Jet<N>& f) {
  const double tmp = 1.0 / sqrt(1.0 - f.a * f.a);
  return Jet<N>(asin(f.a), tmp * f.v);
}
template <int N>
inline Jet<N> tan(const Jet<N>& f) {
  const double tan_a = tan(f.a);
  const double tmp = 1.0 + tan_a * tan_a;
  return Jet<N>(tan_a, tmp * f.v);
}
template <int N>
inline Jet<N> atan(const Jet<N>& f) {
  const double tmp = 1.0 / (1.0 + f.a * f.a);
  return Jet<N>(atan(f.a), tmp * f.v);
}
template <int N>
inline Jet<N> sinh(const Jet<N>& f) {
  return Jet<N>(sinh(f.a), cosh(f.a) * f.v);
}
template <int N>
inline Jet<N> cosh(const Jet<N>& f) {
  return Jet<N>(cosh(f.a), sinh(f.a) * f.v);
}
template <int N>
inline Jet<N> tanh(const Jet<N>& f) {
  const double tanh_a = tanh(f.a);
  const double tmp = 1.0 - tanh_a * tanh_a;
  return Jet<N>(tanh_a, tmp * f.v);
}
// floor and ceil: a zero derivative.
template <int N>
inline Jet<N> floor(const Jet<N>& f) {
  return Jet<N>(floor(f.a));
}
template <int N>
inline Jet<N> ceil(const Jet<N>& f) {
  return Jet<N>(ceil(f.a));
}
template <int N>
inline Jet<N> cbrt(const Jet<N>& f) {
  const double derivative = 1.0 / (3.0 * cbrt(f.a * f.a));
  return Jet<N>(cbrt(f.a), f.v * derivative);
}
template <int N>
inline Jet<N> exp2(const Jet<N>& f) {
  const double tmp = exp2(f.a);
  const double derivative = tmp * log(2.0);
  return Jet<N>(tmp, f.v * derivative);
}
template <int N>
inline Jet<N> log2(const Jet<N>& f) {
  const double derivative = 1.0 / (f.a * log(2.0));
  return Jet<N>(log2(f.a), f.v * derivative);
}
template <int N>
inline Jet<N> hypot(const Jet<N>& x, const Jet<N>& y) {
  const double tmp = hypot(x.a, y.a);
  return Jet<N>(tmp, x.a / tmp * x.v + y.a / tmp * y.v);
}
template <int N>
inline Jet<N> hypot(const Jet<N>& x, const Jet<N>& y, const Jet<N>& z) {
  const double tmp = hypot(x.a, y.a, z.a);
  return Jet<N>(tmp, x.a / tmp * x.v + y.a / tmp * y.v + z.a / tmp * z.v);
}
template <int N>
inline Jet<N> fma(const Jet<N>& x, const Jet<N>& y, const Jet<N>& z) {
  return Jet<N>(fma(x.a, y.a, z.a), y.a * x.v + x.a * y.v + z.v);
}
template <int N>
inline Jet<N> erf(const Jet<N>& x) {
  return Jet<N>(erf(x.a), x.v * exp(-x.a * x.a) * (1.0 / sqrt(atan(1.0))));
}
template <int N>
inline Jet<N> erfc(const Jet<N>& x) {
  return Jet<N>(erfc(x.a), -x.v * exp(-x.a * x.a) * (1.0 / sqrt(atan(1.0))));
}
// atan2(b + db, a + da) ~= atan2(b, a) + (- b da + a db) / (a^2 + b^2)
template <int N>
inline Jet<N> atan2(const Jet<N>& g, const Jet<N>& f) {
  const double tmp = 1.0 / (f.a * f.a + g.a * g.a);
  return Jet<N>(atan2(g.a, f.a), tmp * (-g.a * f.v + f.a * g.v));
}
// The square x^2 (std::norm's meaning).
template <int N>
inline Jet<N> norm(const Jet<N>& f) {
  return Jet<N>(f.a * f.a, 2.0 * f.a * f.v);
}

// ----- Classification: on the value -------------------------------------------------------------

template <int N>
inline bool isfinite(const Jet<N>& f) {
  return isfinite(f.a);
}
template <int N>
inline bool isinf(const Jet<N>& f) {
  return isinf(f.a);
}
template <int N>
inline bool isnan(const Jet<N>& f) {
  return isnan(f.a);
}
template <int N>
inline bool isnormal(const Jet<N>& f) {
  return isnormal(f.a);
}
template <int N>
inline int fpclassify(const Jet<N>& f) {
  return fpclassify(f.a);
}
template <int N>
inline bool signbit(const Jet<N>& f) {
  return signbit(f.a);
}
// The quiet comparisons, for a Jet and a Jet or a double on either side.
#define EPUCK2_FIT_JET_QUIET_COMPARISON(name)                  \
  template <int N>                                             \
  inline bool name(const Jet<N>& f, const Jet<N>& g) {         \
    return name(f.a, g.a);                                     \
  }                                                            \
  template <int N>                                             \
  inline bool name(const Jet<N>& f, double g) {                \
    return name(f.a, g);                                       \
  }                                                            \
  template <int N>                                             \
  inline bool name(double f, const Jet<N>& g) {                \
    return name(f, g.a);                                       \
  }
EPUCK2_FIT_JET_QUIET_COMPARISON(isless)
EPUCK2_FIT_JET_QUIET_COMPARISON(isgreater)
EPUCK2_FIT_JET_QUIET_COMPARISON(islessequal)
EPUCK2_FIT_JET_QUIET_COMPARISON(isgreaterequal)
EPUCK2_FIT_JET_QUIET_COMPARISON(islessgreater)
EPUCK2_FIT_JET_QUIET_COMPARISON(isunordered)
#undef EPUCK2_FIT_JET_QUIET_COMPARISON

// fmax, fmin (a NaN is missing data) and fdim, for a Jet and a Jet or a double on either side.
template <int N>
inline Jet<N> fmax(const Jet<N>& f, const Jet<N>& g) {
  return (isnan(g) || isgreater(f, g)) ? f : g;
}
template <int N>
inline Jet<N> fmax(const Jet<N>& f, double g) {
  return (isnan(g) || isgreater(f, g)) ? f : Jet<N>{g};
}
template <int N>
inline Jet<N> fmax(double f, const Jet<N>& g) {
  return (isnan(g) || isgreater(f, g)) ? Jet<N>{f} : g;
}
template <int N>
inline Jet<N> fmin(const Jet<N>& f, const Jet<N>& g) {
  return (isnan(f) || isless(g, f)) ? g : f;
}
template <int N>
inline Jet<N> fmin(const Jet<N>& f, double g) {
  return (isnan(f) || isless(g, f)) ? Jet<N>{g} : f;
}
template <int N>
inline Jet<N> fmin(double f, const Jet<N>& g) {
  return (isnan(f) || isless(g, f)) ? g : Jet<N>{f};
}
template <int N>
inline Jet<N> fdim(const Jet<N>& f, const Jet<N>& g) {
  if (isnan(f) || isnan(g)) return Jet<N>(std::numeric_limits<double>::quiet_NaN());
  return isgreater(f, g) ? Jet<N>{f - g} : Jet<N>{};
}
template <int N>
inline Jet<N> fdim(const Jet<N>& f, double g) {
  if (isnan(f) || isnan(g)) return Jet<N>(std::numeric_limits<double>::quiet_NaN());
  return isgreater(f, g) ? Jet<N>{f - g} : Jet<N>{};
}
template <int N>
inline Jet<N> fdim(double f, const Jet<N>& g) {
  if (isnan(f) || isnan(g)) return Jet<N>(std::numeric_limits<double>::quiet_NaN());
  return isgreater(f, g) ? Jet<N>{f - g} : Jet<N>{};
}

// ----- pow: Ceres 2.1's three forms and their special cases -------------------------------------

// Base differentiable, exponent constant: (a + da)^p ~= a^p + p a^(p-1) da.
template <int N>
inline Jet<N> pow(const Jet<N>& f, double g) {
  const double tmp = g * pow(f.a, g - 1.0);
  return Jet<N>(pow(f.a, g), tmp * f.v);
}
// Base constant, exponent differentiable: f > 0: f^g + f^g log(f) dg; f == 0 and g > 0: 0;
// f < 0 and g an integer: f^g, with NaN derivatives wherever dg != 0.
template <int N>
inline Jet<N> pow(double f, const Jet<N>& g) {
  Jet<N> result;
  if (fpclassify(f) == FP_ZERO && g > 0) {
    result = Jet<N>(0.0);
  } else {
    if (f < 0 && g == floor(g.a)) {
      result = Jet<N>(pow(f, g.a));
      for (int i = 0; i < N; i++)
        if (fpclassify(g.v[i]) != FP_ZERO) result.v[i] = std::numeric_limits<double>::quiet_NaN();
    } else {
      const double tmp = pow(f, g.a);
      result = Jet<N>(tmp, log(f) * tmp * g.v);
    }
  }
  return result;
}
// Both differentiable: f > 0: f^g + f^(g-1) (g df + f log(f) dg); f == 0 and g > 1: 0;
// f == 0 and g == 1: f; f < 0 and g an integer: g f^(g-1) df, NaN wherever dg != 0; elsewhere
// log() gives the non-finite derivatives.
template <int N>
inline Jet<N> pow(const Jet<N>& f, const Jet<N>& g) {
  Jet<N> result;
  if (fpclassify(f) == FP_ZERO && g >= 1) {
    if (g > 1) {
      result = Jet<N>(0.0);
    } else {
      result = f;
    }
  } else {
    if (f < 0 && g == floor(g.a)) {
      const double tmp = g.a * pow(f.a, g.a - 1.0);
      result = Jet<N>(pow(f.a, g.a), tmp * f.v);
      for (int i = 0; i < N; i++)
        if (fpclassify(g.v[i]) != FP_ZERO) result.v[i] = std::numeric_limits<double>::quiet_NaN();
    } else {
      const double tmp1 = pow(f.a, g.a);
      const double tmp2 = g.a * pow(f.a, g.a - 1.0);
      const double tmp3 = tmp1 * log(f.a);
      result = Jet<N>(tmp1, tmp2 * f.v + tmp3 * g.v);
    }
  }
  return result;
}

template <int N>
inline std::ostream& operator<<(std::ostream& s, const Jet<N>& z) {
  s << "[" << z.a << " ; ";
  for (int i = 0; i < N; ++i) {
    s << z.v[i];
    if (i != N - 1) s << ", ";
  }
  s << "]";
  return s;
}

}  // namespace dual

/// A value and its derivatives with respect to N parameters (member `a`: the value; `v`: the
/// derivatives, an Eigen vector of N).
template <int N>
using Jet = dual::Jet<N>;

/// The value of a scalar or a Jet (models branch on values, never on derivatives).
inline double value_of(double x) { return x; }
template <int N>
double value_of(const Jet<N>& x) {
  return x.a;
}

}  // namespace epuck2::fit

namespace std {
template <int N>
struct numeric_limits<epuck2::fit::dual::Jet<N>> : numeric_limits<double> {
  using J = epuck2::fit::dual::Jet<N>;
  static J min() noexcept { return J((numeric_limits<double>::min)()); }
  static J lowest() noexcept { return J(numeric_limits<double>::lowest()); }
  static J max() noexcept { return J((numeric_limits<double>::max)()); }
  static J epsilon() noexcept { return J(numeric_limits<double>::epsilon()); }
  static J round_error() noexcept { return J(numeric_limits<double>::round_error()); }
  static J infinity() noexcept { return J(numeric_limits<double>::infinity()); }
  static J quiet_NaN() noexcept { return J(numeric_limits<double>::quiet_NaN()); }
  static J signaling_NaN() noexcept { return J(numeric_limits<double>::signaling_NaN()); }
  static J denorm_min() noexcept { return J(numeric_limits<double>::denorm_min()); }
};
}  // namespace std

namespace Eigen {
// Jets in Eigen matrices, and Jet-double operations there, as Ceres declares them.
template <int N>
struct NumTraits<epuck2::fit::dual::Jet<N>> {
  using Real = epuck2::fit::dual::Jet<N>;
  using NonInteger = Real;
  using Nested = Real;
  using Literal = Real;
  static Real dummy_precision() { return Real(1e-12); }
  static inline Real epsilon() { return Real(std::numeric_limits<double>::epsilon()); }
  static inline int digits10() { return NumTraits<double>::digits10(); }
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned,
    ReadCost = 1,
    AddCost = 1,
    MulCost = 3,
    HasFloatingPoint = 1,
    RequireInitialization = 1
  };
  template <bool Vectorized>
  struct Div {
    enum {
#if defined(EIGEN_VECTORIZE_AVX)
      AVX = true,
#else
      AVX = false,
#endif
      Cost = 3
    };
  };
  static inline Real highest() { return Real((std::numeric_limits<double>::max)()); }
  static inline Real lowest() { return Real(-(std::numeric_limits<double>::max)()); }
};
template <typename BinaryOp, int N>
struct ScalarBinaryOpTraits<epuck2::fit::dual::Jet<N>, double, BinaryOp> {
  using ReturnType = epuck2::fit::dual::Jet<N>;
};
template <typename BinaryOp, int N>
struct ScalarBinaryOpTraits<double, epuck2::fit::dual::Jet<N>, BinaryOp> {
  using ReturnType = epuck2::fit::dual::Jet<N>;
};
}  // namespace Eigen
