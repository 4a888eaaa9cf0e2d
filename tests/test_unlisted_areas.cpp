// Tests aimed at slips nobody listed (issue #22, item 6), second set: the voltage->charge map,
// the cluster-robust standard errors, the robots' Cochran Q test, the Tobit terms, codegen and the
// naming step of the diagnosis's findings. Every expected value is
// worked by hand below from the formulas the headers and docs state (not read back from the code):
// a map given by hand with a load term whose offsets differ per speed, runs whose scores differ
// per parameter, robots whose weights differ, and the cases at the branch points (exactly
// kMinClusters runs, a voltage exactly at a knot and at the range's ends, a Q whose p-value sits
// either side of kRobotSpreadP). The slips they were written against: bench/fresh-slips.md.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "epuck2/calibrate/charge_map.hpp"
#include "epuck2/coefficients/codegen.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/fit/report.hpp"
#include "epuck2/fit/robust.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/effects.hpp"
// The diagnosis's problems (make_problem, Problem::identify) are the library's own, not in its
// public headers.
#include "../lib/diagnose/src/problem.hpp"

namespace {

namespace c = epuck2::calibrate;
namespace fit = epuck2::fit;
namespace fx = epuck2::models::effects;

// ----- the voltage->charge map ------------------------------------------------------------------

// f through (3.0 V, 0), (3.5 V, 0.4), (4.0 V, 1.0); load offsets 0, 0.02, 0.10 V at 0, 5, 15 cm/s.
c::ChargeMap hand_map_unlisted() {
  c::ChargeMap m;
  m.knots_v = {3.0, 3.5, 4.0};
  m.knot_charge = {0.0, 0.4, 1.0};
  m.load_speeds_cm_s = {0.0, 5.0, 15.0};
  m.load_offset_v = {0.0, 0.02, 0.10};
  m.voltage_min_v = 3.0;
  m.voltage_max_v = 4.0;
  return m;
}

TEST(ChargeMapByHand, LoadOffsetIsLinearBetweenSpeedsFromTheLowerOne) {
  const c::ChargeMap m = hand_map_unlisted();
  // 7 cm/s: 0.02 + (0.10 - 0.02) * (7 - 5) / (15 - 5) = 0.036; 10 cm/s: 0.06; 14: 0.092.
  EXPECT_NEAR(c::load_offset_v(m, 7.0), 0.036, 1e-12);
  EXPECT_NEAR(c::load_offset_v(m, 10.0), 0.06, 1e-12);
  EXPECT_NEAR(c::load_offset_v(m, -14.0), 0.092, 1e-12);  // a speed's sign does not matter
  // Exactly at the speeds (the knots of the load term).
  EXPECT_NEAR(c::load_offset_v(m, 0.0), 0.0, 1e-15);
  EXPECT_NEAR(c::load_offset_v(m, 5.0), 0.02, 1e-15);
  EXPECT_NEAR(c::load_offset_v(m, 15.0), 0.10, 1e-15);
}

TEST(ChargeMapByHand, ConversionAddsTheLoadOffsetToTheVoltage) {
  const c::ChargeMap m = hand_map_unlisted();
  // 3.64 V at 10 cm/s: corrected 3.70 V, on the second segment: 0.4 + 0.6 * 0.2 / 0.5 = 0.64.
  c::ChargeConversion r = c::convert_voltage(m, 3.64, 10.0);
  EXPECT_NEAR(r.charge, 0.64, 1e-12);
  EXPECT_EQ(r.side, 0);
  // 3.30 V at 15 cm/s: corrected 3.40 V, first segment: 0.4 * 0.4 / 0.5 = 0.32.
  r = c::convert_voltage(m, 3.30, 15.0);
  EXPECT_NEAR(r.charge, 0.32, 1e-12);
  // Exactly at the middle knot (3.48 V + 0.02 V at 5 cm/s).
  r = c::convert_voltage(m, 3.48, 5.0);
  EXPECT_NEAR(r.charge, 0.4, 1e-12);
  EXPECT_EQ(r.side, 0);
}

TEST(ChargeMapByHand, OutsideTheRangeClampsAndSaysOnWhichSide) {
  const c::ChargeMap m = hand_map_unlisted();
  c::ChargeConversion below = c::convert_voltage(m, 2.9, 0.0);
  EXPECT_EQ(below.side, -1);
  EXPECT_NEAR(below.charge, 0.0, 1e-15);
  c::ChargeConversion above = c::convert_voltage(m, 3.95, 15.0);  // corrected 4.05 V
  EXPECT_EQ(above.side, 1);
  EXPECT_NEAR(above.charge, 1.0, 1e-15);
  // Exactly at the range's ends: inside.
  EXPECT_EQ(c::convert_voltage(m, 3.0, 0.0).side, 0);
  EXPECT_EQ(c::convert_voltage(m, 4.0, 0.0).side, 0);
  EXPECT_NEAR(c::convert_voltage(m, 4.0, 0.0).charge, 1.0, 1e-15);
}

// The fitted map's residual sd is sqrt(RSS / (n - p)) (charge_map.hpp, docs): RSS recomputed
// here from the map's own conversion of each row, p = the map's parameter count.
TEST(ChargeMapByHand, ResidualSdCountsTheParameters) {
  std::vector<c::ChargeSample> rows;
  const int n = 40;
  for (int i = 0; i < n; ++i) {
    const double v = 3.0 + 1.0 * i / (n - 1);
    rows.push_back({v, 4.0, 0.8 * (v - 3.0) + (i % 2 ? 0.01 : -0.01)});  // one speed: no load term
  }
  const c::ChargeMapFit f = c::fit_charge_map(rows, {"by-hand"});
  ASSERT_TRUE(f.usable) << f.message;
  EXPECT_FALSE(f.map.has_load());
  double rss = 0, max_abs = 0;
  for (const auto& r : rows) {
    const c::ChargeConversion q = c::convert_voltage(f.map, r.voltage_v, r.speed_cm_s);
    EXPECT_EQ(q.side, 0);
    rss += (r.charge - q.charge) * (r.charge - q.charge);
    max_abs = std::max(max_abs, std::abs(r.charge - q.charge));
  }
  const double p = static_cast<double>(f.map.parameters());
  ASSERT_GE(p, 2.0);
  EXPECT_NEAR(f.map.residual_sd, std::sqrt(rss / (n - p)), 1e-9);
  EXPECT_NEAR(f.map.max_abs_residual, max_abs, 1e-9);
  // The alternating +-0.01 is what is left: the sd near 0.01 * sqrt(n / (n - p)).
  EXPECT_NEAR(f.map.residual_sd, 0.01 * std::sqrt(n / (n - p)), 2e-3);
}

// ----- the cluster-robust standard errors --------------------------------------------------------

// Two parameters with orthogonal columns (J col 0 = 1, col 1 = +1, -1 within each run of two
// rows), so J^T J = diag(10, 10). The runs' scores s = J^T r: run 0 r = (1, 1): (2, 0);
// run 1 (-1, -1): (-2, 0); run 2 (2, 0): (2, 2); run 3 (-1, -1): (-2, 0); run 4 (0, 0): (0, 0).
// sum s s^T = [[16, 4], [4, 4]]; V = (1/10)^2 [[16, 4], [4, 4]] * 5/4: V00 = 0.2, V11 = 0.05.
struct Runs {
  Eigen::MatrixXd J;
  std::vector<double> r;
  std::vector<int> run;
};
Runs five_runs() {
  Runs x;
  const std::vector<double> r{1, 1, -1, -1, 2, 0, -1, -1, 0, 0};
  x.J.resize(10, 2);
  for (int i = 0; i < 10; ++i) {
    x.J(i, 0) = 1.0;
    x.J(i, 1) = i % 2 ? -1.0 : 1.0;
    x.run.push_back(i / 2);
  }
  x.r = r;
  return x;
}

fit::FitResult two_parameters(double se0, double se1) {
  fit::FitResult f;
  f.usable = true;
  f.parameters = {fit::ParameterEstimate("a", 0.0, se0), fit::ParameterEstimate("b", 0.0, se1)};
  return f;
}

TEST(ClusterRobustByHand, FiveRunsExactlyAtTheLimitGiveTheSandwichWithGOverGMinusOne) {
  ASSERT_EQ(fit::kMinClusters, 5u);  // the case below is exactly at the limit
  const Runs x = five_runs();
  fit::AutocorrelationCorrection a;
  fit::apply_cluster_robust(a, two_parameters(0.01, 0.01), x.J, x.r, x.run);
  ASSERT_TRUE(a.cluster_robust) << a.cluster_why_not;
  EXPECT_EQ(a.series, 5u);
  EXPECT_NEAR(a.std_error("a"), std::sqrt(0.2), 1e-12);
  EXPECT_NEAR(a.std_error("b"), std::sqrt(0.05), 1e-12);
}

TEST(ClusterRobustByHand, NeverBelowTheCovariancesError) {
  const Runs x = five_runs();
  fit::AutocorrelationCorrection a;
  // a's covariance error 1.0 is above its cluster-robust 0.447: kept; b's 0.1 below 0.224: replaced.
  fit::apply_cluster_robust(a, two_parameters(1.0, 0.1), x.J, x.r, x.run);
  ASSERT_TRUE(a.cluster_robust);
  EXPECT_NEAR(a.std_error("a"), 1.0, 1e-15);
  EXPECT_NEAR(a.std_error("b"), std::sqrt(0.05), 1e-12);
}

TEST(ClusterRobustByHand, FourRunsFallBackToTheAr1Factor) {
  Runs x = five_runs();
  for (int& g : x.run) g = std::min(g, 3);  // runs 3 and 4 merged: 4 runs
  fit::AutocorrelationCorrection a;  // not computed: the AR(1) factor is 1
  fit::apply_cluster_robust(a, two_parameters(0.3, 0.02), x.J, x.r, x.run);
  EXPECT_FALSE(a.cluster_robust);
  EXPECT_FALSE(a.cluster_why_not.empty());
  EXPECT_NEAR(a.std_error("a"), 0.3, 1e-15);
  EXPECT_NEAR(a.std_error("b"), 0.02, 1e-15);
}

// ----- the robots' Cochran Q test ---------------------------------------------------------------

fit::FitResult robot(double x, double se) {
  fit::FitResult f;
  f.usable = true;
  f.parameters = {fit::ParameterEstimate("gain", x, se)};
  return f;
}

TEST(RobotSpreadByHand, QAboutTheInverseVarianceMean) {
  // x = 1, 2, 4 with se 0.5, 1, 1: weights 4, 1, 1, x_w = 10 / 6 = 5/3;
  // Q = 4 (2/3)^2 + (1/3)^2 + (7/3)^2 = 66/9 = 22/3; chi^2(2) tail exp(-Q/2) = exp(-11/3).
  // The robots' sample sd: mean 7/3, ss = (16 + 1 + 25)/9, sd = sqrt(42/9/2) = sqrt(7/3).
  const fit::FitResult r1 = robot(1, 0.5), r2 = robot(2, 1), r3 = robot(4, 1);
  const auto s = fit::robot_spread({&r1, &r2, &r3});
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].parameter, "gain");
  EXPECT_NEAR(s[0].q, 22.0 / 3.0, 1e-12);
  EXPECT_EQ(s[0].dof, 2u);
  EXPECT_NEAR(s[0].p_value, std::exp(-11.0 / 3.0), 1e-9);
  EXPECT_NEAR(s[0].spread_sd, std::sqrt(7.0 / 3.0), 1e-12);
  EXPECT_FALSE(s[0].exceeds);  // p = 0.0256 > 0.01
}

TEST(RobotSpreadByHand, PValueEitherSideOfTheCut) {
  // x = 0, 0, d with se 1: x_w = d/3, Q = 2 (d/3)^2 + (2d/3)^2 = 2 d^2 / 3; with 2 degrees of
  // freedom p = exp(-Q/2), so p = 0.01 at Q = 2 ln 100 = 9.2103. Q = 9.0 and 9.5 either side.
  ASSERT_DOUBLE_EQ(fit::kRobotSpreadP, 0.01);
  for (const double q : {9.0, 9.5}) {
    const double d = std::sqrt(1.5 * q);
    const fit::FitResult r1 = robot(0, 1), r2 = robot(0, 1), r3 = robot(d, 1);
    const auto s = fit::robot_spread({&r1, &r2, &r3});
    ASSERT_EQ(s.size(), 1u);
    EXPECT_NEAR(s[0].q, q, 1e-9);
    EXPECT_NEAR(s[0].p_value, std::exp(-q / 2), 1e-9);
    EXPECT_EQ(s[0].exceeds, q > 2 * std::log(100.0)) << "Q = " << q;
  }
}

TEST(RobotSpreadByHand, TwoRobotsHaveOneDegreeOfFreedom) {
  // x = 0 and 3 with se 1 and 2: weights 1, 1/4, x_w = 0.75 / 1.25 = 0.6;
  // Q = 0.36 + (2.4)^2 / 4 = 0.36 + 1.44 = 1.8; chi^2(1) tail = erfc(sqrt(Q/2)).
  const fit::FitResult r1 = robot(0, 1), r2 = robot(3, 2);
  const auto s = fit::robot_spread({&r1, &r2});
  ASSERT_EQ(s.size(), 1u);
  EXPECT_NEAR(s[0].q, 1.8, 1e-12);
  EXPECT_EQ(s[0].dof, 1u);
  EXPECT_NEAR(s[0].p_value, std::erfc(std::sqrt(0.9)), 1e-9);
}


// ----- the Tobit terms ---------------------------------------------------------------------------

// A constant model f = a; five readings inside the rails, two on an upper rail at 1.5, one on a
// lower rail at 0. The likelihood of docs/fitting.md, written here afresh with erfc:
//   inside: -log sigma - log sqrt(2 pi) - (y - a)^2 / 2 sigma^2
//   upper rail U: log Phi((a - U) / sigma); lower rail L: log Phi((L - a) / sigma)
// and maximised here by bisection (a) and golden section (sigma), not by the code under test.
namespace tobit {

const std::vector<double> kInside{0.2, 1.0, 1.4, 0.6, 0.9};
constexpr double kUpper = 1.5, kLower = 0.0;
constexpr int kOnUpper = 2, kOnLower = 1;

double Phi_unlisted(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }
double phi(double z) { return std::exp(-0.5 * z * z) / std::sqrt(2 * M_PI); }

double loglik(double a, double s) {
  double l = 0;
  for (double y : kInside) l += -std::log(s) - 0.5 * std::log(2 * M_PI) - (y - a) * (y - a) / (2 * s * s);
  l += kOnUpper * std::log(Phi_unlisted((a - kUpper) / s)) + kOnLower * std::log(Phi_unlisted((kLower - a) / s));
  return l;
}

// d loglik / d a, decreasing in a.
double score_a(double a, double s) {
  double g = 0;
  for (double y : kInside) g += (y - a) / (s * s);
  const double zu = (a - kUpper) / s, zl = (kLower - a) / s;
  return g + kOnUpper * phi(zu) / Phi_unlisted(zu) / s - kOnLower * phi(zl) / Phi_unlisted(zl) / s;
}

double a_of(double s) {
  double lo = -10, hi = 10;
  for (int i = 0; i < 200; ++i) (score_a(0.5 * (lo + hi), s) > 0 ? lo : hi) = 0.5 * (lo + hi);
  return 0.5 * (lo + hi);
}

double sigma_ml() {
  double lo = 0.05, hi = 5;
  const double g = (std::sqrt(5.0) - 1) / 2;
  for (int i = 0; i < 200; ++i) {
    const double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
    (loglik(a_of(x1), x1) < loglik(a_of(x2), x2) ? lo : hi) = (loglik(a_of(x1), x1) < loglik(a_of(x2), x2) ? x1 : x2);
  }
  return 0.5 * (lo + hi);
}

struct UnlistedConstant {
  std::size_t n;
  template <typename T>
  bool operator()(const T* p, T* out) const {
    for (std::size_t i = 0; i < n; ++i) out[i] = p[0];
    return true;
  }
};

fit::RobustFit fit_it(double noise_sd) {
  std::vector<fit::Observation> obs;
  for (double y : kInside) obs.push_back({y, fit::Censoring::none, "inside", -1});
  for (int i = 0; i < kOnUpper; ++i) obs.push_back({kUpper, fit::Censoring::at_or_above, "upper", -1});
  for (int i = 0; i < kOnLower; ++i) obs.push_back({kLower, fit::Censoring::at_or_below, "lower", -1});
  fit::RobustOptions o;
  o.robust = false;
  o.noise_sd = noise_sd;
  return fit::fit_robust(UnlistedConstant{obs.size()}, obs, {fit::free_parameter("a", 0.5)}, o);
}

}  // namespace tobit

TEST(TobitByHand, GivenNoiseTheEstimateLikelihoodAndErrorAreTobits) {
  const double s = 0.5;
  const fit::RobustFit f = tobit::fit_it(s);
  ASSERT_TRUE(f.usable) << f.message;
  const double a = tobit::a_of(s);
  // The two upper-rail readings pull a above the inside readings' mean 0.82, the lower one less.
  ASSERT_GT(a, 0.82);
  EXPECT_NEAR(f.value("a"), a, 1e-7);
  EXPECT_NEAR(f.log_likelihood, tobit::loglik(a, s), 1e-8);
  EXPECT_EQ(f.kept_censored_above, 2u);
  EXPECT_EQ(f.kept_censored_below, 1u);
  // Gauss-Newton covariance of the residuals r = (y - a)/sigma and r = sqrt(-2 log Phi(z)):
  // d r / d a = -1/sigma inside, -lambda(z) / r * (dz/da) on a rail, lambda = phi/Phi.
  double info = 5 / (s * s);
  for (const auto& [z, count] : {std::pair{(a - tobit::kUpper) / s, 2}, std::pair{(tobit::kLower - a) / s, 1}}) {
    const double r = std::sqrt(-2 * std::log(tobit::Phi_unlisted(z)));
    const double d = tobit::phi(z) / tobit::Phi_unlisted(z) / r / s;
    info += count * d * d;
  }
  EXPECT_NEAR(f.std_error("a"), 1 / std::sqrt(info), 1e-7);
}

TEST(TobitByHand, EstimatedNoiseIsTheMaximumLikelihoodOne) {
  const fit::RobustFit f = tobit::fit_it(std::numeric_limits<double>::quiet_NaN());
  ASSERT_TRUE(f.usable) << f.message;
  const double s = tobit::sigma_ml(), a = tobit::a_of(s);
  EXPECT_NEAR(f.value("a"), a, 1e-6);
  // noise_sd carries the degrees of freedom the one parameter takes from the 5 inside readings.
  EXPECT_NEAR(f.noise_sd, s * std::sqrt(5.0 / 4.0), 1e-6);
  EXPECT_NEAR(f.log_likelihood, tobit::loglik(a, s), 1e-8);
}

// ----- codegen ------------------------------------------------------------------------------------

// Every parameter of every catalogue effect (iterated over the registry, lib/models effects.hpp)
// set to a value inside its range, not neutral, different per effect, parameter and sensor; the
// generated C++ is read back here line by line ("  m.MEMBER = value;" or "= {v0, v1, ...};") and
// must give back exactly the values set (codegen writes numbers that round-trip).
namespace codegen {

// The number list of the line "  m.<member> = ...;" (one number, or a braced list).
std::vector<double> numbers_of(const std::string& cpp, const std::string& member) {
  const std::string head = "\n  m." + member + " = ";
  const std::size_t at = cpp.find(head);
  EXPECT_NE(at, std::string::npos) << "no line for " << member << " in\n" << cpp;
  if (at == std::string::npos) return {};
  EXPECT_EQ(cpp.find(head, at + 1), std::string::npos) << member << " written twice";
  const std::size_t end = cpp.find(";\n", at);
  std::string text = cpp.substr(at + head.size(), end - at - head.size());
  for (char& ch : text)
    if (ch == '{' || ch == '}' || ch == ',') ch = ' ';
  std::istringstream is(text);
  std::vector<double> out;
  for (std::string w; is >> w;) out.push_back(std::strtod(w.c_str(), nullptr));
  return out;
}

template <class Model>
void every_effect_round_trips(Model m) {
  const fx::Catalogue& cat = fx::catalogue_of(m);
  std::map<std::string, std::vector<double>> set;  // member -> values, in element order
  fx::for_each_param(fx::effects_of(m), [&](std::size_t id, int p, int k, double& v) {
    const fx::Param& P = cat[id].params[static_cast<std::size_t>(p)];
    double frac = 0.21 + 0.061 * k + 0.017 * p + 0.007 * static_cast<double>(id);
    v = P.lower + frac * (P.upper - P.lower);
    if (v == P.neutral) v = P.lower + (frac + 0.013) * (P.upper - P.lower);
    ASSERT_TRUE(fx::Effect::admissible(P, v));
    if (cat[id].home != fx::Home::base) set[P.member].push_back(v);
  });
  ASSERT_FALSE(set.empty());
  const std::string cpp = epuck2::coefficients::model_to_cpp(m, "a test");
  for (const auto& [member, values] : set) {
    const std::vector<double> got = numbers_of(cpp, member);
    ASSERT_EQ(got.size(), values.size()) << member;
    for (std::size_t i = 0; i < values.size(); ++i) EXPECT_EQ(got[i], values[i]) << member << "[" << i << "]";
  }
}

}  // namespace codegen

TEST(CodegenByHand, EveryCatalogueEffectOfEveryKindWithNonNeutralValues) {
  namespace s = epuck2::models::sensors;
  codegen::every_effect_round_trips(s::ProximityModel{});
  codegen::every_effect_round_trips(s::LightModel{});
  codegen::every_effect_round_trips(s::GroundModel{});
  codegen::every_effect_round_trips(s::CameraModel{});
  codegen::every_effect_round_trips(s::DriveModel{});
  codegen::every_effect_round_trips(s::BatteryModel{});
}

TEST(CodegenByHand, GroundSensorsAndCovariatesKeepTheirOrder) {
  namespace s = epuck2::models::sensors;
  s::GroundModel m;
  for (std::size_t k = 0; k < m.sensors.size(); ++k) m.sensors[k] = {1.25 + 0.5 * k, 40.0 + 7.0 * k};  // gain, black offset
  m.covariates = {{"speed_cm_s", 0.375, 7.5}, {"time_s", -2.25, 300.0}};
  const std::string cpp = epuck2::coefficients::model_to_cpp(m, "a test");
  for (std::size_t k = 0; k < m.sensors.size(); ++k) {
    const std::vector<double> v = codegen::numbers_of(cpp, "sensors[" + std::to_string(k) + "]");
    ASSERT_EQ(v.size(), 2u);
    EXPECT_EQ(v[0], 1.25 + 0.5 * k) << "gain of sensor " << k;
    EXPECT_EQ(v[1], 40.0 + 7.0 * k) << "offset of sensor " << k;
  }
  // {"speed_cm_s", slope, centre}, ...: the numbers in the order written.
  const std::size_t at = cpp.find("  m.covariates = {");
  ASSERT_NE(at, std::string::npos);
  const std::string line = cpp.substr(at, cpp.find('\n', at) - at);
  EXPECT_NE(line.find("{\"speed_cm_s\", 0.375, 7.5}"), std::string::npos) << line;
  EXPECT_NE(line.find("{\"time_s\", -2.25, 300}"), std::string::npos) << line;
  EXPECT_LT(line.find("speed_cm_s"), line.find("time_s"));
}


// ----- the naming step of findings (identify) ------------------------------------------------------

// The ground's rule: sensor gains equal within their errors are one white level. Three sensors,
// gains 1.0, 1.2, 1.1 (differences from the first d = (0.2, 0.1)); every gain's variance v,
// every two gains' covariance c (correlated through the offsets). The differences' covariance is
// V = (v - c) [[2, 1], [1, 2]], so the Wald statistic d^T V^-1 d = (2 0.04 + 2 0.01 - 2 0.02) /
// (3 (v - c)) = 0.02 / (v - c) on 2 degrees of freedom, p = exp(-W/2); equal when p >= 0.01,
// that is W <= 2 ln 100 = 9.2103. v - c = 0.0023: W = 8.70, p = 0.0129, one white level
// offset + (level - offset) * 1.1 (the gains' mean); v - c = 0.0020: W = 10, p = 0.0067, not.
namespace identify {

namespace d = epuck2::diagnose::detail;

std::unique_ptr<d::Problem> ground_problem() {
  std::string csv = "grey,sensor,value\n";
  for (double grey : {0.0, 0.25, 0.5, 0.75, 1.0})
    for (int k = 0; k < 3; ++k) csv += std::to_string(grey) + "," + std::to_string(k) + "," + std::to_string(40 + 900 * grey) + "\n";
  std::vector<epuck2::logs::Log> logs{epuck2::logs::parse_log(csv, "ground.csv", epuck2::logs::Kind::ground)};
  std::string why;
  auto p = d::make_problem(logs, epuck2::diagnose::Options{}, why);
  EXPECT_NE(p, nullptr) << why;
  return p;
}

const d::Effect* effect_unlisted(const d::Problem& p, std::size_t id) {
  for (const d::Effect& e : p.effects)
    if (e.cause == fx::ground_catalogue()[id].name) return &e;
  return nullptr;
}

struct UnlistedCase {
  std::vector<double> values;
  Eigen::MatrixXd covariance;
  int level = -1, offset = -1;
  std::vector<int> gains;
};

// Gains and their covariance as above; every other parameter at the plug-in's value, no error.
UnlistedCase ground_case(const d::Problem& p, double v, double c) {
  UnlistedCase x;
  x.values = p.plugin_values;
  const d::Effect* g = effect_unlisted(p, fx::ground::sensor_gain);
  const d::Effect* l = effect_unlisted(p, fx::ground::white_level);
  const d::Effect* o = effect_unlisted(p, fx::ground::black_offset);
  EXPECT_TRUE(g != nullptr && l != nullptr && o != nullptr);
  if (g == nullptr || l == nullptr || o == nullptr) return x;
  x.gains = g->params;
  EXPECT_EQ(x.gains.size(), 3u);
  x.level = l->params.at(0);
  x.offset = o->params.at(0);
  const auto P = static_cast<Eigen::Index>(p.params.size());
  x.covariance = Eigen::MatrixXd::Zero(P, P);
  const std::vector<double> gain{1.0, 1.2, 1.1};
  for (std::size_t a = 0; a < x.gains.size(); ++a) {
    x.values[static_cast<std::size_t>(x.gains[a])] = gain[a];
    for (std::size_t b = 0; b < x.gains.size(); ++b) x.covariance(x.gains[a], x.gains[b]) = a == b ? v : c;
  }
  return x;
}

}  // namespace identify

TEST(IdentifyByHand, GroundGainsEqualWithinTheirCorrelatedErrorsAreOneWhiteLevel) {
  const auto p = identify::ground_problem();
  ASSERT_NE(p, nullptr);
  const std::string gain_cause = fx::ground_catalogue()[fx::ground::sensor_gain].name;
  // v - c = 0.0023 (p = 0.0129): named a white level at the gains' mean.
  identify::UnlistedCase x = identify::ground_case(*p, 0.0060, 0.0037);
  ASSERT_EQ(x.gains.size(), 3u);
  const double offset = x.values[static_cast<std::size_t>(x.offset)];
  const double level = x.values[static_cast<std::size_t>(x.level)];
  ASSERT_EQ(level, p->params[static_cast<std::size_t>(x.level)].fallback);  // no white level in the model yet
  const auto named = p->identify(gain_cause, x.values, x.covariance);
  ASSERT_TRUE(named.has_value());
  EXPECT_EQ(named->cause, fx::ground_catalogue()[fx::ground::white_level].name);
  ASSERT_EQ(named->starts.size(), 1u);
  EXPECT_EQ(named->starts[0].first, x.level);
  EXPECT_NEAR(named->starts[0].second, offset + (level - offset) * 1.1, 1e-9);
  // v - c = 0.0020 (W = 10, p = 0.0067): the sensors differ; the finding keeps its name.
  x = identify::ground_case(*p, 0.0060, 0.0040);
  EXPECT_FALSE(p->identify(gain_cause, x.values, x.covariance).has_value());
  // The same variances without the correlation (c = 0: W = 0.02 / 0.006 = 3.33, p = 0.19): equal.
  x = identify::ground_case(*p, 0.0060, 0.0);
  EXPECT_TRUE(p->identify(gain_cause, x.values, x.covariance).has_value());
}

}  // namespace
