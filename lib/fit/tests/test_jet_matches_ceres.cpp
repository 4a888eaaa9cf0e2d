// epuck2::fit::Jet against Ceres 2.1's own Jet, bit for bit: every operator and function of
// epuck2/fit/jet.hpp evaluated on the same values and derivatives with both, over seeded random
// operands and the special cases of pow, abs, copysign and the comparisons. lib/fit's Jet is what
// every model is differentiated with, and the fitted numbers stay the same only if its arithmetic
// is Ceres' to the last bit. The expected values come from Ceres (include/ceres/jet.h), not from
// the code under test. This program is lib/fit's (it compiles Ceres' header, as only lib/fit may:
// CTest ceres_in_lib_fit_objects).
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "epuck2/fit/jet.hpp"

namespace {

constexpr int N = 3;
using Ours = epuck2::fit::Jet<N>;
using Theirs = ceres::Jet<double, N>;

bool same_bits(double x, double y) { return std::memcmp(&x, &y, sizeof x) == 0 || (std::isnan(x) && std::isnan(y)); }

::testing::AssertionResult same(const Ours& ours, const Theirs& theirs) {
  bool ok = same_bits(ours.a, theirs.a);
  for (int i = 0; i < N; ++i) ok = ok && same_bits(ours.v[i], theirs.v[i]);
  if (ok) return ::testing::AssertionSuccess();
  std::ostringstream s;
  s.precision(17);
  s << "fit::Jet " << ours << " but ceres::Jet " << theirs;
  return ::testing::AssertionFailure() << s.str();
}

struct Operand {
  double a;
  double v[N];
  Ours ours() const { return Ours(a, Eigen::Matrix<double, N, 1>(v[0], v[1], v[2])); }
  Theirs theirs() const { return Theirs(a, Eigen::Matrix<double, N, 1>(v[0], v[1], v[2])); }
};

// Seeded operands: positive (for log, sqrt, pow), in (-1, 1) (for asin, acos), of either sign,
// and the special values the formulas branch on.
std::vector<Operand> operands() {
  std::mt19937_64 rng(20261126);
  std::uniform_real_distribution<double> value(-3.0, 3.0), unit(-0.99, 0.99), positive(1e-3, 7.0), slope(-2.0, 2.0);
  std::vector<Operand> out;
  for (int k = 0; k < 200; ++k) {
    const double a = k % 3 == 0 ? positive(rng) : k % 3 == 1 ? unit(rng) : value(rng);
    out.push_back({a, {slope(rng), slope(rng), slope(rng)}});
  }
  for (double a : {0.0, -0.0, 1.0, -1.0, 2.0, -2.0, 0.5, -3.0, 1e-300, 1e300})
    out.push_back({a, {1.0, 0.0, -0.5}});
  out.push_back({-2.0, {0.0, 0.0, 0.0}});  // a constant: pow's integer-exponent cases
  out.push_back({3.0, {0.0, 0.0, 0.0}});
  return out;
}

#define EXPECT_UNARY(expr)                                                                   \
  for (const Operand& o : operands()) {                                                      \
    {                                                                                        \
      using namespace std;                                                                   \
      const Ours x = o.ours();                                                               \
      const Ours ours = (expr);                                                              \
      const Theirs theirs = [&] {                                                            \
        const Theirs x = o.theirs();                                                         \
        return Theirs(expr);                                                                 \
      }();                                                                                   \
      EXPECT_TRUE(same(ours, theirs)) << #expr << " at a = " << o.a;                        \
    }                                                                                        \
  }

#define EXPECT_BINARY(expr)                                                                  \
  {                                                                                          \
    const std::vector<Operand> all = operands();                                             \
    for (std::size_t i = 0; i < all.size(); i += 3)                                          \
      for (std::size_t j = 1; j < all.size(); j += 7) {                                      \
        using namespace std;                                                                 \
        const double s = all[j].a;                                                           \
        const Ours x = all[i].ours(), y = all[j].ours();                                     \
        const Ours ours = (expr);                                                            \
        const Theirs theirs = [&] {                                                          \
          const Theirs x = all[i].theirs(), y = all[j].theirs();                             \
          return Theirs(expr);                                                               \
        }();                                                                                 \
        EXPECT_TRUE(same(ours, theirs)) << #expr << " at " << all[i].a << ", " << all[j].a; \
        (void)s;                                                                             \
      }                                                                                      \
  }

TEST(JetMatchesCeres, Arithmetic) {
  EXPECT_BINARY(x + y);
  EXPECT_BINARY(x - y);
  EXPECT_BINARY(x * y);
  EXPECT_BINARY(x / y);
  EXPECT_BINARY(x + s);
  EXPECT_BINARY(s + x);
  EXPECT_BINARY(x - s);
  EXPECT_BINARY(s - x);
  EXPECT_BINARY(x * s);
  EXPECT_BINARY(s * x);
  EXPECT_BINARY(x / s);
  EXPECT_BINARY(s / x);
  EXPECT_UNARY(-x);
  EXPECT_UNARY(+x);
}

TEST(JetMatchesCeres, CompoundAssignment) {
  EXPECT_BINARY([&] { auto z = x; z += y; return z; }());
  EXPECT_BINARY([&] { auto z = x; z -= y; return z; }());
  EXPECT_BINARY([&] { auto z = x; z *= y; return z; }());
  EXPECT_BINARY([&] { auto z = x; z /= y; return z; }());
  EXPECT_BINARY([&] { auto z = x; z += s; return z; }());
  EXPECT_BINARY([&] { auto z = x; z -= s; return z; }());
  EXPECT_BINARY([&] { auto z = x; z *= s; return z; }());
  EXPECT_BINARY([&] { auto z = x; z /= s; return z; }());
}

TEST(JetMatchesCeres, Functions) {
  EXPECT_UNARY(abs(x));
  EXPECT_UNARY(log(x));
  EXPECT_UNARY(log10(x));
  EXPECT_UNARY(log1p(x));
  EXPECT_UNARY(exp(x));
  EXPECT_UNARY(expm1(x));
  EXPECT_UNARY(sqrt(x));
  EXPECT_UNARY(cos(x));
  EXPECT_UNARY(acos(x));
  EXPECT_UNARY(sin(x));
  EXPECT_UNARY(asin(x));
  EXPECT_UNARY(tan(x));
  EXPECT_UNARY(atan(x));
  EXPECT_UNARY(sinh(x));
  EXPECT_UNARY(cosh(x));
  EXPECT_UNARY(tanh(x));
  EXPECT_UNARY(floor(x));
  EXPECT_UNARY(ceil(x));
  EXPECT_UNARY(cbrt(x));
  EXPECT_UNARY(exp2(x));
  EXPECT_UNARY(log2(x));
  EXPECT_UNARY(erf(x));
  EXPECT_UNARY(erfc(x));
  EXPECT_UNARY(norm(x));
  EXPECT_BINARY(atan2(x, y));
  EXPECT_BINARY(hypot(x, y));
  EXPECT_BINARY(hypot(x, y, x * y));
  EXPECT_BINARY(fma(x, y, x));
  EXPECT_BINARY(copysign(x, y));
  EXPECT_BINARY(fmax(x, y));
  EXPECT_BINARY(fmin(x, y));
  EXPECT_BINARY(fdim(x, y));
  EXPECT_BINARY(fmax(x, s));
  EXPECT_BINARY(fmin(s, x));
}

TEST(JetMatchesCeres, PowInItsThreeFormsAndSpecialCases) {
  EXPECT_BINARY(pow(x, y));
  EXPECT_BINARY(pow(x, s));
  EXPECT_BINARY(pow(s, y));
  for (double e : {0.0, 1.0, 2.0, -1.0, 0.5, 3.0, -2.5}) {
    EXPECT_UNARY(pow(x, e));
    EXPECT_UNARY(pow(e, x));
    EXPECT_UNARY(pow(x, decltype(x)(e)));
    EXPECT_UNARY(pow(decltype(x)(e), x));
  }
}

TEST(JetMatchesCeres, ComparisonsAndClassificationOnTheValue) {
  const std::vector<Operand> all = operands();
  for (const Operand& p : all)
    for (const Operand& q : all) {
      const Ours x = p.ours(), y = q.ours();
      const Theirs cx = p.theirs(), cy = q.theirs();
      EXPECT_EQ(x < y, cx < cy);
      EXPECT_EQ(x <= y, cx <= cy);
      EXPECT_EQ(x > y, cx > cy);
      EXPECT_EQ(x >= y, cx >= cy);
      EXPECT_EQ(x == y, cx == cy);
      EXPECT_EQ(x != y, cx != cy);
      EXPECT_EQ(x < q.a, cx < q.a);
      EXPECT_EQ(p.a >= y, p.a >= cy);
      EXPECT_EQ(x > 0, cx > 0);
      EXPECT_EQ(isless(x, y), ceres::isless(cx, cy));
      EXPECT_EQ(isgreater(x, q.a), ceres::isgreater(cx, q.a));
    }
  for (double a : {0.0, 1.0, std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN(), 1e-310}) {
    const Ours x(a, 0);
    const Theirs cx(a, 0);
    EXPECT_EQ(isfinite(x), ceres::isfinite(cx));
    EXPECT_EQ(isnan(x), ceres::isnan(cx));
    EXPECT_EQ(isinf(x), ceres::isinf(cx));
    EXPECT_EQ(isnormal(x), ceres::isnormal(cx));
    EXPECT_EQ(fpclassify(x), ceres::fpclassify(cx));
  }
}

TEST(JetMatchesCeres, ConstructionAndSeeding) {
  const Ours zero;
  EXPECT_TRUE(same(zero, Theirs()));
  EXPECT_TRUE(same(Ours(2.5), Theirs(2.5)));
  for (int k = 0; k < N; ++k) EXPECT_TRUE(same(Ours(-1.25, k), Theirs(-1.25, k)));
  EXPECT_EQ(epuck2::fit::value_of(Ours(4.0, 1)), 4.0);
  EXPECT_EQ(std::numeric_limits<Ours>::infinity().a, std::numeric_limits<Theirs>::infinity().a);
  EXPECT_TRUE(same(std::numeric_limits<Ours>::epsilon(), std::numeric_limits<Theirs>::epsilon()));
}

}  // namespace
