#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <numeric>

#include "epuck2/calibrate/battery.hpp"
#include "epuck2/calibrate/charge_map.hpp"
#include "epuck2/fit/fit_curve.hpp"
#include "epuck2/models/battery_simulation.hpp"

namespace epuck2::calibrate {

using namespace epuck2::fit;  // the engine (lib/fit)

namespace mb = models::battery;

namespace {

// ---- models in scaled time u = t / lifetime (the same formulas lib/models runs) ----

// charge(u) = p3 u^3 + p2 u^2 + p1 u + p0
struct CubicInScaledTime {
  static constexpr int kParameters = 4;
  static constexpr bool kLinearInParameters = true;
  template <typename T>
  T operator()(const T* p, double u) const {
    return mb::cubic_charge(p, u);
  }
};

// charge(u) = p0 + p1 u
struct LineInScaledTime {
  static constexpr int kParameters = 2;
  static constexpr bool kLinearInParameters = true;
  template <typename T>
  T operator()(const T* p, double u) const {
    return mb::line_charge(p[0], p[1], u);
  }
};

// Knots (0, 1), (p0, p2), (p1, p3), (last_knot_u, p4): the Approximated model's three sloped
// segments, starting from full charge as the plug-in's M1 does.
struct PolylineInScaledTime {
  static constexpr int kParameters = 5;
  double last_knot_u;
  template <typename T>
  T operator()(const T* p, double u) const {
    const T x[4] = {T(0.0), p[0], p[1], T(last_knot_u)};
    const T y[4] = {T(1.0), p[2], p[3], p[4]};
    return mb::polyline_charge(x, y, 4, u);
  }
};

double mean_of(const std::vector<double>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

double std_error_of_mean(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = mean_of(v);
  double ss = 0;
  for (double x : v) ss += (x - m) * (x - m);
  return std::sqrt(ss / static_cast<double>(v.size() - 1) / static_cast<double>(v.size()));
}

// Rescale parameter k of a fit by factor[k] (values, std errors, covariance).
void rescale(FitResult& r, const std::vector<double>& factor, const std::vector<std::string>& names) {
  for (std::size_t k = 0; k < r.parameters.size(); ++k) {
    r.parameters[k].value *= factor[k];
    r.parameters[k].std_error *= std::abs(factor[k]);
    r.parameters[k].name = names[k];
  }
  if (r.covariance.size() > 0)
    for (Eigen::Index i = 0; i < r.covariance.rows(); ++i)
      for (Eigen::Index j = 0; j < r.covariance.cols(); ++j)
        r.covariance(i, j) *= factor[static_cast<std::size_t>(i)] * factor[static_cast<std::size_t>(j)];
}

// Least squares for the knot values (y1, y2, y3) with the knot positions fixed: the profile that
// the breakpoint grid search minimises. Returns the RSS; fills y.
double polyline_profile(const std::vector<double>& u, const std::vector<double>& y, double x1, double x2,
                        double x3, double out[3]) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  const double xs[4] = {0.0, x1, x2, x3};
  for (std::size_t i = 0; i < u.size(); ++i) {
    // weights of knots 0..3 for linear interpolation / extrapolation at u[i]
    int seg = 0;
    if (u[i] > x1) seg = 1;
    if (u[i] > x2) seg = 2;
    const double w = (u[i] - xs[seg]) / (xs[seg + 1] - xs[seg]);
    double phi[4] = {0, 0, 0, 0};
    phi[seg] = 1 - w;
    phi[seg + 1] = w;
    const double target = y[i] - phi[0] * 1.0;  // knot 0 is fixed at (0, 1)
    const Eigen::Vector3d f(phi[1], phi[2], phi[3]);
    A += f * f.transpose();
    b += f * target;
  }
  const Eigen::Vector3d sol = A.ldlt().solve(b);
  double rss = 0;
  for (std::size_t i = 0; i < u.size(); ++i) {
    int seg = 0;
    if (u[i] > x1) seg = 1;
    if (u[i] > x2) seg = 2;
    const double w = (u[i] - xs[seg]) / (xs[seg + 1] - xs[seg]);
    const double ys[4] = {1.0, sol(0), sol(1), sol(2)};
    const double e = y[i] - ((1 - w) * ys[seg] + w * ys[seg + 1]);
    rss += e * e;
  }
  for (int k = 0; k < 3; ++k) out[k] = sol(k);
  return rss;
}

// The autocorrelation correction of a fit in scaled time (before its values are rescaled to
// seconds): its residuals in row order, each run its own series.
template <class Model>
AutocorrelationCorrection run_autocorrelation(const Model& model, const FitResult& f, const std::vector<double>& u,
                                              const std::vector<double>& y, const std::vector<int>& run_of) {
  if (!f.usable) {
    AutocorrelationCorrection a;
    a.why_not = "the fit is not usable";
    return a;
  }
  const std::vector<double> p = f.values();
  std::vector<double> e(u.size());
  for (std::size_t i = 0; i < u.size(); ++i) e[i] = y[i] - model(p.data(), u[i]);
  return autocorrelation_correction(e, run_of);
}

double mse_of(const std::vector<double>& t, const std::vector<double>& y, const std::function<double(double)>& f) {
  double ss = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double e = y[i] - f(t[i]);
    ss += e * e;
  }
  return t.empty() ? 0.0 : ss / static_cast<double>(t.size());
}

}  // namespace

double ModelMse::get(mb::Model m) const {
  switch (m) {
    case mb::Model::simple: return simple;
    case mb::Model::linear: return linear;
    case mb::Model::cubic: return cubic;
    case mb::Model::approximated: return approximated;
  }
  return 0;
}

double& ModelMse::get(mb::Model m) {
  switch (m) {
    case mb::Model::simple: return simple;
    case mb::Model::linear: return linear;
    case mb::Model::cubic: return cubic;
    case mb::Model::approximated: break;
  }
  return approximated;
}

std::vector<BatteryRun> battery_runs(const std::vector<logs::Log>& all) { return battery_runs(all, nullptr, nullptr); }

std::vector<BatteryRun> battery_runs(const std::vector<logs::Log>& all, const ChargeMap* map, ChargeConversionReport* report) {
  std::vector<BatteryRun> runs;
  for (const logs::Log& log : all) {
    if (log.kind != logs::Kind::battery)
      throw logs::InputError(log.path, 0, 0, "is not a battery log (time_s, speed_cm_s, charge)");
    BatteryRun run;
    run.path = log.path;
    run.robot = log.robot;
    run.time_s = log.col("time_s");
    run.line = log.line_of_row;
    const auto& speed = log.col("speed_cm_s");
    if (log.has("charge")) {
      run.charge = log.col("charge");
    } else if (map == nullptr) {
      throw logs::InputError(
          log.path, log.header_line, 1,
          "no 'charge' column, only 'voltage_v': a voltage-only log needs a voltage->charge map; give one with "
          "--charge-map FILE (a battery coefficient file written by `epuck2-fit battery -o` from logs with both "
          "charge and voltage_v, or a map file, docs/coefficient-files.md#charge-map), or give such logs in the same call");
    } else {
      const auto& volts = log.col("voltage_v");
      run.charge_from_voltage = true;
      run.charge.resize(volts.size());
      for (std::size_t i = 0; i < volts.size(); ++i) {
        if (!covers_speed(*map, speed[i])) {
          char msg[240];
          std::snprintf(msg, sizeof msg,
                        "column 'speed_cm_s': speed %g cm/s is outside the charge map's load term (%g..%g cm/s): its voltage "
                        "sag is not known there",
                        std::abs(speed[i]), map->load_speeds_cm_s.front(), map->load_speeds_cm_s.back());
          throw logs::InputError(log.path, log.line_of_row[i], log.column_of(i, "speed_cm_s"), msg);
        }
        const ChargeConversion c = convert_voltage(*map, volts[i], speed[i]);
        run.charge[i] = c.charge;
        if (report != nullptr && c.side != 0) {
          (c.side < 0 ? report->below_range : report->above_range) += 1;
          if (report->clamped.size() < 10) {
            char where[96];
            // With a load term the range is of the corrected voltage: both are said.
            if (c.corrected_v != volts[i])
              std::snprintf(where, sizeof where, " (%.4f V; %.4f V with the load offset at %g cm/s)", volts[i], c.corrected_v,
                            std::abs(speed[i]));
            else
              std::snprintf(where, sizeof where, " (%.4f V)", volts[i]);
            report->clamped.push_back(log.path + ":" + std::to_string(log.line_of_row[i]) + where);
          }
        }
      }
      if (report != nullptr) {
        report->logs += 1;
        report->rows += volts.size();
      }
    }
    constexpr double kSameSpeed_cm_s = 0.005;  // speeds are logged to 0.01 cm/s at best
    run.speed_cm_s = std::abs(speed.front());
    for (std::size_t i = 1; i < speed.size(); ++i) {
      if (std::abs(std::abs(speed[i]) - run.speed_cm_s) > kSameSpeed_cm_s)
        throw logs::InputError(log.path, log.line_of_row[i], log.column_of(i, "speed_cm_s"),
                               "column 'speed_cm_s': the speed changes from " + std::to_string(run.speed_cm_s) +
                                   " to " + std::to_string(std::abs(speed[i])) +
                                   "; battery calibration expects one speed per run (diagnose and simulate accept profiles)");
    }
    run.speed_cm_s = std::round(run.speed_cm_s * 100.0) / 100.0;
    run.lifetime_s = run.time_s.back();
    if (run.lifetime_s <= 0)
      throw logs::InputError(log.path, log.line_of_row.back(), log.column_of(log.rows() - 1, "time_s"),
                             "column 'time_s': the run must last longer than 0 s (the last row is the stop time)");
    for (std::size_t i = 0; i < speed.size(); ++i) run.profile.push_back({run.time_s[i], std::abs(speed[i])});
    runs.push_back(std::move(run));
  }
  return runs;
}

double analytic_charge(const SpeedFit& s, const BatteryFit& all, mb::Model m, double t_s) {
  switch (m) {
    case mb::Model::simple: {
      const double slope = s.speed_cm_s == 0 ? all.simple_static_slope_per_s : all.simple_moving_slope_per_s;
      return std::max(0.0, 1.0 + slope * t_s);
    }
    case mb::Model::linear: return std::max(0.0, 1.0 + s.linear_slope_per_s * t_s);
    case mb::Model::cubic: {
      const double p[4] = {s.cubic.value("d"), s.cubic.value("c"), s.cubic.value("b"), s.cubic.value("a")};
      return mb::cubic_charge(p, t_s);
    }
    case mb::Model::approximated: {
      // The model as written (segments M1..M4): the three fitted lines up to lifetime - 1 s,
      // then M4, the 1-second drop from y3 to 0 at the lifetime, and 0 after it -- not the
      // third line extended past the lifetime (a run that outlasts the mean lifetime would be
      // compared with a charge below 0, which no model the tool writes gives).
      const auto& pw = s.piecewise;
      const double L = s.lifetime_s;
      if (t_s >= L) return 0.0;
      if (t_s > L - 1.0) return std::max(0.0, pw.value("y3") * (L - t_s));
      const double x[4] = {0.0, pw.value("x1_s"), pw.value("x2_s"), L - 1.0};
      const double y[4] = {1.0, pw.value("y1"), pw.value("y2"), pw.value("y3")};
      return mb::polyline_charge(x, y, 4, t_s);
    }
  }
  return 0;
}

namespace {
/// The reading noise's robust sd from the absolute residuals `dev` (reordered): 1.4826 times
/// their median (the normal's MAD factor, 1 / Phi^-1(3/4)).
double mad_sd(std::vector<double>& dev) {
  if (dev.empty()) return 0.0;
  std::nth_element(dev.begin(), dev.begin() + static_cast<std::ptrdiff_t>(dev.size() / 2), dev.end());
  return 1.482602218505602 * dev[dev.size() / 2];
}
}  // namespace

std::string lifetime_no_error_why(const SpeedFit& s) {
  if (s.runs >= 2 && s.lifetime_std_error_s > 0) return "";
  return s.runs < 2 ? "the end of the only run's log: no spread to estimate an error from" : "the runs end at the same time";
}

std::string simple_static_no_error_why(const BatteryFit& f) {
  for (const SpeedFit& s : f.speeds)
    if (s.speed_cm_s == 0) {
      if (s.runs >= 2 && s.lifetime_std_error_s > 0) return "";
      return s.runs < 2 ? "one run at 0 cm/s" : "the " + std::to_string(s.runs) + " runs at 0 cm/s end at the same time";
    }
  return "no run at 0 cm/s: m0 is taken as m1";
}

std::string simple_moving_no_error_why(const BatteryFit& f) {
  std::size_t moving = 0, single = 0, together = 0;
  for (const SpeedFit& s : f.speeds) {
    if (s.speed_cm_s == 0) continue;
    ++moving;
    if (s.runs < 2)
      ++single;
    else if (!(s.lifetime_std_error_s > 0))
      ++together;
  }
  if (moving == 0) return "no run while moving";
  if (single + together < moving) return "";
  if (together == 0) return "one run a speed";
  if (single == 0) return "at every speed the runs end at the same time";
  return "at every speed one run, or runs ending at the same time";
}

BatteryFit fit_battery(const std::vector<BatteryRun>& runs, const FitOptions& options, double reject_sd) {
  BatteryFit out;
  std::map<long, std::vector<const BatteryRun*>> by_speed;  // key: speed in 0.01 cm/s
  for (const BatteryRun& r : runs) {
    by_speed[std::lround(r.speed_cm_s * 100.0)].push_back(&r);
    out.sources.push_back(r.path);
  }
  for (const auto& [key, group] : by_speed) {
    SpeedFit s;
    s.speed_cm_s = static_cast<double>(key) / 100.0;
    s.runs = group.size();
    std::vector<double> lifetimes, t, y;
    std::vector<std::string> where;
    std::vector<int> run_of;  // per row: its run (the residuals' series, for the autocorrelation)
    for (const BatteryRun* r : group) {
      lifetimes.push_back(r->lifetime_s);
      t.insert(t.end(), r->time_s.begin(), r->time_s.end());
      y.insert(y.end(), r->charge.begin(), r->charge.end());
      run_of.insert(run_of.end(), r->time_s.size(), static_cast<int>(lifetimes.size()));
      for (std::size_t i = 0; i < r->time_s.size(); ++i)
        where.push_back(r->path + ":" + (i < r->line.size() ? std::to_string(r->line[i]) : "?"));
    }
    s.lifetime_s = mean_of(lifetimes);
    s.lifetime_std_error_s = std_error_of_mean(lifetimes);
    const double L = s.lifetime_s;
    std::vector<double> u(t.size());
    for (std::size_t i = 0; i < t.size(); ++i) u[i] = t[i] / L;

    // Cubic, in scaled time, back to seconds. Robust: readings far from it (a wild reading of
    // the charge) leave every model at this speed, and the cubic is fitted again without them.
    // Cheap when there are none: one pass over the residuals.
    s.cubic = fit_curve(CubicInScaledTime{}, u, y, {{"d", 1.0}, {"c", -1.0}, {"b", 0.0}, {"a", 0.0}}, options);
    for (int pass = 0; pass < 5 && reject_sd > 0 && s.cubic.usable; ++pass) {
      const std::vector<double> p = s.cubic.values();
      std::vector<double> r(u.size()), dev(u.size());
      for (std::size_t i = 0; i < u.size(); ++i) {
        r[i] = y[i] - CubicInScaledTime{}(p.data(), u[i]);
        dev[i] = std::abs(r[i]);
      }
      s.noise_sd = mad_sd(dev);
      const double limit = reject_sd * s.noise_sd;
      std::size_t kept = 0;
      for (std::size_t i = 0; i < u.size(); ++i) {
        if (std::abs(r[i]) > limit && limit > 0) {
          s.outliers.push_back(where[i]);
          continue;
        }
        u[kept] = u[i];
        t[kept] = t[i];
        y[kept] = y[i];
        where[kept] = where[i];
        run_of[kept] = run_of[i];
        ++kept;
      }
      if (kept == u.size()) break;
      u.resize(kept);
      t.resize(kept);
      y.resize(kept);
      where.resize(kept);
      run_of.resize(kept);
      s.cubic = fit_curve(CubicInScaledTime{}, u, y, {{"d", 1.0}, {"c", -1.0}, {"b", 0.0}, {"a", 0.0}}, options);
    }
    // --least-squares (no rejection pass): the same robust sd of the cubic's residuals, so that
    // the file's reading noise does not depend on whether outliers were looked for.
    if (!(reject_sd > 0) && s.cubic.usable) {
      const std::vector<double> p = s.cubic.values();
      std::vector<double> dev(u.size());
      for (std::size_t i = 0; i < u.size(); ++i) dev[i] = std::abs(y[i] - CubicInScaledTime{}(p.data(), u[i]));
      s.noise_sd = mad_sd(dev);
    }
    s.observations = t.size();
    // Lack of fit: the runs' readings at the same time are replicates (the calibration protocol
    // logs every run on one clock); a time with one reading is no replicate and is not tested.
    if (s.cubic.usable) {
      const std::vector<double> p = s.cubic.values();
      std::map<long long, fit::ReplicateGroup> at;
      for (std::size_t i = 0; i < u.size(); ++i) {
        fit::ReplicateGroup& g = at[std::llround(t[i] * 1e3)];
        g.condition = t[i];
        g.readings.push_back(y[i]);
        g.predictions.push_back(CubicInScaledTime{}(p.data(), u[i]));
      }
      std::vector<fit::ReplicateGroup> groups;
      for (auto& [ms, g] : at) groups.push_back(std::move(g));
      s.cubic_lack_of_fit = fit::lack_of_fit(groups, 4, fit::MisfitWords{"times", "s", "charge", 1.0, 1.0});
    }
    s.cubic_autocorrelation = run_autocorrelation(CubicInScaledTime{}, s.cubic, u, y, run_of);
    rescale(s.cubic, {1.0, 1.0 / L, 1.0 / (L * L), 1.0 / (L * L * L)}, {"d", "c", "b", "a"});

    s.free_line = fit_curve(LineInScaledTime{}, u, y, {{"intercept", 1.0}, {"slope_per_s", -1.0}}, options);
    s.free_line_autocorrelation = run_autocorrelation(LineInScaledTime{}, s.free_line, u, y, run_of);
    rescale(s.free_line, {1.0, 1.0 / L}, {"intercept", "slope_per_s"});

    s.linear_slope_per_s = mb::lifetime_slope_per_s(L);
    s.linear_slope_std_error = s.lifetime_std_error_s / (L * L);

    // Approximated: the two breakpoints by a coarse-then-fine grid search on the profile of the
    // linear sub-problem (knot values given breakpoints), then all five refined jointly in Ceres.
    const double last_u = (L - 1.0) / L;
    double best_rss = std::numeric_limits<double>::infinity();
    double best[5] = {0.25, 0.7, 0.7, 0.5, 0.2};
    // Evaluates one pair of breakpoints and keeps the best.
    auto consider = [&](double x1, double x2) {
      if (x1 <= 0 || x2 <= x1 || x2 >= last_u) return;
      double ys[3];
      const double rss = polyline_profile(u, y, x1, x2, last_u, ys);
      if (rss < best_rss) {
        best_rss = rss;
        best[0] = x1;
        best[1] = x2;
        best[2] = ys[0];
        best[3] = ys[1];
        best[4] = ys[2];
      }
    };
    constexpr double kCoarseStep = 0.05, kFineStep = 0.01;
    for (double x1 = kCoarseStep; x1 <= last_u - kCoarseStep; x1 += kCoarseStep)
      for (double x2 = x1 + kCoarseStep; x2 <= last_u - 0.5 * kCoarseStep; x2 += kCoarseStep) consider(x1, x2);
    const double c1 = best[0], c2 = best[1];
    for (double x1 = c1 - kCoarseStep; x1 <= c1 + kCoarseStep + 1e-12; x1 += kFineStep)
      for (double x2 = c2 - kCoarseStep; x2 <= c2 + kCoarseStep + 1e-12; x2 += kFineStep) consider(x1, x2);
    s.piecewise = fit_curve(PolylineInScaledTime{last_u}, u, y,
                            {{"x1_s", best[0]}, {"x2_s", best[1]}, {"y1", best[2]}, {"y2", best[3]}, {"y3", best[4]}},
                            options);
    // The knots' charges y1..y3 belong in [0, 1], the range every reader of the segments checks
    // (lib/coefficients battery_tables.cpp). A run that reads exactly 1.000 at its start (a full
    // gauge) puts y1 a rounding above 1 (the least squares of readings all 1), and no reader
    // would take the file: a knot outside the range is fitted again with y1..y3 bounded to it
    // (from the free solution brought within), the knot at the bound held there. Only then: a
    // bounded solve stops on the projected gradient, a little earlier than the free one, whose
    // solution stands where it is in range.
    bool out_of_range = false;
    for (const char* name : {"y1", "y2", "y3"})
      out_of_range = out_of_range || (s.piecewise.usable && !(s.piecewise.value(name) >= 0.0 && s.piecewise.value(name) <= 1.0));
    if (out_of_range) {
      const std::vector<double> free = s.piecewise.values();
      std::vector<Parameter> knots{free_parameter("x1_s", free[0]), free_parameter("x2_s", free[1])};
      for (const char* name : {"y1", "y2", "y3"}) {
        Parameter p = free_parameter(name, std::clamp(free[knots.size()], 0.0, 1.0));
        p.lower = 0.0;
        p.upper = 1.0;
        knots.push_back(p);
      }
      FitResult bounded = fit_curve(PolylineInScaledTime{last_u}, u, y, knots, options);
      if (bounded.usable) s.piecewise = std::move(bounded);
    }
    s.piecewise_autocorrelation = run_autocorrelation(PolylineInScaledTime{last_u}, s.piecewise, u, y, run_of);
    rescale(s.piecewise, {L, L, 1.0, 1.0, 1.0}, {"x1_s", "x2_s", "y1", "y2", "y3"});

    // Two runs a speed (the protocol) are too few for errors robust to a misfit that lasts a whole
    // run: the AR(1) factor corrects them.
    for (auto [fit_of, a] : {std::pair{&s.cubic, &s.cubic_autocorrelation}, std::pair{&s.free_line, &s.free_line_autocorrelation},
                             std::pair{&s.piecewise, &s.piecewise_autocorrelation}}) {
      apply_ar1(*a, *fit_of);
      a->cluster_why_not = std::to_string(s.runs) + " runs: too few to estimate the spread between runs (cluster-robust needs " +
                           std::to_string(kMinClusters) + ")";
      if (s.runs >= kMinClusters) a->cluster_why_not = "not computed for the battery's fits (the AR(1) factor is used)";
    }
    // The plug-in's segment format M1..M4 (M4: the 1-second drop to 0 at the lifetime).
    const double kx[5] = {0.0, s.piecewise.value("x1_s"), s.piecewise.value("x2_s"), L - 1.0, L};
    const double ky[5] = {1.0, s.piecewise.value("y1"), s.piecewise.value("y2"), s.piecewise.value("y3"), 0.0};
    for (int k = 0; k < mb::kSegmentCount; ++k) {
      const double m = (ky[k + 1] - ky[k]) / (kx[k + 1] - kx[k]);
      s.segments[static_cast<std::size_t>(k)] = mb::Segment{ky[k] - m * kx[k], m, kx[k], kx[k + 1], ky[k], ky[k + 1]};
    }
    out.speeds.push_back(std::move(s));
  }

  // Simple: m0 from the static robot, m1 from the mean lifetime of the moving speeds.
  std::vector<double> moving;
  double moving_var = 0;
  for (const SpeedFit& s : out.speeds) {
    if (s.speed_cm_s == 0) {
      out.simple_static_slope_per_s = mb::lifetime_slope_per_s(s.lifetime_s);
      out.simple_static_std_error = s.lifetime_std_error_s / (s.lifetime_s * s.lifetime_s);
    } else {
      moving.push_back(s.lifetime_s);
      moving_var += s.lifetime_std_error_s * s.lifetime_std_error_s;
    }
  }
  if (!moving.empty()) {
    const double mean_life = mean_of(moving);
    out.simple_moving_slope_per_s = mb::lifetime_slope_per_s(mean_life);
    const double se_mean = std::sqrt(moving_var) / static_cast<double>(moving.size());
    out.simple_moving_std_error = se_mean / (mean_life * mean_life);
  }
  if (out.simple_static_slope_per_s == 0) out.simple_static_slope_per_s = out.simple_moving_slope_per_s;

  // What the logs leave weak, said plainly.
  std::vector<double> single_run;
  bool at_rest = false;
  for (const SpeedFit& s : out.speeds) {
    at_rest = at_rest || s.speed_cm_s == 0;
    if (s.runs == 1) single_run.push_back(s.speed_cm_s);
    if (s.runs > 1 && s.cubic_lack_of_fit.replicates_agree_exactly)
      out.warnings.push_back(speeds_text({s.speed_cm_s}) + " cm/s: the " + std::to_string(s.runs) +
                             " runs read the same charge at every time: the cubic's lack of fit is not tested (" +
                             s.cubic_lack_of_fit.why_not + ")");
    for (const auto& [name, fit] : {std::pair<const char*, const FitResult*>{"cubic", &s.cubic}, {"approximated", &s.piecewise}}) {
      const std::size_t p = fit->parameters.empty() ? (std::string(name) == "cubic" ? 4u : 5u) : fit->parameters.size();
      if (!fit->usable || s.observations >= kBatteryRowsPerParameter * p) continue;
      char text[240];
      std::snprintf(text, sizeof text,
                    "%g cm/s: %zu rows for the %s model's %zu parameters (fewer than %zu per parameter): its fit is barely "
                    "determined",
                    s.speed_cm_s, s.observations, name, p, kBatteryRowsPerParameter);
      out.warnings.push_back(text);
    }
  }
  // Tables the plug-in's own arithmetic cannot run (Cardano's root clamped at 0 from the first
  // tick): said here, where they are written, as codegen, table5 and the ARGoS battery say it.
  std::vector<mb::ArgosCubicStall> stalls;
  for (const SpeedFit& s : out.speeds) {
    if (!s.cubic.usable) continue;
    const mb::CubicRow row{s.cubic.value("d"), s.cubic.value("c"), s.cubic.value("b"), s.cubic.value("a"), s.lifetime_s};
    const mb::ArgosCubicRun r = mb::argos_cubic_run(row);
    if (!r.discharges) stalls.push_back({s.speed_cm_s, r});
  }
  if (!stalls.empty()) out.warnings.push_back(mb::argos_cubic_stall_text(stalls));
  if (!single_run.empty())
    out.warnings.push_back("one run at " + speeds_text(single_run) +
                           " cm/s: the lifetime's standard error needs two runs or more (written 0 there)");
  if (!out.speeds.empty() && !at_rest)
    out.warnings.push_back("no run at 0 cm/s: the Simple model's static slope m0 is taken from the moving runs (m1)");
  if (!out.speeds.empty() && moving.empty())
    out.warnings.push_back("no run while moving: the Simple model's moving slope m1 is not determined (written 0)");

  // Analytic MSE per speed and model, and the averages (Table 5 "analytic").
  for (SpeedFit& s : out.speeds) {
    std::vector<double> t, y;
    for (const BatteryRun& r : runs) {
      if (std::lround(r.speed_cm_s * 100.0) != std::lround(s.speed_cm_s * 100.0)) continue;
      t.insert(t.end(), r.time_s.begin(), r.time_s.end());
      y.insert(y.end(), r.charge.begin(), r.charge.end());
    }
    for (mb::Model m : mb::kAllModels)
      s.mse.get(m) = mse_of(t, y, [&](double ts) { return analytic_charge(s, out, m, ts); });
  }
  for (mb::Model m : mb::kAllModels) {
    double sum = 0;
    for (const SpeedFit& s : out.speeds) sum += s.mse.get(m);
    out.mse.get(m) = out.speeds.empty() ? 0.0 : sum / static_cast<double>(out.speeds.size());
  }

  // Tables when every integer speed 0..15 is covered.
  bool complete = out.speeds.size() == mb::kSpeedCount;
  for (std::size_t i = 0; complete && i < out.speeds.size(); ++i)
    complete = std::lround(out.speeds[i].speed_cm_s * 100.0) == static_cast<long>(i) * 100;
  if (complete) out.tables = tables_from_fit(out);
  return out;
}

std::string pooled_robots_warning(const std::vector<BatteryRun>& runs) {
  std::vector<std::string> robots;
  for (const auto& r : runs)
    if (std::find(robots.begin(), robots.end(), r.robot) == robots.end()) robots.push_back(r.robot);
  if (robots.size() < 2) return std::string();
  // Per speed (to 0.01 cm/s, as the fit groups runs) and robot: the sum and count of lifetimes.
  std::map<long, std::map<std::string, std::pair<double, int>>> lifetimes;
  for (const auto& r : runs) {
    auto& cell = lifetimes[std::lround(r.speed_cm_s * 100)][r.robot];
    cell.first += r.lifetime_s;
    ++cell.second;
  }
  double worst = 0;
  std::string worst_text;
  for (const auto& [speed, per_robot] : lifetimes) {
    if (per_robot.size() < 2) continue;
    double lo = std::numeric_limits<double>::infinity(), hi = 0;
    std::string text;
    for (const std::string& robot : robots) {
      const auto it = per_robot.find(robot);
      if (it == per_robot.end()) continue;
      const double mean = it->second.first / it->second.second;
      lo = std::min(lo, mean);
      hi = std::max(hi, mean);
      char part[64];
      std::snprintf(part, sizeof part, " %.0f s", mean);
      text += (text.empty() ? "" : ", ") + robot + part;
    }
    if (lo > 0 && hi / lo - 1 >= worst) {
      worst = hi / lo - 1;
      char at[32];
      std::snprintf(at, sizeof at, "%g cm/s: ", static_cast<double>(speed) / 100);
      worst_text = at + text;
    }
  }
  std::string names;
  for (const std::string& r : robots) names += (names.empty() ? "" : ", ") + r;
  std::string w = "the logs come from " + std::to_string(robots.size()) + " robots (" + names +
                  "), pooled: battery fits one table per speed over all their runs and does not fit or compare the robots one "
                  "by one (the file has no `robots` and no `robot_spread`)";
  if (!worst_text.empty()) {
    char pct[32];
    std::snprintf(pct, sizeof pct, "%.1f %%", 100 * worst);
    w += std::string("; their mean run lifetimes differ by up to ") + pct + " at one speed (" + worst_text + ")";
  }
  return w + ". --robot ID fits one robot's logs alone.";
}

SpeedCoverage speed_coverage(const BatteryFit& f) {
  SpeedCoverage c;
  std::vector<bool> seen(static_cast<std::size_t>(mb::kSpeedCount), false);
  for (const SpeedFit& s : f.speeds) {
    c.covered.push_back(s.speed_cm_s);
    const long centi = std::lround(s.speed_cm_s * 100.0);
    if (centi % 100 == 0 && centi >= 0 && centi / 100 < mb::kSpeedCount) seen[static_cast<std::size_t>(centi / 100)] = true;
    else c.other.push_back(s.speed_cm_s);
  }
  for (int s = 0; s < mb::kSpeedCount; ++s)
    if (!seen[static_cast<std::size_t>(s)]) c.missing.push_back(s);
  return c;
}

std::string speeds_text(const std::vector<double>& speeds) {
  if (speeds.empty()) return "none";
  std::string out;
  char buf[32];
  for (double s : speeds) {
    std::snprintf(buf, sizeof buf, "%g", s);
    out += (out.empty() ? "" : ", ") + std::string(buf);
  }
  return out;
}

mb::Tables tables_from_fit(const BatteryFit& fit) {
  mb::Tables t{};
  for (std::size_t s = 0; s < fit.speeds.size() && s < static_cast<std::size_t>(mb::kSpeedCount); ++s) {
    const SpeedFit& f = fit.speeds[s];
    t.cubic[s] = mb::CubicRow{f.cubic.value("d"), f.cubic.value("c"), f.cubic.value("b"), f.cubic.value("a"), f.lifetime_s};
    t.segments[s] = f.segments;
    t.linear_slope_per_s[s] = f.linear_slope_per_s;
    t.lifetime_s[s] = f.lifetime_s;
  }
  t.simple_static_slope_per_s = fit.simple_static_slope_per_s;
  t.simple_moving_slope_per_s = fit.simple_moving_slope_per_s;
  return t;
}

ModelMse simulated_mse(const std::vector<BatteryRun>& runs, const mb::Tables& tables, mb::Behaviour behaviour,
                       double dt_s) {
  ModelMse out;
  for (mb::Model m : mb::kAllModels) {
    std::map<long, std::pair<double, std::size_t>> per_speed;  // sum of squares, count
    for (const BatteryRun& r : runs) {
      const auto sim = mb::simulate_discharge(m, behaviour, tables, r.profile, dt_s, 1.0);
      auto& acc = per_speed[std::lround(r.speed_cm_s * 100.0)];
      for (std::size_t i = 0; i < r.time_s.size(); ++i) {
        auto k = static_cast<std::size_t>(std::llround(r.time_s[i] / dt_s));
        k = std::min(k, sim.size() - 1);
        const double e = r.charge[i] - sim[k].charge;
        acc.first += e * e;
        acc.second += 1;
      }
    }
    double sum = 0;
    for (const auto& [speed, acc] : per_speed) sum += acc.first / static_cast<double>(acc.second);
    out.get(m) = per_speed.empty() ? 0.0 : sum / static_cast<double>(per_speed.size());
  }
  return out;
}

}  // namespace epuck2::calibrate
