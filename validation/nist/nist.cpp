#include "epuck2/nist/nist.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <type_traits>

#include "epuck2/fit/fit_curve.hpp"
#include "epuck2/fit/problem.hpp"
#include "epuck2/logs/log.hpp"

namespace epuck2::nist {

using namespace epuck2::fit;  // the engine (lib/fit)

namespace {

using logs::InputError;

struct Token {
  std::string text;
  int column = 0;  // 1-based
};

std::vector<Token> split(const std::string& line) {
  std::vector<Token> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    if (i >= line.size()) break;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    out.push_back({line.substr(start, i - start), static_cast<int>(start) + 1});
  }
  return out;
}

double number(const Token& t, const std::string& path, int line, const std::string& what) {
  const char* begin = t.text.c_str();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  if (end == begin || *end != '\0' || !std::isfinite(v))
    throw InputError(path, line, t.column, "expected a number for " + what + ", found '" + t.text + "'");
  return v;
}

bool starts_with(const std::string& s, const std::string& prefix) { return s.compare(0, prefix.size(), prefix) == 0; }

// Near an exact fit (Lanczos1: certified RSS 1.4e-25, residuals 1e-13 beside values near 1) a
// residual computed in double keeps two or three digits, the double solver stops where that
// rounding noise hides the last descent, and the standard errors, proportional to sqrt(RSS),
// inherit both. The polish: Gauss-Newton steps on residuals computed in long double (64-bit
// mantissa), the Jacobian by automatic differentiation in double, each step kept only when the
// long-double RSS falls; then the RSS of the final values, in long double, is the one reported.
// `residual(b, i)` is generic over the scalar (long double, fit::Jet).
constexpr int kPolishSteps = 4;

template <int N, class Residual>
void polish_in_extended_precision(FitResult& r, std::size_t n, Residual residual) {
  if (!r.usable || r.parameters.size() != static_cast<std::size_t>(N)) return;
  auto rss_at = [&](const Eigen::Matrix<double, N, 1>& p) {
    long double b[N];
    for (int j = 0; j < N; ++j) b[j] = static_cast<long double>(p(j));
    long double sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const long double e = residual(b, i);
      sum += e * e;
    }
    return sum;
  };
  Eigen::Matrix<double, N, 1> p;
  for (int j = 0; j < N; ++j) p(j) = r.parameters[static_cast<std::size_t>(j)].value;
  long double rss = rss_at(p);
  if (!std::isfinite(static_cast<double>(rss))) return;
  using Jet = fit::Jet<N>;
  for (int step = 0; step < kPolishSteps && rss > 0; ++step) {
    Eigen::MatrixXd J(static_cast<Eigen::Index>(n), N);
    Eigen::VectorXd e(static_cast<Eigen::Index>(n));
    long double b[N];
    Jet bj[N];
    for (int j = 0; j < N; ++j) {
      b[j] = static_cast<long double>(p(j));
      bj[j] = Jet(p(j), j);
    }
    for (std::size_t i = 0; i < n; ++i) {
      e(static_cast<Eigen::Index>(i)) = static_cast<double>(residual(b, i));
      const Jet ej = residual(bj, i);
      J.row(static_cast<Eigen::Index>(i)) = ej.v.transpose();
    }
    // Equilibrated columns, column-pivoted QR: min |e + J d|.
    Eigen::VectorXd scale(N);
    for (int j = 0; j < N; ++j) {
      const double norm = J.col(j).norm();
      scale(j) = norm > 0 ? 1.0 / norm : 1.0;
      J.col(j) *= scale(j);
    }
    const Eigen::VectorXd d = J.colPivHouseholderQr().solve(-e).cwiseProduct(scale);
    if (!d.allFinite()) break;
    const Eigen::Matrix<double, N, 1> candidate = p + d;
    const long double candidate_rss = rss_at(candidate);
    if (!(candidate_rss < rss)) break;
    p = candidate;
    rss = candidate_rss;
  }
  // Values, RSS, and the covariance recomputed at the polished values.
  Eigen::MatrixXd J(static_cast<Eigen::Index>(n), N);
  Jet bj[N];
  for (int j = 0; j < N; ++j) bj[j] = Jet(p(j), j);
  for (std::size_t i = 0; i < n; ++i) J.row(static_cast<Eigen::Index>(i)) = residual(bj, i).v.transpose();
  Eigen::MatrixXd inverse;
  if (!inverse_normal_matrix(J, &inverse)) return;
  for (int j = 0; j < N; ++j) r.parameters[static_cast<std::size_t>(j)].value = p(j);
  const double s2 = r.residual_variance;
  r.covariance = inverse * s2;
  for (int j = 0; j < N; ++j)
    r.parameters[static_cast<std::size_t>(j)].std_error = std::sqrt(std::max(0.0, r.covariance(j, j)));
  set_rss(r, static_cast<double>(rss));
}

// A model's fit from a starting point: y = f(b, x) with one predictor.
template <class Model>
FitResult fit_one(const Problem& p, const std::vector<double>& start, const std::vector<std::string>& names,
                  const FitOptions& options) {
  FitResult r = fit_curve(Model{}, p.x.at(0), p.y, free_parameters(names, start), options);
  const Model model{};
  polish_in_extended_precision<Model::kParameters>(r, p.y.size(), [&](const auto* b, std::size_t i) {
    using T = std::decay_t<decltype(*b)>;
    if constexpr (std::is_same_v<T, long double>)
      return p.y_extended[i] - model(b, p.x_extended[0][i]);
    else
      return T(p.y[i]) - model(b, p.x[0][i]);
  });
  return r;
}

// Nelson: log y = f(b, x1, x2), residual (log y - f) for each row.
class NelsonResidual {
 public:
  NelsonResidual(double x1, double x2, double log_y) : x1_(x1), x2_(x2), log_y_(log_y) {}
  template <typename T>
  bool operator()(const T* b, T* residual) const {
    residual[0] = T(log_y_) - models::Nelson{}(b, x1_, x2_);
    return true;
  }
  static ResidualBlock block(double x1, double x2, double log_y) {
    return autodiff<1, models::Nelson::kParameters>(NelsonResidual(x1, x2, log_y));
  }

 private:
  const double x1_, x2_, log_y_;
};

FitResult fit_nelson(const Problem& p, const std::vector<double>& start, const std::vector<std::string>& names,
                     const FitOptions& options) {
  std::vector<double> b = start;
  FitResult bad;
  if (p.x.size() != 2 || b.size() != static_cast<std::size_t>(models::Nelson::kParameters)) {
    bad.message = "Nelson needs two predictors and three parameters";
    return bad;
  }
  std::vector<double> log_y;
  for (double y : p.y) {
    if (!(y > 0)) {
      bad.message = "Nelson's response must be positive (its model is for log y)";
      return bad;
    }
    log_y.push_back(std::log(y));
  }
  fit::Problem problem;
  for (std::size_t i = 0; i < p.y.size(); ++i) problem.add(NelsonResidual::block(p.x[0][i], p.x[1][i], log_y[i]), {b.data()}, options);
  const SolveSummary summary = problem.solve(options);
  FitResult r = problem.summarize(ParameterLayout{{b.data()}, {models::Nelson::kParameters}, names}, log_y, summary, options);
  std::vector<long double> log_y_extended;
  for (long double y : p.y_extended) log_y_extended.push_back(std::log(y));
  polish_in_extended_precision<models::Nelson::kParameters>(r, p.y.size(), [&](const auto* c, std::size_t i) {
    using T = std::decay_t<decltype(*c)>;
    return T(log_y_extended[i]) - models::Nelson{}(c, p.x[0][i], p.x[1][i]);
  });
  return r;
}

using FitFn = FitResult (*)(const Problem&, const std::vector<double>&, const std::vector<std::string>&,
                            const FitOptions&);

struct ModelEntry {
  int parameters;
  int predictors;
  FitFn fit;
};

template <class Model>
ModelEntry entry() {
  return {Model::kParameters, 1, &fit_one<Model>};
}

const std::map<std::string, ModelEntry>& registry() {
  static const std::map<std::string, ModelEntry> r = {
      {"Misra1a", entry<models::Misra1a>()},
      {"Chwirut2", entry<models::Chwirut>()},
      {"Chwirut1", entry<models::Chwirut>()},
      {"Lanczos3", entry<models::Lanczos>()},
      {"Gauss1", entry<models::Gauss>()},
      {"Gauss2", entry<models::Gauss>()},
      {"DanWood", entry<models::DanWood>()},
      {"Misra1b", entry<models::Misra1b>()},
      {"Kirby2", entry<models::Kirby2>()},
      {"Hahn1", entry<models::Rational33>()},
      {"Nelson", ModelEntry{models::Nelson::kParameters, 2, &fit_nelson}},
      {"MGH17", entry<models::MGH17>()},
      {"Lanczos1", entry<models::Lanczos>()},
      {"Lanczos2", entry<models::Lanczos>()},
      {"Gauss3", entry<models::Gauss>()},
      {"Misra1c", entry<models::Misra1c>()},
      {"Misra1d", entry<models::Misra1d>()},
      {"Roszman1", entry<models::Roszman1>()},
      {"ENSO", entry<models::ENSO>()},
      {"MGH09", entry<models::MGH09>()},
      {"Thurber", entry<models::Rational33>()},
      {"BoxBOD", entry<models::BoxBOD>()},
      {"Rat42", entry<models::Rat42>()},
      {"MGH10", entry<models::MGH10>()},
      {"Eckerle4", entry<models::Eckerle4>()},
      {"Rat43", entry<models::Rat43>()},
      {"Bennett5", entry<models::Bennett5>()},
  };
  return r;
}

}  // namespace

const std::vector<std::string>& problem_names() {
  // NIST's order: lower, then average, then higher difficulty.
  static const std::vector<std::string> names = {
      "Misra1a", "Chwirut2", "Chwirut1", "Lanczos3", "Gauss1",   "Gauss2",  "DanWood", "Misra1b", "Kirby2",
      "Hahn1",   "Nelson",   "MGH17",    "Lanczos1", "Lanczos2", "Gauss3",  "Misra1c", "Misra1d", "Roszman1",
      "ENSO",    "MGH09",    "Thurber",  "BoxBOD",   "Rat42",    "MGH10",   "Eckerle4", "Rat43",  "Bennett5"};
  return names;
}

bool has_model(const std::string& name) { return registry().count(name) > 0; }

Problem parse(const std::string& text, const std::string& path) {
  Problem p;
  p.path = path;
  p.name = std::filesystem::path(path).stem().string();
  const auto found = registry().find(p.name);
  if (found == registry().end())
    throw InputError(path, 1, 1, "unknown StRD problem '" + p.name + "' (the file name names the model)");
  const ModelEntry& model = found->second;

  std::vector<std::string> lines;
  {
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      lines.push_back(line);
    }
  }
  bool have_rss = false, have_n = false;
  int data_header = -1;  // 0-based index of the "Data:   y   x" line
  int data_columns = 0;
  for (std::size_t i = 0; i < lines.size() && data_header < 0; ++i) {
    const int ln = static_cast<int>(i) + 1;
    const std::vector<Token> t = split(lines[i]);
    if (t.empty()) continue;
    // Parameter line: "b1 = start1 start2 certified sd"
    if (t.size() >= 2 && t[0].text.size() >= 2 && t[0].text[0] == 'b' && t[1].text == "=" &&
        std::all_of(t[0].text.begin() + 1, t[0].text.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      const std::string expected = "b" + std::to_string(p.parameters.size() + 1);
      if (t[0].text != expected)
        throw InputError(path, ln, t[0].column, "expected parameter " + expected + ", found " + t[0].text);
      if (t.size() != 6) {
        const int col = t.size() > 6 ? t[6].column : static_cast<int>(lines[i].size()) + 1;
        throw InputError(path, ln, col,
                         "a parameter line holds 'bN = start1 start2 certified_value certified_sd' (" +
                             std::to_string(t.size() - 2) + " numbers found, 4 expected)");
      }
      CertifiedParameter c;
      c.name = t[0].text;
      c.start1 = number(t[2], path, ln, c.name + " start 1");
      c.start2 = number(t[3], path, ln, c.name + " start 2");
      c.certified = number(t[4], path, ln, c.name + " certified value");
      c.certified_sd = number(t[5], path, ln, c.name + " certified standard deviation");
      p.parameters.push_back(c);
      continue;
    }
    if (starts_with(lines[i], "Residual Sum of Squares:")) {
      if (t.size() != 5) throw InputError(path, ln, t.back().column, "expected one number after 'Residual Sum of Squares:'");
      p.certified_rss = number(t[4], path, ln, "the residual sum of squares");
      have_rss = true;
      continue;
    }
    if (starts_with(lines[i], "Number of Observations:")) {
      if (t.size() != 4) throw InputError(path, ln, t.back().column, "expected one number after 'Number of Observations:'");
      const double n = number(t[3], path, ln, "the number of observations");
      if (!(n >= 1) || n != std::floor(n)) throw InputError(path, ln, t[3].column, "the number of observations must be a positive integer");
      p.certified_observations = static_cast<std::size_t>(n);
      have_n = true;
      continue;
    }
    if (t[0].text == "Data:" && t.size() >= 3 && t[1].text == "y") {
      data_header = static_cast<int>(i);
      data_columns = static_cast<int>(t.size()) - 1;
    }
  }
  const int last_line = static_cast<int>(lines.size());
  if (p.parameters.empty()) throw InputError(path, last_line, 1, "no parameter lines ('b1 = ...') found");
  if (static_cast<int>(p.parameters.size()) != model.parameters)
    throw InputError(path, last_line, 1,
                     p.name + " has " + std::to_string(model.parameters) + " parameters; the file lists " +
                         std::to_string(p.parameters.size()));
  if (!have_rss) throw InputError(path, last_line, 1, "no 'Residual Sum of Squares:' line found");
  if (!have_n) throw InputError(path, last_line, 1, "no 'Number of Observations:' line found");
  if (data_header < 0) throw InputError(path, last_line, 1, "no data header ('Data:   y   x') found");
  if (data_columns != 1 + model.predictors)
    throw InputError(path, data_header + 1, 1,
                     p.name + " has " + std::to_string(model.predictors) + " predictor(s); the data header names " +
                         std::to_string(data_columns - 1));
  p.x.assign(static_cast<std::size_t>(model.predictors), {});
  p.x_extended.assign(static_cast<std::size_t>(model.predictors), {});
  for (std::size_t i = static_cast<std::size_t>(data_header) + 1; i < lines.size(); ++i) {
    const int ln = static_cast<int>(i) + 1;
    const std::vector<Token> t = split(lines[i]);
    if (t.empty()) continue;
    if (static_cast<int>(t.size()) != data_columns) {
      const int col = static_cast<int>(t.size()) > data_columns ? t[static_cast<std::size_t>(data_columns)].column
                                                                : static_cast<int>(lines[i].size()) + 1;
      throw InputError(path, ln, col,
                       "a data row holds " + std::to_string(data_columns) + " numbers, found " + std::to_string(t.size()));
    }
    p.y.push_back(number(t[0], path, ln, "y"));
    p.y_extended.push_back(std::strtold(t[0].text.c_str(), nullptr));
    for (int k = 0; k < model.predictors; ++k) {
      const Token& token = t[static_cast<std::size_t>(k) + 1];
      p.x[static_cast<std::size_t>(k)].push_back(number(token, path, ln, "x"));
      p.x_extended[static_cast<std::size_t>(k)].push_back(std::strtold(token.text.c_str(), nullptr));
    }
  }
  if (p.y.size() != p.certified_observations)
    throw InputError(path, last_line, 1,
                     "the file announces " + std::to_string(p.certified_observations) + " observations but holds " +
                         std::to_string(p.y.size()) + " data rows");
  return p;
}

Problem read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, 0, "cannot open file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse(ss.str(), path);
}

double log_relative_error(double computed, double certified, double digits) {
  if (!std::isfinite(computed)) return 0.0;
  const double err = std::abs(computed - certified);
  if (err == 0) return digits;
  const double rel = certified != 0 ? err / std::abs(certified) : err;
  const double lre = -std::log10(rel);
  return std::clamp(lre, 0.0, digits);
}

FitOptions default_options() { return FitOptions::reference(); }

FitResult fit(const Problem& problem, int start, const FitOptions& options) {
  const auto found = registry().find(problem.name);
  if (found == registry().end()) {
    FitResult bad;
    bad.message = "unknown StRD problem '" + problem.name + "'";
    return bad;
  }
  std::vector<double> b;
  std::vector<std::string> names;
  for (const auto& c : problem.parameters) {
    b.push_back(start == 2 ? c.start2 : c.start1);
    names.push_back(c.name);
  }
  return found->second.fit(problem, b, names, options);
}

RunReport run(const Problem& problem, int start, const FitOptions& options, const Target& target) {
  RunReport r;
  r.problem = problem.name;
  r.start = start;
  r.certified_rss = problem.certified_rss;
  const auto t0 = std::chrono::steady_clock::now();
  const FitResult f = fit(problem, start, options);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.usable = f.usable;
  r.message = f.message;
  r.iterations = f.iterations;
  r.rss = f.rss;
  r.rss_lre = log_relative_error(f.rss, problem.certified_rss);
  r.min_lre = kCertifiedDigits;
  r.min_std_error_lre = kCertifiedDigits;
  for (std::size_t i = 0; i < problem.parameters.size(); ++i) {
    const CertifiedParameter& c = problem.parameters[i];
    ParameterReport pr;
    pr.name = c.name;
    pr.certified = c.certified;
    pr.certified_sd = c.certified_sd;
    if (i < f.parameters.size()) {
      pr.value = f.parameters[i].value;
      pr.std_error = f.parameters[i].std_error;
    } else {
      pr.value = pr.std_error = std::numeric_limits<double>::quiet_NaN();
    }
    pr.lre = log_relative_error(pr.value, c.certified);
    pr.std_error_lre = log_relative_error(pr.std_error, c.certified_sd);
    r.min_lre = std::min(r.min_lre, pr.lre);
    r.min_std_error_lre = std::min(r.min_std_error_lre, pr.std_error_lre);
    r.parameters.push_back(pr);
  }
  r.at_target = r.usable && r.min_lre >= target.parameter_lre && r.min_std_error_lre >= target.std_error_lre;
  return r;
}

}  // namespace epuck2::nist
