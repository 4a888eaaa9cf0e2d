// The censored, robust fit of epuck2/fit/robust.hpp: the Tobit likelihood stated to the engine as
// a fit::Problem over fit::readings_block, Cauchy-weighted first pass, outliers left out beyond
// reject_sd, noise by EM, identifiability by the engine's one check (check_identifiability) with
// the calibration's policy (hold at the fallback, refit), lack of fit against replicates, and the
// distributions the tests need. No Ceres here: the engine's sources below hold it.
#include "epuck2/fit/robust.hpp"
#include "epuck2/fit/replicates.hpp"
#include "epuck2/fit/problem.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <sstream>

#include "epuck2/logs/output.hpp"

namespace epuck2::fit {

// ================================================================================================
// Distributions
// ================================================================================================

namespace {
constexpr double kLogSqrt2Pi = 0.91893853320467274178;  // log(sqrt(2 pi))

double gamma_series(double a, double x) {  // P(a, x), x < a + 1
  double sum = 1.0 / a, term = sum, ap = a;
  for (int n = 0; n < 1000; ++n) {
    ap += 1;
    term *= x / ap;
    sum += term;
    if (std::abs(term) < std::abs(sum) * 1e-16) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

double gamma_continued_fraction(double a, double x) {  // Q(a, x), x >= a + 1 (modified Lentz)
  const double tiny = 1e-300;
  double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
  for (int i = 1; i < 1000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1) < 1e-16) break;
  }
  return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

double beta_continued_fraction(double a, double b, double x) {
  const double tiny = 1e-300;
  const double qab = a + b, qap = a + 1, qam = a - 1;
  double c = 1, d = 1 - qab * x / qap;
  if (std::abs(d) < tiny) d = tiny;
  d = 1 / d;
  double h = d;
  for (int m = 1; m < 1000; ++m) {
    const int m2 = 2 * m;
    double aa = m * (b - m) * x / ((qam + m2) * (a + m2));
    d = 1 + aa * d;
    if (std::abs(d) < tiny) d = tiny;
    c = 1 + aa / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1 / d;
    h *= d * c;
    aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
    d = 1 + aa * d;
    if (std::abs(d) < tiny) d = tiny;
    c = 1 + aa / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1) < 1e-16) break;
  }
  return h;
}

/// Regularised incomplete beta I_x(a, b).
double incomplete_beta(double a, double b, double x) {
  if (x <= 0) return 0;
  if (x >= 1) return 1;
  const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x));
  if (x < (a + 1) / (a + b + 2)) return front * beta_continued_fraction(a, b, x) / a;
  return 1 - front * beta_continued_fraction(b, a, 1 - x) / b;
}
}  // namespace

double gamma_q(double a, double x) {
  if (!(a > 0) || !(x >= 0)) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0) return 1;
  if (x < a + 1) return 1 - gamma_series(a, x);
  return gamma_continued_fraction(a, x);
}

double chi2_upper_tail(double chi2, double dof) { return gamma_q(0.5 * dof, 0.5 * std::max(chi2, 0.0)); }

double f_upper_tail(double f, double d1, double d2) {
  if (!(f > 0)) return 1;
  return incomplete_beta(0.5 * d2, 0.5 * d1, d2 / (d2 + d1 * f));
}

// ================================================================================================
// The Tobit problem, stated to the engine
// ================================================================================================

namespace {

// The readings as the engine's one treatment states them (fit::readings_block over the model's
// latent predictions): observation i's residual is reading_residual(f_i, y_i, censoring, sigma,
// sqrt(w_i)), so that 1/2 sum r_i^2 is the negative log-likelihood up to constants; a weight of 0
// leaves it out, and so does `use_censored` false for a reading on a rail.
ResidualBlock tobit_block(const ModelEvaluator& model, const std::vector<Observation>& obs, const std::vector<double>& weights,
                          double sigma, bool use_censored, int parameters) {
  ResidualBlock latent;
  latent.residuals = static_cast<int>(obs.size());
  latent.sizes = {parameters};
  latent.evaluate = [&model](double const* const* p, double* predictions, double** jacobians) {
    return model(p[0], predictions, jacobians != nullptr ? jacobians[0] : nullptr);
  };
  std::vector<double> y(obs.size()), w(obs.size());
  std::vector<Censoring> censoring(obs.size());
  for (std::size_t i = 0; i < obs.size(); ++i) {
    y[i] = obs[i].value;
    censoring[i] = obs[i].censoring;
    w[i] = obs[i].censoring != Censoring::none && !use_censored ? 0.0 : weights[i];
  }
  return readings_block(std::move(latent), std::move(y), std::move(censoring), std::move(w), sigma);
}

struct Solution {
  bool ok = false;
  std::string message;
  std::vector<double> predictions;
};

// One solve with the given weights and sigma, parameters in and out of `p`: a fit::Problem over
// the readings block, the held parameters held, bounds on the others, the calibration's settings.
Solution solve_once(const ModelEvaluator& model, const std::vector<Observation>& obs, std::vector<double>& p,
                    const std::vector<Parameter>& params, const std::vector<bool>& held, const std::vector<double>& w,
                    double sigma, bool use_censored) {
  const int m = static_cast<int>(p.size());
  const FitOptions options = FitOptions::calibration();
  Problem problem;
  problem.add(tobit_block(model, obs, w, sigma, use_censored, m), {p.data()}, options);
  std::vector<int> held_idx;
  for (int j = 0; j < m; ++j)
    if (held[static_cast<std::size_t>(j)]) held_idx.push_back(j);
  problem.hold(p.data(), held_idx);
  if (static_cast<int>(held_idx.size()) < m)
    for (int j = 0; j < m; ++j) {
      const Parameter& q = params[static_cast<std::size_t>(j)];
      if (held[static_cast<std::size_t>(j)]) continue;
      if (std::isfinite(q.lower)) problem.set_lower_bound(p.data(), j, q.lower);
      if (std::isfinite(q.upper)) problem.set_upper_bound(p.data(), j, q.upper);
    }
  const SolveSummary summary = problem.solve(options);
  Solution s;
  s.ok = summary.usable;
  s.message = summary.message;
  s.predictions.resize(obs.size());
  if (!model(p.data(), s.predictions.data(), nullptr)) {
    s.ok = false;
    s.message = "the model is not finite at the solution";
  }
  return s;
}

/// The calibration's policy on a direction the logs do not determine: of the parameters along it
/// (kAlongShare), the last declared of those with at least this share is held at its fallback.
constexpr double kHoldShare = 0.5;

/// A number in a message: `digits` significant digits (the project's one formatter).
std::string fmt(double v, int digits = 4) { return logs::format_number(v, digits); }

}  // namespace

// ================================================================================================
// fit_robust
// ================================================================================================

RobustFit fit_robust(const ModelEvaluator& model, const std::vector<Observation>& obs, std::vector<Parameter> params,
                     const RobustOptions& opt) {
  RobustFit out;
  const std::size_t n = obs.size(), m = params.size();
  out.FitResult::parameters.resize(m);
  for (std::size_t j = 0; j < m; ++j) {
    out.FitResult::parameters[j].name = params[j].name;
    out.FitResult::parameters[j].value = std::numeric_limits<double>::quiet_NaN();
    out.FitResult::parameters[j].std_error = std::numeric_limits<double>::quiet_NaN();
  }
  out.final_parameters = params;
  out.method = opt.robust ? "robust: Cauchy-reweighted start, readings beyond " + fmt(opt.reject_sd) +
                                " noise sd left out as outliers; readings on a rail censored (Tobit)"
                          : "least squares; readings on a rail censored (Tobit)";
  for (const Observation& o : obs) {
    if (o.censoring == Censoring::none) ++out.exact;
    if (o.censoring == Censoring::at_or_below) ++out.censored_below;
    if (o.censoring == Censoring::at_or_above) ++out.censored_above;
  }
  if (m == 0 || m > static_cast<std::size_t>(kMaxRobustParameters)) {
    out.message = "internal: a robust fit takes 1 to " + std::to_string(kMaxRobustParameters) + " parameters";
    return out;
  }
  std::vector<bool> held(m, false);
  for (std::size_t j = 0; j < m; ++j) {
    held[j] = params[j].fixed;
    params[j].value = std::clamp(params[j].value, params[j].lower, params[j].upper);
  }
  const bool sigma_given = std::isfinite(opt.noise_sd) && opt.noise_sd > 0;
  if (out.exact == 0 && !sigma_given) {
    out.message = "every reading is on a rail: the noise cannot be estimated";
    return out;
  }
  // Too few readings for the parameters and the noise: no calibration, whatever the solver says.
  std::size_t free_count = 0;
  for (const Parameter& q : params) free_count += q.fixed ? 0 : 1;
  if (out.exact < free_count + (sigma_given ? 0 : 1)) {
    out.message = "too few readings inside the rails (" + std::to_string(out.exact) + ") for " +
                  std::to_string(free_count) + " parameters" + (sigma_given ? "" : " and the noise");
    return out;
  }

  // Readings that repeat under the same conditions are judged wild against their replicates, not
  // against the curve (a model that misses some conditions would otherwise shed good readings).
  std::vector<double> values(n);
  std::vector<int> groups(n);
  std::vector<bool> on_rail(n), judged_by_replicates(n, false);
  std::map<int, std::size_t> group_size;
  // The screen's groups: the same conditions read by the same robot (a robot's readings are not
  // replicates of another's: the robots' differences would pass for noise).
  std::map<std::pair<int, int>, int> screen_group;
  std::set<int> robots;
  for (std::size_t i = 0; i < n; ++i) {
    values[i] = obs[i].value;
    groups[i] = obs[i].group < 0 ? -1
                                 : screen_group.emplace(std::make_pair(obs[i].group, obs[i].robot), static_cast<int>(screen_group.size()))
                                       .first->second;
    on_rail[i] = obs[i].censoring != Censoring::none;
    if (groups[i] >= 0) ++group_size[groups[i]];
    if (obs[i].robot >= 0) robots.insert(obs[i].robot);
  }
  for (std::size_t i = 0; i < n; ++i) judged_by_replicates[i] = groups[i] >= 0 && group_size[groups[i]] >= kMinReplicates;
  // The method says which rule judged which readings: a reading among replicates is never judged
  // by the curve (however far from it), the others are.
  const std::size_t by_replicates =
      static_cast<std::size_t>(std::count(judged_by_replicates.begin(), judged_by_replicates.end(), true));
  if (opt.robust && by_replicates > 0)
    out.method = "robust: the " + std::to_string(by_replicates) + " readings in groups of " + std::to_string(kMinReplicates) +
                 " or more under the same conditions" + (robots.size() > 1 ? " and robot" : "") +
                 " judged against their replicates only (left out beyond " +
                 fmt(kWildReadingSd) + " robust sd of their group's median, not by their distance to the curve)" +
                 (by_replicates < n ? "; the other " + std::to_string(n - by_replicates) +
                                          ": Cauchy-reweighted start, readings beyond " + fmt(opt.reject_sd) +
                                          " noise sd of the curve left out as outliers"
                                    : std::string()) +
                 "; readings on a rail censored (Tobit)";
  const std::vector<bool> replicate_wild =
      opt.robust ? flag_wild_replicates(values, groups, on_rail, opt.noise_floor) : std::vector<bool>(n, false);
  std::vector<double> w(n, 1.0), p(m), predictions;
  double sigma = sigma_given ? opt.noise_sd : 1.0;
  auto exact_residuals = [&](const std::vector<double>& f, const std::vector<double>& weights) {
    std::vector<double> r;
    for (std::size_t i = 0; i < n; ++i)
      if (obs[i].censoring == Censoring::none && weights[i] > 0) r.push_back(obs[i].value - f[i]);
    return r;
  };
  auto robust_sigma = [&](const std::vector<double>& f, const std::vector<double>& weights) {
    std::vector<double> r = exact_residuals(f, weights);
    for (double& x : r) x = std::abs(x);
    double s = 1.482602218505602 * median(r);
    if (!(s > 0)) {  // more than half exact: fall back on the root mean square
      double ss = 0;
      for (double x : r) ss += x * x;
      s = r.empty() ? 0 : std::sqrt(ss / static_cast<double>(r.size()));
    }
    return std::max(s, opt.noise_floor);
  };

  for (;;) {  // until every free parameter is identifiable
    for (std::size_t j = 0; j < m; ++j) p[j] = params[j].value;
    for (std::size_t i = 0; i < n; ++i) w[i] = replicate_wild[i] ? 0.0 : 1.0;
    // 1. Start: the exact readings alone, plain least squares.
    Solution s = solve_once(model, obs, p, params, held, w, 1.0, false);
    if (!s.ok) {
      out.message = "no solution: " + s.message;
      return out;
    }
    if (!sigma_given) sigma = robust_sigma(s.predictions, w);
    if (!(sigma > 0)) sigma = std::max(opt.noise_floor, 1e-12);
    // 2. Robust: Cauchy weights, sigma from the median absolute residual.
    if (opt.robust) {
      for (int pass = 0; pass < 10; ++pass) {
        for (std::size_t i = 0; i < n; ++i) {
          if (judged_by_replicates[i]) continue;
          double dev = obs[i].value - s.predictions[i];
          // A railed reading pulls only when the curve is on the wrong side of its rail.
          if (obs[i].censoring == Censoring::at_or_above) dev = std::max(dev, 0.0);
          if (obs[i].censoring == Censoring::at_or_below) dev = std::min(dev, 0.0);
          const double u = dev / (opt.cauchy_scale_sd * sigma);
          w[i] = 1 / (1 + u * u);
        }
        const std::vector<double> before = p;
        s = solve_once(model, obs, p, params, held, w, sigma, true);
        if (!s.ok) break;
        if (!sigma_given) sigma = robust_sigma(s.predictions, w);
        double change = 0;
        for (std::size_t j = 0; j < m; ++j) change = std::max(change, std::abs(p[j] - before[j]) / (std::abs(p[j]) + 1e-12));
        if (change < 1e-9) break;
      }
      if (!s.ok) {
        out.message = "no solution in the reweighted pass: " + s.message;
        return out;
      }
    }
    // 3. Outliers out (robust), the rest by Tobit maximum likelihood, sigma by EM.
    std::vector<double> hard(n, 1.0);
    for (int pass = 0; pass < opt.max_passes; ++pass) {
      std::vector<double> next(n, 1.0);
      for (std::size_t i = 0; i < n; ++i) next[i] = replicate_wild[i] ? 0.0 : 1.0;
      if (opt.robust)
        for (std::size_t i = 0; i < n; ++i) {
          if (judged_by_replicates[i]) continue;
          const double dev = (obs[i].value - s.predictions[i]) / sigma;
          if (obs[i].censoring == Censoring::none && std::abs(dev) > opt.reject_sd) next[i] = 0;
          // A rail reading the curve puts far on the other side of the rail is just as wild.
          if (obs[i].censoring == Censoring::at_or_above && -dev < -opt.reject_sd) next[i] = 0;
          if (obs[i].censoring == Censoring::at_or_below && dev < -opt.reject_sd) next[i] = 0;
        }
      const bool same_set = pass > 0 && next == hard;
      hard = next;
      const std::vector<double> before = p;
      const double sigma_before = sigma;
      s = solve_once(model, obs, p, params, held, hard, sigma, true);
      if (!s.ok) {
        out.message = "no solution: " + s.message;
        return out;
      }
      if (!sigma_given) {
        double ss = 0, count = 0;
        for (std::size_t i = 0; i < n; ++i) {
          if (hard[i] <= 0) continue;
          const Observation& o = obs[i];
          if (o.censoring == Censoring::none) {
            ss += (o.value - s.predictions[i]) * (o.value - s.predictions[i]);
          } else {
            // E[(y* - f)^2 | beyond the rail] = sigma^2 (1 + c lambda), c the rail in sd beyond f.
            const double c = (o.censoring == Censoring::at_or_above ? 1.0 : -1.0) * (o.value - s.predictions[i]) / sigma;
            ss += sigma * sigma * (1 + c * normal_hazard_lower(-c));
          }
          count += 1;
        }
        sigma = std::max(std::sqrt(ss / std::max(count, 1.0)), opt.noise_floor);
      }
      double change = std::abs(sigma - sigma_before) / sigma_before;
      for (std::size_t j = 0; j < m; ++j) change = std::max(change, std::abs(p[j] - before[j]) / (std::abs(p[j]) + 1e-12));
      if (same_set && change < 1e-8) break;
    }
    w = hard;
    predictions = s.predictions;

    // 4. Identifiability: the engine's one check on the Jacobian of the residuals over the free
    // parameters (check_identifiability); the calibration's policy holds the parameter it names.
    const ResidualBlock cost = tobit_block(model, obs, w, sigma, true, static_cast<int>(m));
    std::vector<double> r(n), jrow(n * m);
    double* jac[1] = {jrow.data()};
    const double* pp[1] = {p.data()};
    if (!cost.evaluate(pp, r.data(), jac)) {
      out.message = "the model is not finite at the solution";
      return out;
    }
    std::vector<std::size_t> free_idx;
    for (std::size_t j = 0; j < m; ++j)
      if (!held[j]) free_idx.push_back(j);
    const std::size_t k = free_idx.size();
    Eigen::MatrixXd J(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(k));
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t c = 0; c < k; ++c) J(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c)) = jrow[i * m + free_idx[c]];
    std::size_t to_hold = m;  // none
    std::string why;
    Eigen::MatrixXd cov_free;
    if (k > 0) {
      const Identifiability id = check_identifiability(J, {}, opt.max_condition);
      Identifiability said = id;  // for the report: columns as the parameters' indices
      said.inverse_normal.resize(0, 0);
      for (Eigen::Index& c : said.estimable) c = static_cast<Eigen::Index>(free_idx[static_cast<std::size_t>(c)]);
      for (Identifiability::Column& u : said.undetermined) u.column = static_cast<Eigen::Index>(free_idx[static_cast<std::size_t>(u.column)]);
      out.identifiability.push_back(std::move(said));
      if (id.any(Identifiability::Why::zero_column)) {
        // The first free parameter the logs do not depend on.
        for (const Identifiability::Column& u : id.undetermined)
          if (u.why == Identifiability::Why::zero_column) {
            to_hold = free_idx[static_cast<std::size_t>(u.column)];
            why = "the logs do not depend on it";
            break;
          }
      } else if (!id.determined()) {
        // Along the least-determined direction: the last declared of those most along it is held.
        std::vector<std::string> along;
        for (const Identifiability::Column& u : id.undetermined) {
          if (u.share >= kHoldShare) to_hold = free_idx[static_cast<std::size_t>(u.column)];
          along.push_back(params[free_idx[static_cast<std::size_t>(u.column)]].name);
        }
        why = "the logs determine only a combination of ";
        for (std::size_t a = 0; a < along.size(); ++a) why += (a ? (a + 1 == along.size() ? " and " : ", ") : "") + along[a];
        why += id.rank_deficient() ? " (they enter the logs only together)" : " (condition number " + fmt(id.condition) + ")";
      } else {
        cov_free = id.inverse_normal;
      }
    }
    if (to_hold != m) {
      held[to_hold] = true;
      const double fallback = params[to_hold].fallback;
      if (!std::isfinite(fallback)) {
        out.message = params[to_hold].name + " is not identifiable from these logs (" + why +
                          ") and has no documented default";
        return out;
      }
      params[to_hold].value = fallback;
      out.not_identifiable.push_back(params[to_hold].name);
      out.std_error_why[params[to_hold].name] = "not identifiable: " + why + "; held at its documented default " + fmt(fallback, 10);
      out.warnings.push_back(params[to_hold].name + " is not identifiable from these logs: " + why +
                             "; it keeps its documented default " + fmt(fallback, 10) + ".");
      continue;
    }

    // 5. Statistics. Sigma with the degrees of freedom taken by the free parameters.
    std::size_t kept_exact = 0, kept_censored = 0;
    double rss = 0, ybar = 0, loglik = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (w[i] <= 0) continue;
      if (obs[i].censoring == Censoring::none) {
        ++kept_exact;
        ybar += obs[i].value;
        rss += (obs[i].value - predictions[i]) * (obs[i].value - predictions[i]);
      } else {
        ++kept_censored;
        ++(obs[i].censoring == Censoring::at_or_below ? out.kept_censored_below : out.kept_censored_above);
      }
    }
    out.kept_exact = kept_exact;
    ybar /= std::max<std::size_t>(kept_exact, 1);
    double tss = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (w[i] > 0 && obs[i].censoring == Censoring::none) tss += (obs[i].value - ybar) * (obs[i].value - ybar);
    for (std::size_t i = 0; i < n; ++i) {
      if (w[i] <= 0) continue;
      if (obs[i].censoring == Censoring::none) {
        const double z = (obs[i].value - predictions[i]) / sigma;
        loglik += -std::log(sigma) - kLogSqrt2Pi - 0.5 * z * z;
      } else {
        const double sign = obs[i].censoring == Censoring::at_or_above ? 1.0 : -1.0;
        loglik += log_normal_cdf(sign * (predictions[i] - obs[i].value) / sigma);
      }
    }
    const std::size_t kept = kept_exact + kept_censored;
    const double dof_scale =
        (!sigma_given && kept_exact > k) ? static_cast<double>(kept_exact) / static_cast<double>(kept_exact - k) : 1.0;
    for (std::size_t i = 0; i < n; ++i)
      if (w[i] <= 0) {
        out.outliers.push_back(i);
        out.outlier_where.push_back(obs[i].where);
      }
    FitResult& f = out;
    f.usable = true;
    f.message = s.message;
    f.observations = kept;
    f.rss = rss;
    f.mse = kept_exact ? rss / static_cast<double>(kept_exact) : 0.0;
    f.residual_variance = sigma * sigma * dof_scale;
    f.r2 = tss > 0 ? 1 - rss / tss : std::numeric_limits<double>::quiet_NaN();
    f.free_parameters = static_cast<int>(k);
    const double nparams = static_cast<double>(k + (sigma_given ? 0 : 1));
    f.aic = -2 * loglik + 2 * nparams;
    f.bic = -2 * loglik + nparams * std::log(static_cast<double>(std::max<std::size_t>(kept, 1)));
    out.log_likelihood = loglik;
    out.noise_sd = sigma * std::sqrt(dof_scale);
    f.covariance = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(m));
    for (std::size_t a = 0; a < k; ++a)
      for (std::size_t b = 0; b < k; ++b)
        f.covariance(static_cast<Eigen::Index>(free_idx[a]), static_cast<Eigen::Index>(free_idx[b])) =
            cov_free(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) * dof_scale;
    for (std::size_t j = 0; j < m; ++j) {
      params[j].value = p[j];
      f.parameters[j].value = p[j];
      if (held[j]) {
        const bool not_identifiable =
            std::find(out.not_identifiable.begin(), out.not_identifiable.end(), params[j].name) != out.not_identifiable.end();
        f.parameters[j].std_error = not_identifiable ? std::numeric_limits<double>::quiet_NaN() : 0.0;
        continue;
      }
      const double var = f.covariance(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(j));
      f.parameters[j].std_error = var >= 0 ? std::sqrt(var) : std::numeric_limits<double>::quiet_NaN();
      if (!std::isfinite(f.parameters[j].std_error)) out.std_error_why[params[j].name] = "the covariance is not finite";
      const bool at_lower = std::isfinite(params[j].lower) && p[j] <= params[j].lower + 1e-12 * (1 + std::abs(p[j]));
      const bool at_upper = std::isfinite(params[j].upper) && p[j] >= params[j].upper - 1e-12 * (1 + std::abs(p[j]));
      if (at_lower || at_upper)
        out.warnings.push_back(params[j].name + " = " + fmt(p[j]) + " sits on its physical bound; the data push it beyond, "
                               "and its standard error assumes the bound is not there.");
    }
    f.iterations = 0;
    out.final_parameters = params;
    out.predictions = predictions;
    out.scaled_residuals = r;
    out.jacobian = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(m));
    for (std::size_t c = 0; c < k; ++c) out.jacobian.col(static_cast<Eigen::Index>(free_idx[c])) = J.col(static_cast<Eigen::Index>(c));
    if (kept_exact <= k)
      out.warnings.push_back("only " + std::to_string(kept_exact) + " readings inside the rails for " + std::to_string(k) +
                             " free parameters: the noise is not estimated from the fit.");
    else if (kept_exact < kFewReadingsPerParameter * (k + (sigma_given ? 0 : 1)))
      out.warnings.push_back("only " + std::to_string(kept_exact) + " readings inside the rails for " + std::to_string(k) +
                             (k == 1 ? " free parameter" : " free parameters") + (sigma_given ? "" : " and the noise") +
                             " (fewer than " + std::to_string(kFewReadingsPerParameter) +
                             " per parameter): the fit is barely determined and its standard errors are rough.");

    // 6. Lack of fit against the replicates (groups without censored or left-out readings).
    std::map<int, std::vector<std::size_t>> groups;
    std::map<int, bool> spoilt;
    for (std::size_t i = 0; i < n; ++i) {
      if (obs[i].group < 0) continue;
      if (obs[i].censoring != Censoring::none) spoilt[obs[i].group] = true;
      if (w[i] > 0) groups[obs[i].group].push_back(i);
    }
    std::vector<ReplicateGroup> replicates;
    for (const auto& [id, members] : groups) {
      if (spoilt[id] || members.empty()) continue;
      ReplicateGroup rg;
      rg.condition = static_cast<double>(id);
      rg.label = "the " + std::to_string(members.size()) + " readings from " + obs[members.front()].where;
      for (std::size_t i : members) {
        rg.readings.push_back(obs[i].value);
        rg.predictions.push_back(predictions[i]);
      }
      replicates.push_back(std::move(rg));
    }
    LackOfFit& lof = out.lack_of_fit;
    lof = lack_of_fit(replicates, k, {}, opt.noise_floor);
    if (lof.tested) {
      std::set<int> spanned;
      for (const auto& [id, members] : groups)
        if (!spoilt[id])
          for (std::size_t i : members)
            if (obs[i].robot >= 0) spanned.insert(obs[i].robot);
      lof.robots = spanned.size();
    }
    if (lof.tested && lof.p_value < 1e-3)
      out.warnings.push_back("the model does not fit these data within their noise: lack-of-fit reduced chi^2 " +
                             fmt(lof.reduced_chi2) + " (p = " + fmt(lof.p_value) + ") against the replicates' sd " +
                             fmt(lof.replicate_sd) + ".");
    if (lof.tested && lof.misfit_ratio > kMisfitWarnRatio)
      out.warnings.push_back("the curve misses the replicates' means by " + fmt(lof.misfit_ratio, 3) +
                             " times their own sd; worst: " + lof.worst + ".");
    return out;
  }
}

// ================================================================================================
// Lack of fit against replicates
// ================================================================================================

LackOfFit lack_of_fit(const std::vector<ReplicateGroup>& groups_in, std::size_t k, const MisfitWords& words,
                      double sd_floor, double known_sd, std::size_t known_dof_pure) {
  LackOfFit lof;
  std::vector<const ReplicateGroup*> groups;
  for (const ReplicateGroup& g : groups_in)
    if (!g.spoilt && !g.readings.empty() && g.readings.size() == g.predictions.size()) groups.push_back(&g);
  std::stable_sort(groups.begin(), groups.end(),
                   [](const ReplicateGroup* a, const ReplicateGroup* b) { return a->condition < b->condition; });
  const bool known = known_sd > 0 && known_dof_pure > 0;
  double ss_pure = 0, ss_resid = 0;
  std::size_t count = 0;
  std::vector<double> miss;  // mean reading - mean prediction, per group
  for (const ReplicateGroup* g : groups) {
    double mean = 0, pred = 0;
    for (std::size_t i = 0; i < g->readings.size(); ++i) {
      mean += g->readings[i];
      pred += g->predictions[i];
    }
    mean /= static_cast<double>(g->readings.size());
    pred /= static_cast<double>(g->readings.size());
    for (std::size_t i = 0; i < g->readings.size(); ++i) {
      ss_pure += (g->readings[i] - mean) * (g->readings[i] - mean);
      ss_resid += (g->readings[i] - g->predictions[i]) * (g->readings[i] - g->predictions[i]);
      ++count;
    }
    miss.push_back(mean - pred);
  }
  const std::size_t g = groups.size();
  if (g == 0) {
    lof.why_not = "no repeated readings under the same conditions";
    return lof;
  }
  if (g <= k) {
    lof.why_not = "too few replicate groups (" + std::to_string(g) + "): the test needs more groups than the curve's " +
                  std::to_string(k) + (k == 1 ? " free parameter" : " free parameters");
    return lof;
  }
  if (!known && count <= g) {
    lof.why_not = "too few readings for the test (" + std::to_string(count) + " in " + std::to_string(g) + " replicate groups)";
    return lof;
  }
  if (!known && !(ss_pure > 0) && !(sd_floor > 0)) {
    // Replicates that agree to the last digit carry no noise to judge a misfit by (a ratio over
    // 0 would be infinite whatever the curve): most likely the same log given twice.
    lof.replicates_agree_exactly = true;
    lof.why_not = "the repeated readings agree exactly (" + std::to_string(g) +
                  " groups, no spread between them: the same log given twice?), so there is no noise to judge the curve by";
    return lof;
  }
  lof.tested = true;
  lof.groups = g;
  lof.dof_pure = known ? known_dof_pure : count - g;
  lof.dof_lack = g - k;
  const double pure_var = std::max(known ? known_sd * known_sd : ss_pure / static_cast<double>(lof.dof_pure), sd_floor * sd_floor);
  lof.replicate_sd = std::sqrt(pure_var);
  const double ss_lack = std::max(ss_resid - (known ? 0.0 : ss_pure), 0.0);
  const double lack = ss_lack / static_cast<double>(lof.dof_lack);
  lof.reduced_chi2 = pure_var > 0 ? lack / pure_var : std::numeric_limits<double>::infinity();
  lof.p_value = pure_var > 0 ? f_upper_tail(lof.reduced_chi2, static_cast<double>(lof.dof_lack),
                                            static_cast<double>(lof.dof_pure))
                             : 0.0;
  lof.misfit_rms = std::sqrt(ss_lack / static_cast<double>(count));
  lof.misfit_ratio = pure_var > 0 ? lof.misfit_rms / lof.replicate_sd : std::numeric_limits<double>::infinity();
  // The worst conditions: the group the curve misses most, with its neighbours missed on the same
  // side by at least half as much.
  std::size_t top = 0;
  for (std::size_t i = 1; i < g; ++i)
    if (std::abs(miss[i]) > std::abs(miss[top])) top = i;
  auto alike = [&](std::size_t i) {
    return std::abs(miss[i]) >= 0.5 * std::abs(miss[top]) && (miss[i] > 0) == (miss[top] > 0);
  };
  std::size_t first = top, last = top;
  while (first > 0 && alike(first - 1)) --first;
  while (last + 1 < g && alike(last + 1)) ++last;
  const std::string side = miss[top] > 0 ? "the readings above it" : "the readings below it";
  const std::string by = fmt(std::abs(miss[top]) * words.unit_scale, 3) + (words.unit.empty() ? "" : " " + words.unit);
  if (words.conditions.empty()) {
    lof.worst = groups[top]->label + ": the curve misses by " + by + ", " + side;
  } else {
    const std::string a = fmt(groups[first]->condition * words.condition_scale, 3);
    const std::string b = fmt(groups[last]->condition * words.condition_scale, 3);
    std::string what = words.conditions;  // "distances", one: "distance"
    if (first == last && !what.empty() && what.back() == 's') what.pop_back();
    lof.worst = what + " " + a + (first == last ? "" : "\u2013" + b) +
                (words.condition_unit.empty() ? "" : " " + words.condition_unit) + ": the curve misses by " + by + ", " + side;
  }
  return lof;
}

std::string misfit_verdict(const LackOfFit& lof, double r2) {
  if (lof.tested && lof.misfit_ratio > kMisfitFailRatio)
    return "the curve misses its data by " + fmt(lof.misfit_ratio, 3) + " times the replicates' own sd (limit " +
           fmt(kMisfitFailRatio) + "); worst: " + lof.worst;
  // A low R^2 alone may be noise over a narrow range of conditions, not a misfit: it stops the
  // calibration where the replicates show the curve missing too, or where the curve does worse
  // than a flat line; otherwise it is a warning (misfit_warning).
  if (std::isfinite(r2) && r2 < kMisfitR2Floor && lof.tested && lof.misfit_ratio > kMisfitWarnRatio)
    return "R^2 = " + fmt(r2, 3) + " is below the floor of " + fmt(kMisfitR2Floor) + " and the curve misses the replicates by " +
           fmt(lof.misfit_ratio, 3) + " times their sd; worst: " + lof.worst;
  if (std::isfinite(r2) && r2 < kMisfitR2Negative)
    return "R^2 = " + fmt(r2, 3) + ": the curve does worse than a flat line through the readings' mean";
  return "";
}

std::string misfit_warning(const LackOfFit& lof, double r2) {
  if (!std::isfinite(r2) || r2 >= kMisfitR2Floor || !misfit_verdict(lof, r2).empty()) return "";
  return "R^2 = " + fmt(r2, 3) + " is below " + fmt(kMisfitR2Floor) +
         (lof.tested ? ", but the curve misses the replicates by only " + fmt(lof.misfit_ratio, 3) +
                           " times their sd: the readings vary mostly by their noise over these conditions"
                     : "; the lack-of-fit test against the replicates was not run (" +
                           (lof.why_not.empty() ? std::string("no repeated readings under the same conditions") : lof.why_not) +
                           "), so noise cannot be told from misfit");
}

// ================================================================================================
// Several robots
// ================================================================================================

std::vector<RobotSpread> robot_spread(const std::vector<const FitResult*>& robots) {
  std::vector<RobotSpread> out;
  if (robots.empty() || robots.front() == nullptr) return out;
  for (const ParameterEstimate& first : robots.front()->parameters) {
    std::vector<double> x, se;
    for (const FitResult* r : robots) {
      if (r == nullptr || !r->usable) continue;
      const double v = r->value(first.name), e = r->std_error(first.name);
      if (std::isfinite(v) && std::isfinite(e) && e > 0) {
        x.push_back(v);
        se.push_back(e);
      }
    }
    if (x.size() < 2) continue;
    RobotSpread s;
    s.parameter = first.name;
    double sw = 0, swx = 0, mean = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      sw += 1 / (se[i] * se[i]);
      swx += x[i] / (se[i] * se[i]);
      mean += x[i];
    }
    mean /= static_cast<double>(x.size());
    const double xw = swx / sw;
    double ss = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      s.q += (x[i] - xw) * (x[i] - xw) / (se[i] * se[i]);
      ss += (x[i] - mean) * (x[i] - mean);
    }
    s.spread_sd = std::sqrt(ss / static_cast<double>(x.size() - 1));
    s.dof = x.size() - 1;
    s.p_value = chi2_upper_tail(s.q, static_cast<double>(s.dof));
    s.exceeds = s.p_value < kRobotSpreadP;
    out.push_back(s);
  }
  return out;
}

}  // namespace epuck2::fit
