// The NIST StRD nonlinear regression problems: the certified reference for the fitting engine.
//
// Source of every model below: the "Model:" block of the problem's own .dat file (NIST
// Information Technology Laboratory, Statistical Reference Datasets, nonlinear regression;
// public domain; copies in tests/data/nist/). The constants inside the formulas (pi, 12 months in
// ENSO, the 0.5 and 2 of Eckerle4 and the Misra problems) are part of those published formulas.
//
// A problem is read from its .dat file (certified values and standard deviations, certified
// residual sum of squares, both starting points, the data) and identified by the file's name.
// `run` fits it from start 1 or 2 with the project's fitting layer (fit_curve / summarize) and
// reports the log relative error (LRE) of every estimate against the certified value, as
// McCullough (1998) and Ceres' examples/nist.cc do.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "epuck2/fit/least_squares.hpp"

namespace epuck2::nist {

using fit::FitOptions;
using fit::FitResult;


/// Significant digits of every certified value in the StRD files (e.g. 2.3894212918E+02): the
/// cap on a log relative error.
constexpr double kCertifiedDigits = 11.0;

/// pi, for the models that use it (Roszman1, ENSO).
constexpr double kPi = 3.14159265358979323846;

struct CertifiedParameter {
  std::string name;  ///< b1, b2, ...
  double start1 = 0;
  double start2 = 0;
  double certified = 0;
  double certified_sd = 0;  ///< certified standard deviation (standard error)
};

struct Problem {
  std::string name;  ///< file stem, e.g. "Misra1a": identifies the model
  std::string path;
  std::vector<CertifiedParameter> parameters;
  double certified_rss = 0;
  std::size_t certified_observations = 0;
  std::vector<double> y;
  std::vector<long double> y_extended;  ///< y read in long double: the decimal data to 19 digits
  std::vector<std::vector<double>> x;  ///< x[k][i]: predictor k (x, or x1 and x2 for Nelson) at row i
  std::vector<std::vector<long double>> x_extended;  ///< x read in long double
};

/// Parses the text of a StRD .dat file; `path` names it in errors and gives the model (its stem).
/// Throws logs::InputError (file:line:column) on malformed content or an unknown problem name.
Problem parse(const std::string& text, const std::string& path);
/// Reads and parses a .dat file (InputError when it cannot be read).
Problem read(const std::string& path);

/// Names of the 27 models implemented (the StRD problems, by file stem).
const std::vector<std::string>& problem_names();
bool has_model(const std::string& name);

/// LRE = -log10(|computed - certified| / |certified|), capped at `digits` (an exact match gives
/// `digits`), floored at 0; with a certified value of 0 the absolute error is used. NaN or
/// infinite `computed` gives 0.
double log_relative_error(double computed, double certified, double digits = kCertifiedDigits);

struct Target {
  double parameter_lre = 6.0;
  double std_error_lre = 4.0;
};

struct ParameterReport {
  std::string name;
  double value = 0, std_error = 0, certified = 0, certified_sd = 0;
  double lre = 0, std_error_lre = 0;
};

struct RunReport {
  std::string problem;
  int start = 1;
  bool usable = false;
  std::string message;
  std::vector<ParameterReport> parameters;
  double rss = 0, certified_rss = 0, rss_lre = 0;
  double min_lre = 0, min_std_error_lre = 0;
  int iterations = 0;
  double seconds = 0;  ///< wall time of the fit (not the parsing)
  bool at_target = false;
};

/// Options the NIST runs use by default: the fitting layer's multi-strategy search (restarts from
/// the solution; where that solution fails its own checks, alternative trust-region strategies
/// and linear solvers, the lowest cost wins) and tight tolerances. They never see the certified
/// values.
FitOptions default_options();

/// Fits `problem` from start 1 or 2 and compares with the certified values.
RunReport run(const Problem& problem, int start, const FitOptions& options = default_options(),
              const Target& target = {});

/// The fit alone (no comparison): what a benchmark times.
FitResult fit(const Problem& problem, int start, const FitOptions& options = default_options());

// ---------------------------------------------------------------------------------------------
// The models, y = f(b, x), templated on the scalar (double, float, fit::Jet). b[0] is b1.
// x is a double for the fit; the extended-precision polish passes a long double x (with
// T = long double) so that decimal data like 0.05 keep 19 digits.
namespace models {

/// Misra1a, BoxBOD: y = b1*(1-exp[-b2*x])
struct Misra1a {
  static constexpr int kParameters = 2;
  template <typename T, typename X = double>
  T operator()(const T* b, X x) const {
    using std::exp;
    return b[0] * (T(1.0) - exp(-b[1] * x));
  }
};
struct BoxBOD : Misra1a {};

/// Chwirut1, Chwirut2: y = exp[-b1*x]/(b2+b3*x)
struct Chwirut {
  static constexpr int kParameters = 3;
  template <typename T, typename X = double>
  T operator()(const T* b, X x) const {
    using std::exp;
    return exp(-b[0] * x) / (b[1] + b[2] * x);
  }
};

/// Lanczos1, 2, 3: y = b1*exp(-b2*x) + b3*exp(-b4*x) + b5*exp(-b6*x)
struct Lanczos {
  static constexpr int kParameters = 6;
  template <typename T, typename X = double>
  T operator()(const T* b, X x) const {
    using std::exp;
    return b[0] * exp(-b[1] * x) + b[2] * exp(-b[3] * x) + b[4] * exp(-b[5] * x);
  }
};

/// Gauss1, 2, 3: y = b1*exp(-b2*x) + b3*exp(-(x-b4)**2/b5**2) + b6*exp(-(x-b7)**2/b8**2)
struct Gauss {
  static constexpr int kParameters = 8;
  template <typename T, typename X = double>
  T operator()(const T* b, X x) const {
    using std::exp;
    const T d1 = x - b[3];
    const T d2 = x - b[6];
    return b[0] * exp(-b[1] * x) + b[2] * exp(-d1 * d1 / (b[4] * b[4])) + b[5] * exp(-d2 * d2 / (b[7] * b[7]));
  }
};

/// DanWood: y = b1*x**b2
struct DanWood {
  static constexpr int kParameters = 2;
  template <typename T, typename X = double>
  T operator()(const T* b, X x) const {
    using std::pow;
    return b[0] * pow(x, b[1]);
  }
};

/// Misra1b: y = b1 * (1-(1+b2*x/2)**(-2))
struct Misra1b {
  static constexpr int kParameters = 2;
  template <typename T, typename X = double>
  T operator()(const T* b, X x) const {
    const T u = T(1.0) + b[1] * x / 2.0;
    return b[0] * (T(1.0) - T(1.0) / (u * u));
  }
};

/// Kirby2: y = (b1 + b2*x + b3*x**2) / (1 + b4*x + b5*x**2)
struct Kirby2 {
  static constexpr int kParameters = 5;
  template <typename T, typename X = double>
  T operator()(const T* b, X x) const {
    return (b[0] + b[1] * x + b[2] * x * x) / (T(1.0) + b[3] * x + b[4] * x * x);
  }
};

/// Hahn1, Thurber: y = (b1 + b2*x + b3*x**2 + b4*x**3) / (1 + b5*x + b6*x**2 + b7*x**3)
struct Rational33 {
  static constexpr int kParameters = 7;
  template <typename T, typename X = double>
  T operator()(const T* b, X x) const {
    const X x2 = x * x, x3 = x2 * x;
    return (b[0] + b[1] * x + b[2] * x2 + b[3] * x3) / (T(1.0) + b[4] * x + b[5] * x2 + b[6] * x3);
  }
};

/// Nelson: log[y] = b1 - b2*x1 * exp[-b3*x2] (two predictors; the response is log y)
struct Nelson {
  static constexpr int kParameters = 3;
  template <typename T>
  T operator()(const T* b, double x1, double x2) const {
    using std::exp;
    return b[0] - b[1] * x1 * exp(-b[2] * x2);
  }
};

/// MGH17: y = b1 + b2*exp[-x*b4] + b3*exp[-x*b5]
struct MGH17 {
  static constexpr int kParameters = 5;
  template <typename T, typename X = double>
  T operator()(const T* b, X x) const {
    using std::exp;
    return b[0] + b[1] * exp(-x * b[3]) + b[2] * exp(-x * b[4]);
  }
};

/// Misra1c: y = b1 * (1-(1+2*b2*x)**(-.5))
struct Misra1c {
  static constexpr int kParameters = 2;
  template <typename T, typename X = double>
  T operator()(const T* b, X x) const {
    using std::sqrt;
    return b[0] * (T(1.0) - T(1.0) / sqrt(T(1.0) + 2.0 * b[1] * x));
  }
};

/// Misra1d: y = b1*b2*x*((1+b2*x)**(-1))
struct Misra1d {
  static constexpr int kParameters = 2;
  template <typename T, typename X = double>
  T operator()(const T* b, X x) const {
    return b[0] * b[1] * x / (T(1.0) + b[1] * x);
  }
};

/// Roszman1: y = b1 - b2*x - arctan[b3/(x-b4)]/pi (plain arctan, as in the NIST file)
struct Roszman1 {
  static constexpr int kParameters = 4;
  template <typename T, typename X = double>
  T operator()(const T* b, X x) const {
    using std::atan;
    return b[0] - b[1] * x - atan(b[2] / (x - b[3])) / kPi;
  }
};

/// ENSO: y = b1 + b2*cos(2*pi*x/12) + b3*sin(2*pi*x/12) + b5*cos(2*pi*x/b4) + b6*sin(2*pi*x/b4)
///           + b8*cos(2*pi*x/b7) + b9*sin(2*pi*x/b7)   (12: the annual cycle, in months)
struct ENSO {
  static constexpr int kParameters = 9;
  template <typename T, typename X = double>
  T operator()(const T* b, X x) const {
    using std::cos;
    using std::sin;
    const X annual = 2.0 * kPi * x / 12.0;
    const T w4 = 2.0 * kPi * x / b[3];
    const T w7 = 2.0 * kPi * x / b[6];
    return b[0] + b[1] * cos(annual) + b[2] * sin(annual) + b[4] * cos(w4) + b[5] * sin(w4) +
           b[7] * cos(w7) + b[8] * sin(w7);
  }
};

/// MGH09: y = b1*(x**2+x*b2) / (x**2+x*b3+b4)
struct MGH09 {
  static constexpr int kParameters = 4;
  template <typename T, typename X = double>
  T operator()(const T* b, X x) const {
    return b[0] * (x * x + x * b[1]) / (x * x + x * b[2] + b[3]);
  }
};

/// Rat42: y = b1 / (1+exp[b2-b3*x])
struct Rat42 {
  static constexpr int kParameters = 3;
  template <typename T, typename X = double>
  T operator()(const T* b, X x) const {
    using std::exp;
    return b[0] / (T(1.0) + exp(b[1] - b[2] * x));
  }
};

/// MGH10: y = b1 * exp[b2/(x+b3)]
struct MGH10 {
  static constexpr int kParameters = 3;
  template <typename T, typename X = double>
  T operator()(const T* b, X x) const {
    using std::exp;
    return b[0] * exp(b[1] / (x + b[2]));
  }
};

/// Eckerle4: y = (b1/b2) * exp[-0.5*((x-b3)/b2)**2]
struct Eckerle4 {
  static constexpr int kParameters = 3;
  template <typename T, typename X = double>
  T operator()(const T* b, X x) const {
    using std::exp;
    const T z = (x - b[2]) / b[1];
    return b[0] / b[1] * exp(-0.5 * z * z);
  }
};

/// Rat43: y = b1 / ((1+exp[b2-b3*x])**(1/b4))
struct Rat43 {
  static constexpr int kParameters = 4;
  template <typename T, typename X = double>
  T operator()(const T* b, X x) const {
    using std::exp;
    using std::pow;
    return b[0] / pow(T(1.0) + exp(b[1] - b[2] * x), T(1.0) / b[3]);
  }
};

/// Bennett5: y = b1 * (b2+x)**(-1/b3)
struct Bennett5 {
  static constexpr int kParameters = 3;
  template <typename T, typename X = double>
  T operator()(const T* b, X x) const {
    using std::pow;
    return b[0] * pow(b[1] + x, T(-1.0) / b[2]);
  }
};

}  // namespace models
}  // namespace epuck2::nist
