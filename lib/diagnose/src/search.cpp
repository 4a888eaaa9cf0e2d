// The diagnosis's search: recalibration, greedy forward search over the catalogue's effects with
// BIC and held-out error, residual structure (docs/diagnose.md, steps 2 to 5), on the joint-fit
// engine (engine_detail.hpp).
#include <algorithm>

#include "engine_detail.hpp"

namespace epuck2::diagnose {

using namespace engine_detail;  // the engine and the residual-structure scoring

namespace {

std::vector<NamedValue> named(const Problem& p, const Engine::Fitted& f, const std::vector<int>& which) {
  std::vector<NamedValue> out;
  for (int j : which) {
    const auto& e = f.result.parameters.size() > static_cast<std::size_t>(j) ? f.result.parameters[static_cast<std::size_t>(j)]
                                                                             : ParameterEstimate{};
    out.push_back({p.params[static_cast<std::size_t>(j)].name, f.values[static_cast<std::size_t>(j)], e.std_error,
                   std::isfinite(e.std_error) ? std::string() : e.std_error_why});
  }
  return out;
}

/// The statistics of a fit to every residual (fit::FitStatistics): its RSS over the weighted
/// residuals, and R^2 against the readings' spread about their channel's mean, weighted alike.
fit::FitStatistics all_rows_statistics(const Engine& engine, const Problem& p, const Engine::Fitted& f) {
  const std::size_t C = p.channel_names.size();
  std::vector<double> sum(C, 0.0), count(C, 0.0);
  for (std::size_t i = 0; i < engine.size(); ++i) {
    const std::size_t c = static_cast<std::size_t>(p.channel[i]);
    sum[c] += p.y[i];
    count[c] += 1;
  }
  double tss = 0;
  for (std::size_t i = 0; i < engine.size(); ++i) {
    const std::size_t c = static_cast<std::size_t>(p.channel[i]);
    const double d = engine.error(i, sum[c] / count[c]);
    tss += d * d;
  }
  const double r2 = tss > 0 ? 1.0 - f.result.rss / tss : std::numeric_limits<double>::quiet_NaN();
  return fit::fit_statistics(f.result.observations, f.result.free_parameters, f.result.rss, r2);
}

/// Time series: the lag-1 autocorrelation of the final residuals within each log, per channel
/// (a row's residuals of one channel averaged: the drive's two encoders), and the largest
/// channel's correction; `channel` names it.
std::vector<double> log_of_rows(const Problem& p) {
  std::vector<double> log_of_row(p.rows, 0.0);
  for (std::size_t k = 0; k < p.covariates.size(); ++k)
    if (p.covariates[k].first == "log" && p.is_per_row(k) && p.covariates[k].second.size() == p.rows) log_of_row = p.covariates[k].second;
  return log_of_row;
}

fit::AutocorrelationCorrection residual_autocorrelation(const Engine& engine, const Problem& p,
                                                        const std::vector<double>& values, std::string& channel) {
  const std::vector<double> log_of_row = log_of_rows(p);
  const std::vector<double> r = engine.residuals(values);
  fit::AutocorrelationCorrection best;
  best.why_not = "no channel has neighbouring residuals";
  for (std::size_t c = 0; c < p.channel_names.size(); ++c) {
    std::vector<double> e;
    std::vector<int> series;
    double sum = 0;
    std::size_t count = 0, last_row = 0;
    bool open = false;
    auto flush = [&] {
      if (!open) return;
      e.push_back(sum / static_cast<double>(count));
      series.push_back(static_cast<int>(log_of_row[last_row]));
      sum = 0;
      count = 0;
      open = false;
    };
    for (std::size_t i = 0; i < engine.size(); ++i) {
      if (static_cast<std::size_t>(p.channel[i]) != c) continue;
      if (open && p.row[i] != last_row) flush();
      sum += r[i];
      ++count;
      last_row = p.row[i];
      open = true;
    }
    flush();
    const fit::AutocorrelationCorrection a = fit::autocorrelation_correction(e, series);
    if (a.computed && (!best.computed || a.factor > best.factor)) {
      best = a;
      channel = p.channel_names[c];
    }
  }
  return best;
}

/// The noise estimate and the fit depend on each other through the censored likelihood (a reading
/// on a rail weighs by how many noise sd the model lies from it): alternate until the estimate
/// moves by less than 2 %.
void settle_noise(Engine& engine, const std::vector<int>& free, Engine::Fitted& current) {
  constexpr int kMaxRounds = 8;
  constexpr double kSettled = 0.02;
  for (int k = 0; k < kMaxRounds; ++k) {
    const std::vector<double> sd = engine.noise_sd(current.values);
    bool settled = true;
    for (std::size_t c = 0; c < sd.size(); ++c) settled = settled && std::abs(sd[c] - engine.sigma()[c]) <= kSettled * engine.sigma()[c];
    engine.set_sigma(sd);
    current = engine.fit(free, current.values, engine.all(), true);
    if (settled) break;
  }
}

}  // namespace

namespace {

/// The reading's (channel 0's) mean squared residual at `values` over every row.
double reading_mse(const Engine& engine, const Problem& p, const std::vector<double>& values) {
  const auto r = engine.residuals(values);
  double sse = 0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < r.size(); ++i)
    if (p.channel.empty() || p.channel[i] == 0) {
      sse += r[i] * r[i];
      ++count;
    }
  return count ? sse / static_cast<double>(count) : 0.0;
}

/// The reading's (channel 0's) mean squared error of the model's reading itself at `values`:
/// clamp(latent) to its rails, no noise (what `simulate --like` writes without --noise), every row.
double reading_mse_plain(const Engine& engine, const Problem& p, const std::vector<double>& values) {
  std::vector<double> latent(engine.size());
  engine.latent(values.data(), latent.data());
  double sse = 0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < latent.size(); ++i)
    if (p.channel.empty() || p.channel[i] == 0) {
      const double e = engine.error(i, std::min(std::max(latent[i], engine.lo(i)), engine.hi(i)));
      sse += e * e;
      ++count;
    }
  return count ? sse / static_cast<double>(count) : 0.0;
}

/// One diagnosis, step by step (docs/diagnose.md): each step a method, in the order run() calls
/// them. The state between steps is the search's: the free parameters, the current fit and its
/// held-out error, and the effects kept in the order they were found.
class Diagnosis {
 public:
  explicit Diagnosis(const Options& options) : o_(options) {}

  Report run(const std::vector<logs::Log>& logs, std::vector<logs::Log>* owned) {
    if (!build_problem(logs, owned)) return std::move(report_);
    if (!enough_rows()) return std::move(report_);
    score_plugin();
    recalibrate();
    for (int step = 1; step <= o_.max_findings; ++step)
      if (!search_step(step)) break;
    name_findings();
    fit_final();
    const std::size_t warnings_before = report_.warnings.size();
    estimate_uncertainties();
    // Judged again without them: the final fit, its errors and their warnings; and again, until
    // every finding left is determined and within its physical range (a refit without one may
    // take another to its bound).
    bool left = false;
    while (!report_.findings.empty() && leave_out_undetermined()) {
      left = true;
      report_.warnings.resize(warnings_before);
      fit_final();
      estimate_uncertainties();
    }
    if (left) {
      for (const Finding& f : report_.possible)
        report_.warnings.push_back((f.outside_physical_range ? "not written: " : "possible, not determined: ") +
                                   f.cause + " (" + f.undetermined + "); left out of the final and the extended model");
    }
    score_shares();
    problem_->add_late_covariates();  // after the last fit: not held beside the fits' buffers
    score_residual_structure();
    keep_figure_data();
    return std::move(report_);
  }

 private:
  /// Step 0: wild readings leave, rails are counted, and the kind builds its problem.
  bool build_problem(const std::vector<logs::Log>& all_logs, std::vector<logs::Log>* owned) {
    if (all_logs.empty()) {
      report_.message = "no logs";
      return false;
    }
    report_.kind = all_logs.front().kind;
    report_.base_model = o_.base_model;
    for (const auto& l : all_logs) report_.rows += l.rows();
    // Wild readings (far from the others under the same conditions) would be "explained" by
    // whatever effect bends the curve towards them: they leave before anything is fitted.
    // (In place when the caller handed the logs over: a long log is not copied.)
    std::vector<WildReading> wild;
    std::vector<logs::Log> screened;
    progress("screening", 0, 0, 0, "");
    if (owned != nullptr) drop_wild_readings_in_place(*owned, &wild);
    else screened = drop_wild_readings(all_logs, &wild);
    const std::vector<logs::Log>& logs = owned != nullptr ? *owned : screened;
    for (const WildReading& w : wild) report_.outliers.push_back(w.where + ": " + w.why);
    if (!wild.empty())
      report_.warnings.push_back(std::to_string(wild.size()) + " wild readings left out before the diagnosis (listed under outliers).");
    report_.censored = readings_on_rails(logs);
    std::string why;
    problem_ = detail::make_problem(logs, o_, why);
    if (owned) std::vector<logs::Log>().swap(*owned);  // the problem holds what it needs
    if (!problem_) {
      report_.message = why;
      return false;
    }
    for (const auto& w : problem_->warnings) report_.warnings.push_back(w);
    for (const auto& w : problem_->left_out_on_rails) report_.outliers.push_back(w);
    report_.censored -= std::min(report_.censored, problem_->left_out_on_rails.size());
    engine_ = std::make_unique<Engine>(*problem_, o_);  // adds the covariate: effects
    searched_ = problem_->effects;
    if (!o_.effects.empty()) {
      // Only the effects asked for are searched (an unknown name is the caller's error).
      std::vector<detail::Effect> asked;
      std::set<std::string> seen;
      for (const auto& name : o_.effects) {
        if (!seen.insert(name).second) continue;  // named twice: searched once
        auto e = std::find_if(problem_->effects.begin(), problem_->effects.end(), [&](const detail::Effect& x) { return x.cause == name; });
        if (e == problem_->effects.end()) {
          std::string known;
          for (const auto& x : problem_->effects) known += (known.empty() ? "" : ", ") + x.cause;
          report_.message = "no effect '" + name + "' for these " + std::string(logs::to_string(report_.kind)) + " logs (they can show: " + known + ")";
          engine_.reset();
          problem_.reset();
          return false;
        }
        asked.push_back(*e);
      }
      searched_ = asked;
    }
    report_.residuals = engine_->size();
    report_.supported = true;
    for (const auto& e : searched_) report_.effects_considered.push_back(e.cause);
    return true;
  }

  /// Enough rows to judge an effect? The held-out test cuts the rows into folds; each must hold
  /// rows_per_parameter rows per parameter of the largest model the search tries first (the base
  /// model's free parameters and the largest effect's), and a row in every block of every fold.
  /// The whole problem must also hold more residuals than twice all its parameters. Below that,
  /// any "finding" would be fitted noise: the report says so, with the plug-in's error only.
  bool enough_rows() {
    const Problem& p = *problem_;
    std::size_t largest_effect = 0;
    std::string largest_cause;
    for (const auto& e : searched_)
      if (e.params.size() > largest_effect) {
        largest_effect = e.params.size();
        largest_cause = e.cause;
      }
    const std::size_t first_model = p.base_free.size() + largest_effect;
    const std::size_t folds = static_cast<std::size_t>(std::max(1, o_.folds));
    const std::size_t blocks = static_cast<std::size_t>(std::max(1, o_.folds * o_.blocks_per_fold));
    const std::size_t per_fold = static_cast<std::size_t>(std::max(1, o_.rows_per_parameter)) * std::max<std::size_t>(1, first_model);
    const std::size_t min_residuals = 2 * p.params.size() + 1;
    report_.minimum_rows = std::max(blocks, folds * per_fold);
    if (report_.rows >= report_.minimum_rows && engine_->size() >= min_residuals) return true;
    report_.too_few_rows = true;
    report_.verdict = Verdict::not_judged;
    // The plug-in's error on every row, the one figure that needs no fit (the engine's default
    // noise of 1 in the clamp's expectation: no estimate from so few rows).
    report_.heldout_mse_plugin = reading_mse(*engine_, p, p.plugin_values);
    report_.mse_plugin_reading = reading_mse_plain(*engine_, p, p.plugin_values);
    std::string why = "too few rows (" + std::to_string(report_.rows) + ") to judge effects; need at least " +
                      std::to_string(report_.minimum_rows) + ": the held-out test's " + std::to_string(folds) +
                      " folds must each hold " + std::to_string(o_.rows_per_parameter) +
                      " rows per parameter of the largest model tried first (" + std::to_string(first_model) +
                      ": the base model's " + std::to_string(p.base_free.size()) + " free" +
                      (largest_cause.empty() ? std::string() : " and " + largest_cause + "'s " + std::to_string(largest_effect)) +
                      "), and a row in each of its " + std::to_string(blocks) + " blocks";
    if (engine_->size() < min_residuals)
      why += "; the model also needs at least " + std::to_string(min_residuals) + " residuals (it has " +
             std::to_string(engine_->size()) + ")";
    report_.message = why;
    report_.warnings.push_back(why + ". No effect was judged: verdict " + report_.verdict_name() + ".");
    return false;
  }

  /// Step 1: the plug-in as published; its residuals give the first noise estimate. Nothing is
  /// fitted, so every row is held out.
  void score_plugin() {
    const Problem& p = *problem_;
    engine_->set_sigma(engine_->noise_sd(p.plugin_values));
    report_.heldout_mse_plugin = reading_mse(*engine_, p, p.plugin_values);
    report_.mse_plugin_reading = reading_mse_plain(*engine_, p, p.plugin_values);
    report_.message = p.notes;
  }

  /// Step 2: the base model's free parameters recalibrated, from where every effect is off.
  void recalibrate() {
    const Problem& p = *problem_;
    progress("recalibrating", 0, 0, 0, "");
    std::vector<double> neutral(p.params.size());
    for (std::size_t j = 0; j < p.params.size(); ++j) neutral[j] = p.params[j].fallback;
    free_ = p.base_free;
    current_ = engine_->fit(free_, neutral, engine_->all(), true);
    settle_noise(*engine_, free_, current_);
    report_.recalibrated = named(p, current_, p.base_free);
    report_.base_fit = all_rows_statistics(*engine_, p, current_);
    current_h_ = engine_->heldout_mse(free_, current_.values);
    report_.heldout_mse_base = current_h_.reading;
    report_.heldout_weighted_base = current_h_.all;
    base_values_ = current_.values;
  }

  /// An effect fitted with the current model at one search step.
  struct Candidate {
    std::size_t trial;   ///< index into report_.trials
    std::size_t effect;  ///< index into searched_
    std::vector<int> free;
    Engine::Fitted fit;
  };

  /// Step 3: every effect not yet kept, fitted with the current model (from each of its starting
  /// points); those whose BIC falls by min_delta_bic or more, lowest BIC first.
  /// `usable` (optional) receives every candidate whose fit to all residuals is usable, passing
  /// or not (the pair search's singles).
  std::vector<Candidate> fit_candidates(int step, std::vector<Candidate>* usable = nullptr) {
    const Problem& p = *problem_;
    const Engine& engine = *engine_;
    // Long logs: the starting points are tried on the leading residuals (a model that simulates
    // row after row stops there), and the best is refined on all of them.
    const bool screening = engine.size() > kScreenResiduals;
    std::vector<std::size_t> screen_idx(std::min(engine.size(), kScreenResiduals));
    std::iota(screen_idx.begin(), screen_idx.end(), 0);
    const std::vector<std::size_t>& screen = screening ? screen_idx : engine.all();
    double screen_rss = 0;  // the current model's on the leading residuals
    if (screening) {
      const auto r = engine.loss_residuals(current_.values);
      for (std::size_t i : screen_idx) screen_rss += r[i] * r[i];
    }
    std::vector<Candidate> passing;
    const int to_try = static_cast<int>(searched_.size() - kept_.size());
    int tried = 0;
    for (std::size_t e = 0; e < searched_.size(); ++e) {
      if (kept_.count(e)) continue;
      const detail::Effect& effect = searched_[e];
      progress("fitting effect", step, ++tried, to_try, effect.cause);
      std::vector<int> cand = free_;
      std::vector<double> start = current_.values;
      std::size_t starts = 1;
      for (int j : effect.params) {
        const fit::Parameter& q = p.params[static_cast<std::size_t>(j)];
        cand.push_back(j);
        start[static_cast<std::size_t>(j)] = q.value;
        starts = std::max(starts, 1 + q.other_starts.size());
      }
      if (static_cast<int>(cand.size()) > kMaxFree) continue;
      Trial t;
      t.step = step;
      t.cause = effect.cause;
      Engine::Fitted f = engine.fit(cand, start, screen, false);
      for (std::size_t k = 1; k < starts; ++k) {
        std::vector<double> other = start;
        for (int j : effect.params) {
          const auto& more = p.params[static_cast<std::size_t>(j)].other_starts;
          if (k <= more.size()) other[static_cast<std::size_t>(j)] = more[k - 1];
        }
        Engine::Fitted g = engine.fit(cand, other, screen, false);
        if (g.result.usable && (!f.result.usable || g.result.rss < f.result.rss)) f = g;
      }
      if (screening) {
        // No gain at all on the leading residuals (as a speed limit above every command there):
        // the effect has no support in them and is not refined on all residuals.
        if (!f.result.usable || !(f.result.rss < screen_rss * (1.0 - 1e-9))) {
          t.delta_bic = std::log(static_cast<double>(engine.size())) * static_cast<double>(effect.params.size());
          t.screened_out = true;
          report_.trials.push_back(t);
          continue;
        }
        f = engine.fit(cand, f.values, engine.all(), false);
      }
      if (!f.result.usable) {
        report_.trials.push_back(t);
        continue;
      }
      t.delta_bic = f.result.bic - current_.result.bic;
      report_.trials.push_back(t);
      if (t.delta_bic <= -o_.min_delta_bic) passing.push_back({report_.trials.size() - 1, e, cand, f});
      else if (usable) usable->push_back({report_.trials.size() - 1, e, cand, std::move(f)});
    }
    // Of two effects that fit alike, the one with fewer parameters comes first (white_level
    // rather than three equal sensor gains).
    std::sort(passing.begin(), passing.end(), [&](const Candidate& a, const Candidate& b) {
      return report_.trials[a.trial].delta_bic < report_.trials[b.trial].delta_bic;
    });
    return passing;
  }

  /// Step 4: the held-out test, in BIC order until one candidate gains, then for the others within
  /// min_delta_bic of it (its alternatives; the rest need not run). The winner's index into
  /// `passing`, or -1.
  int pick_by_heldout(int step, std::vector<Candidate>& passing) {
    int best = -1;
    double best_bic = 0;
    int tested = 0;
    for (std::size_t c = 0; c < passing.size(); ++c) {
      Trial& t = report_.trials[passing[c].trial];
      if (best >= 0 && t.delta_bic - best_bic >= o_.min_delta_bic) break;
      progress("held-out test", step, ++tested, static_cast<int>(passing.size()), t.cause);
      t.heldout_mse = engine_->heldout_mse(passing[c].free, passing[c].fit.values).all;
      const bool gain = t.heldout_mse <= current_h_.all * (1.0 - o_.min_heldout_gain);
      if (gain && best < 0) {
        best = static_cast<int>(c);
        best_bic = t.delta_bic;
      }
    }
    return best;
  }

  /// One step of the greedy forward search (steps 3 and 4): the best effect that passes both
  /// tests joins the model; when none does, the pair search (search_pair). False when nothing
  /// joins (the search ends).
  bool search_step(int step) {
    std::vector<Candidate> failing;
    std::vector<Candidate> passing = fit_candidates(step, o_.pair_search ? &failing : nullptr);
    const int best = pick_by_heldout(step, passing);
    if (best < 0) return o_.pair_search && search_pair(step, failing);
    const Candidate& winner = passing[static_cast<std::size_t>(best)];
    return accept(step, {winner.effect}, winner.fit, winner.trial);
  }

  /// The pair search (docs/diagnose.md): no single effect passed this step. Two effects whose
  /// signatures partly cancel over the measured conditions may each gain almost nothing alone
  /// and explain the misfit together (a greedy trap). The Options::pair_singles effects that
  /// lowered the residuals most alone (a gain in RSS at all) are fitted in pairs, jointly with
  /// the current model, from where each stood alone: at most pair_singles (pair_singles - 1) / 2
  /// fits, only at a step where no single passes. The pair with the lowest BIC joins the model
  /// when it passes the same two tests as a single (its BIC change counted for both). Not tried
  /// on long logs (above kScreenResiduals residuals), where each joint fit would cost as much as
  /// a step.
  bool search_pair(int step, std::vector<Candidate>& singles) {
    if (engine_->size() > kScreenResiduals || o_.pair_singles < 2) return false;
    if (static_cast<int>(report_.findings.size()) + 2 > o_.max_findings) return false;
    const double log_n = std::log(static_cast<double>(engine_->size()));
    // Their BIC change less their parameters' penalty: below 0, the RSS fell.
    std::vector<Candidate> gained;
    for (Candidate& c : singles) {
      const double penalty = log_n * static_cast<double>(searched_[c.effect].params.size());
      if (report_.trials[c.trial].delta_bic - penalty < 0) gained.push_back(std::move(c));
    }
    std::sort(gained.begin(), gained.end(), [&](const Candidate& a, const Candidate& b) {
      return report_.trials[a.trial].delta_bic < report_.trials[b.trial].delta_bic;
    });
    if (gained.size() > static_cast<std::size_t>(o_.pair_singles)) gained.resize(static_cast<std::size_t>(o_.pair_singles));
    std::vector<Candidate> pairs;  // `effect` the first's; the second's in `second`
    std::vector<std::size_t> second;
    const int total = static_cast<int>(gained.size() * (gained.size() - (gained.empty() ? 0 : 1)) / 2);
    int done = 0;
    for (std::size_t a = 0; a < gained.size(); ++a)
      for (std::size_t b = a + 1; b < gained.size(); ++b) {
        const detail::Effect& ea = searched_[gained[a].effect];
        const detail::Effect& eb = searched_[gained[b].effect];
        progress("fitting pair", step, ++done, total, ea.cause + " + " + eb.cause);
        std::vector<int> cand = gained[a].free;
        std::vector<double> start = current_.values;
        for (int j : ea.params) start[static_cast<std::size_t>(j)] = gained[a].fit.values[static_cast<std::size_t>(j)];
        for (int j : eb.params) {
          cand.push_back(j);
          start[static_cast<std::size_t>(j)] = gained[b].fit.values[static_cast<std::size_t>(j)];
        }
        if (static_cast<int>(cand.size()) > kMaxFree) continue;
        Engine::Fitted f = engine_->fit(cand, start, engine_->all(), false);
        if (!f.result.usable) continue;
        Trial t;
        t.step = step;
        t.cause = ea.cause;
        t.with = eb.cause;
        t.delta_bic = f.result.bic - current_.result.bic;
        report_.trials.push_back(t);
        if (t.delta_bic <= -o_.min_delta_bic) {
          pairs.push_back({report_.trials.size() - 1, gained[a].effect, cand, std::move(f)});
          second.push_back(gained[b].effect);
        }
      }
    if (pairs.empty()) return false;
    std::vector<std::size_t> order(pairs.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
      return report_.trials[pairs[x].trial].delta_bic < report_.trials[pairs[y].trial].delta_bic;
    });
    // The held-out test, best BIC first, until a pair gains.
    for (std::size_t o : order) {
      Trial& t = report_.trials[pairs[o].trial];
      progress("held-out test", step, 0, 0, t.cause + " + " + t.with);
      t.heldout_mse = engine_->heldout_mse(pairs[o].free, pairs[o].fit.values).all;
      if (t.heldout_mse <= current_h_.all * (1.0 - o_.min_heldout_gain))
        return accept(step, {pairs[o].effect, second[o]}, pairs[o].fit, pairs[o].trial);
    }
    return false;
  }

  /// The effects `effects` (one, or a pair found together) join the model at the fit `fit` of
  /// the trial `trial`; the noise is re-estimated and, with several channels, the held-out test
  /// run again under the new weights. Then backward elimination. False when the finding is undone.
  bool accept(int step, const std::vector<std::size_t>& effects, const Engine::Fitted& fit, std::size_t trial) {
    const Problem& p = *problem_;
    const double best_cv = report_.trials[trial].heldout_mse;
    const double best_bic = report_.trials[trial].delta_bic;
    const std::vector<int> free_before = free_;
    const Engine::Fitted fit_before = current_;
    const std::vector<double> sigma_before = engine_->sigma();
    std::vector<Finding> found(effects.size());
    std::string names;
    for (std::size_t k = 0; k < effects.size(); ++k) {
      Finding& finding = found[k];
      finding.cause = searched_[effects[k]].cause;
      finding.effect = finding.cause;
      finding.delta_bic = best_bic;
      finding.heldout_mse_before = current_h_.reading;
      finding.heldout_weighted_before = current_h_.all;
      if (effects.size() == 2) finding.accepted_with = searched_[effects[1 - k]].cause;
      names += (names.empty() ? "" : " and ") + finding.cause;
      for (int j : searched_[effects[k]].params) free_.push_back(j);
    }
    // Re-estimate the noise with the better model and refit (the clamp's expected value uses
    // it), until the estimate settles; then the held-out error again with that noise.
    current_ = fit;
    settle_noise(*engine_, free_, current_);
    const Engine::Heldout h = engine_->heldout_mse(free_, current_.values);
    if (p.channel_names.size() > 1) {
      // Several channels: the residuals' weights follow the noise estimates, which the finding
      // has just changed. The model without it must lose on held-out rows under the same weights
      // too, or the finding is undone (an effect that only moved weight between channels).
      const Engine::Fitted without = engine_->fit(free_before, fit_before.values, engine_->all(), false);
      const Engine::Heldout h_without = engine_->heldout_mse(free_before, without.values);
      if (!(h.all <= h_without.all * (1.0 - o_.min_heldout_gain))) {
        free_ = free_before;
        current_ = fit_before;
        engine_->set_sigma(sigma_before);
        report_.notes.push_back(names + " passed the search but not the held-out test once the noise was re-estimated");
        return false;
      }
      for (Finding& finding : found) {
        finding.heldout_mse_before = h_without.reading;
        finding.heldout_weighted_before = h_without.all;
      }
    }
    if (effects.size() == 1)
      for (const auto& t : report_.trials) {
        if (t.step != step || t.cause == found[0].cause || !t.with.empty()) continue;
        if (t.heldout_mse > 0 && t.delta_bic <= -o_.min_delta_bic && t.delta_bic - best_bic < o_.min_delta_bic &&
            t.heldout_mse <= best_cv * (1.0 + o_.min_heldout_gain))
          found[0].alternatives.push_back(t.cause);
      }
    else {
      char buf[300];
      std::snprintf(buf, sizeof buf, "%s and %s were accepted together (pair search): neither passed alone, together BIC %+.1f",
                    found[0].cause.c_str(), found[1].cause.c_str(), best_bic);
      report_.notes.push_back(buf);
    }
    report_.trials[trial].kept = true;
    const fit::FitStatistics stats = all_rows_statistics(*engine_, p, current_);
    for (std::size_t k = 0; k < effects.size(); ++k) {
      found[k].fit = stats;
      found[k].heldout_mse_after = h.reading;
      found[k].heldout_weighted_after = h.all;
      kept_.insert(effects[k]);
      order_.push_back(searched_[effects[k]]);
      report_.findings.push_back(std::move(found[k]));
    }
    current_h_ = h;
    eliminate_backwards(effects.size());
    return true;
  }

  /// Backward elimination after each acceptance: an earlier finding whose removal from the model
  /// as it now stands costs less than Options::min_delta_bic on the BIC no longer earns its place
  /// (a later finding explains what it stood in for: a greedy first step that took a partial
  /// effect). It leaves the model, a note says so, and it is not tried again. The weakest first,
  /// one at a time, until every finding earns its place.
  /// The `fresh` findings that just joined (two for a pair) are not candidates for removal.
  void eliminate_backwards(std::size_t fresh) {
    const Problem& p = *problem_;
    while (report_.findings.size() > fresh) {
      const Engine::Fitted with = engine_->fit(free_, current_.values, engine_->all(), false);
      int weakest = -1;
      double weakest_cost = o_.min_delta_bic;
      Engine::Fitted weakest_fit;
      std::vector<int> weakest_free;
      for (std::size_t k = 0; k + fresh < report_.findings.size(); ++k) {
        std::vector<int> free;
        Engine::Fitted without = without_finding(k, &free);
        if (!without.result.usable) continue;
        const double cost = without.result.bic - with.result.bic;  // what removing it costs
        if (cost < weakest_cost) {
          weakest = static_cast<int>(k);
          weakest_cost = cost;
          weakest_fit = std::move(without);
          weakest_free = std::move(free);
        }
      }
      if (weakest < 0) return;
      const auto k = static_cast<std::size_t>(weakest);
      char buf[300];
      std::snprintf(buf, sizeof buf,
                    "%s left the model after %s joined it: removing it then cost %+.1f on the BIC (under %.0f), so the "
                    "later findings explain what it stood in for",
                    report_.findings[k].cause.c_str(), report_.findings.back().cause.c_str(), weakest_cost, o_.min_delta_bic);
      report_.notes.push_back(buf);
      for (auto& t : report_.trials)
        if (t.cause == report_.findings[k].cause || t.with == report_.findings[k].cause) t.kept = false;
      report_.findings.erase(report_.findings.begin() + weakest);
      order_.erase(order_.begin() + weakest);
      free_ = weakest_free;
      current_ = weakest_fit;
      settle_noise(*engine_, free_, current_);
      current_h_ = engine_->heldout_mse(free_, current_.values);
      report_.findings.back().heldout_mse_after = current_h_.reading;
      report_.findings.back().heldout_weighted_after = current_h_.all;
      report_.findings.back().fit = all_rows_statistics(*engine_, p, current_);
    }
  }

  /// The registry's physical-range rule (docs/diagnose.md): a parameter in the unit of one of the
  /// kind's measured quantities (kind_facts: counts, px, mm) whose neutral value is 0 is an amount
  /// added to that reading (an offset, a tail's amplitude); beyond the channel's full scale it is
  /// not an amount the sensor can read: the logs' units are wrong, or the finding stands in for
  /// something else. Why, or "".
  std::string above_full_scale(const detail::Effect& effect) const {
    const Problem& p = *problem_;
    const models::KindFacts* facts = models::kind_facts(std::string(logs::to_string(report_.kind)));
    if (facts == nullptr) return "";
    for (int j : effect.params) {
      const auto q = static_cast<std::size_t>(j);
      if (q >= p.param_units.size() || p.param_units[q].empty() || p.params[q].fallback != 0.0) continue;
      for (const models::Channel& c : facts->channels) {
        if (p.param_units[q] != c.unit) continue;
        const double v = current_.values[q];
        if (!(std::abs(v) > c.full_scale)) break;
        char why[240];
        std::snprintf(why, sizeof why, "%s = %.4g %s is %s the sensor's full scale (%s%.0f %s): %s", p.params[q].name.c_str(), v,
                      c.unit, v > 0 ? "above" : "below minus", v > 0 ? "" : "-", c.full_scale, c.unit,
                      detail::kOutsidePhysicalRange);
        return why;
      }
    }
    return "";
  }

  /// A finding whose fitted parameters make it another effect is named for what it is (the
  /// kind's rule, Problem::identify), whether or not the search tried that effect. When the other
  /// effect is in the catalogue, it replaces the finding in the model if the model refitted with
  /// it has a BIC no higher (it has no more parameters and fits as well); its held-out error is
  /// then measured again and the finding's BIC change moves by the swap's.
  void name_findings() {
    const Problem& p = *problem_;
    for (std::size_t k = 0; k < report_.findings.size(); ++k) {
      Finding& f = report_.findings[k];
      const detail::Effect& effect = order_[k];
      if (std::find(p.identifiable.begin(), p.identifiable.end(), effect.cause) == p.identifiable.end()) continue;
      const Engine::Fitted with_errors = engine_->fit(free_, current_.values, engine_->all(), true);
      const std::optional<detail::Identity> identity = p.identify(effect.cause, current_.values, with_errors.result.covariance);
      if (!identity) continue;
      if (!identity->replace_with.empty()) {
        const auto other = std::find_if(p.effects.begin(), p.effects.end(),
                                        [&](const detail::Effect& e) { return e.cause == identity->replace_with; });
        if (other == p.effects.end()) continue;
        // The effect's parameters leave the model at the values that switch them off; the
        // other's join it from the values the rule gives.
        std::vector<int> free;
        std::vector<double> start = current_.values;
        for (int j : free_)
          if (std::find(effect.params.begin(), effect.params.end(), j) == effect.params.end()) free.push_back(j);
        for (int j : effect.params) start[static_cast<std::size_t>(j)] = p.params[static_cast<std::size_t>(j)].fallback;
        for (const auto& [j, v] : identity->starts) start[static_cast<std::size_t>(j)] = v;
        for (int j : other->params) free.push_back(j);
        Engine::Fitted refit = engine_->fit(free, start, engine_->all(), false);
        if (!refit.result.usable || refit.result.bic > with_errors.result.bic) {
          report_.notes.push_back("finding " + f.cause + " looks like " + identity->cause + " (" + identity->why +
                                  "), but the model with " + identity->replace_with +
                                  " in its place fits worse on the BIC: it stays " + f.cause);
          continue;
        }
        f.delta_bic += refit.result.bic - with_errors.result.bic;
        free_ = free;
        current_ = refit;
        settle_noise(*engine_, free_, current_);
        current_h_ = engine_->heldout_mse(free_, current_.values);
        f.effect = other->cause;
        // Held-out error and fit of the model as it now stands (the findings after this one
        // included): what the swap was measured on.
        f.heldout_mse_after = current_h_.reading;
        f.heldout_weighted_after = current_h_.all;
        f.fit = all_rows_statistics(*engine_, p, current_);
        order_[k] = *other;
      }
      report_.notes.push_back("finding " + f.cause + " is named " + identity->cause + ": " + identity->why);
      f.renamed_from = f.cause;
      f.cause = identity->cause;
      f.alternatives.erase(std::remove(f.alternatives.begin(), f.alternatives.end(), f.cause), f.alternatives.end());
    }
  }

  /// The final joint fit with every finding (covariance included), the noise of a reading, and
  /// the parameters named: the base's in `final_base`, each finding's in its parameters.
  void fit_final() {
    const Problem& p = *problem_;
    current_ = engine_->fit(free_, current_.values, engine_->all(), true);
    report_.heldout_mse_final = current_h_.reading;
    report_.heldout_weighted_final = current_h_.all;
    // The noise of a reading: residuals of readings away from the sensor's rails (a reading on a
    // rail has its noise clipped; the MSE over all rows counts the clipped zeros of every reading
    // beyond the proximity sensor's range).
    const std::vector<double> sd = engine_->noise_sd(current_.values);
    report_.noise_sd = sd.front();
    report_.channel_noise_sd.clear();  // fit_final runs again when undetermined findings leave
    if (p.channel_names.size() > 1)
      for (std::size_t c = 0; c < sd.size(); ++c) report_.channel_noise_sd.push_back({p.channel_names[c], sd[c], 0.0});
    for (std::size_t k = 0; k < order_.size(); ++k) report_.findings[k].parameters = named(p, current_, order_[k].params);
    // The recalibration alone stays in `recalibrated` (step 2's fit); the base parameters of the
    // joint fit with every finding are the extended model's.
    if (!p.base_free.empty()) report_.final_base = named(p, current_, p.base_free);
    report_.final_fit = all_rows_statistics(*engine_, p, current_);
    report_.correlations = fit::correlations(current_.result);
    report_.censored_below = report_.censored_above = 0;
    for (std::size_t i = 0; i < engine_->size(); ++i) {
      if (p.y[i] <= engine_->lo(i)) ++report_.censored_below;
      if (p.y[i] >= engine_->hi(i)) ++report_.censored_above;
    }
  }

  /// Beside the covariance's standard errors: the jackknife over the held-out folds, a warning
  /// where one row carries a parameter's information, the time series' corrections, and a
  /// warning for every finding the logs do not pin down.
  void estimate_uncertainties() {
    const Problem& p = *problem_;
    // Jackknife over the held-out folds (each fold's fit leaves out contiguous blocks of rows):
    // SE^2 = (G - 1)/G sum (theta_g - mean)^2, whatever the residuals' correlation within a block
    // and whatever the model's smoothness, which the covariance assumes.
    std::vector<double> jackknife(p.params.size(), std::numeric_limits<double>::quiet_NaN());
    report_.jackknife_folds = current_h_.fold_values.size();
    if (current_h_.fold_values.size() >= 3) {
      const double G = static_cast<double>(current_h_.fold_values.size());
      for (int j : free_) {
        double mean = 0, ss = 0;
        for (const auto& v : current_h_.fold_values) mean += v[static_cast<std::size_t>(j)] / G;
        for (const auto& v : current_h_.fold_values) ss += (v[static_cast<std::size_t>(j)] - mean) * (v[static_cast<std::size_t>(j)] - mean);
        jackknife[static_cast<std::size_t>(j)] = std::sqrt((G - 1) / G * ss);
      }
    }
    for_each_reported(p, [&](NamedValue& v, int j) { v.std_error_jackknife = jackknife[static_cast<std::size_t>(j)]; });
    // Where one row carries most of a parameter's information (J^T J), the covariance's error
    // rests on that row's derivative: at a jump of the model (a battery's end-of-life drop) a
    // difference across the jump, not information. Said, with the jackknife's error beside it.
    Eigen::MatrixXd final_jacobian;
    const bool have_jacobian = engine_->jacobian(free_, current_.values, &final_jacobian);
    if (have_jacobian)
      for (int j : free_) {
        const auto col = final_jacobian.col(j);
        const double total = col.squaredNorm(), top = col.cwiseAbs2().maxCoeff();
        if (!(total > 0) || top < kOneRowInformation * total) continue;
        const std::string name = p.params[static_cast<std::size_t>(j)].name;
        char buf[400];
        std::snprintf(buf, sizeof buf,
                      "%s: one row carries %.4g %% of the covariance's information (the model's derivative there is a jump, "
                      "not a slope): its covariance error %.2g is not what the logs support; the jackknife over the held-out "
                      "folds gives %.2g.",
                      name.c_str(), 100 * top / total, current_.result.parameters[static_cast<std::size_t>(j)].std_error,
                      jackknife[static_cast<std::size_t>(j)]);
        report_.warnings.push_back(buf);
      }
    if (p.time_series) correct_for_time_series(have_jacobian ? &final_jacobian : nullptr);
    // A finding whose parameter the logs do not pin down (standard error above its size, or none)
    // names a direction of misfit, not a measured effect: say so.
    for (const Finding& f : report_.findings)
      for (const NamedValue& v : f.parameters)
        if (!(std::abs(v.std_error) <= std::abs(v.value)))
          report_.warnings.push_back("finding " + f.cause + ": " + v.name + " = " + std::to_string(v.value) +
                                     " is not determined by these logs (standard error " +
                                     (std::isfinite(v.std_error) ? std::to_string(v.std_error) : std::string("undefined")) +
                                     "); read it as a direction, not a size.");
  }

  /// What each finding carries of the final model's gain: the BIC's rise when it alone is taken
  /// out of the final model (the rest refitted). The largest names the verdict.
  void score_shares() {
    for (std::size_t k = 0; k < report_.findings.size(); ++k) {
      std::vector<int> free;
      const Engine::Fitted without = without_finding(k, &free);
      report_.findings[k].removal_delta_bic = without.result.usable ? without.result.bic - current_.result.bic : 0.0;
    }
  }

  /// The current model refitted without finding k (its parameters back at their neutral values;
  /// no covariance); `free` receives the free parameters that remain.
  Engine::Fitted without_finding(std::size_t k, std::vector<int>* free) const {
    const Problem& p = *problem_;
    free->clear();
    std::vector<double> start = current_.values;
    const auto& params = order_[k].params;
    for (int j : free_)
      if (std::find(params.begin(), params.end(), j) == params.end()) free->push_back(j);
    for (int j : params) start[static_cast<std::size_t>(j)] = p.params[static_cast<std::size_t>(j)].fallback;
    return engine_->fit(*free, start, engine_->all(), false);
  }

  /// Findings the logs cannot determine leave the model (Report::possible, "possible, not
  /// determined"): a parameter with no standard error or one beyond Options::max_relative_se of
  /// its size, a parameter on its bound, or two findings whose parameters correlate beyond
  /// Options::max_correlation (both leave). The rest are refitted without them. True when any left.
  bool leave_out_undetermined() {
    const Problem& p = *problem_;
    const std::size_t F = report_.findings.size();
    std::vector<std::string> why(F);
    auto text = [](double v) {
      char b[40];
      std::snprintf(b, sizeof b, "%.3g", v);
      return std::string(b);
    };
    for (std::size_t k = 0; k < F; ++k) {
      why[k] = above_full_scale(order_[k]);
      if (why[k].empty()) why[k] = p.implausible(order_[k].cause, current_.values);
    }
    for (std::size_t k = 0; k < F; ++k)
      for (std::size_t q = 0; q < order_[k].params.size() && why[k].empty(); ++q) {
        const int j = order_[k].params[q];
        const auto& par = p.params[static_cast<std::size_t>(j)];
        const double v = current_.values[static_cast<std::size_t>(j)];
        const double se = current_.result.parameters.size() > static_cast<std::size_t>(j)
                              ? current_.result.parameters[static_cast<std::size_t>(j)].std_error
                              : std::numeric_limits<double>::quiet_NaN();
        const double size = std::max(std::abs(v), std::abs(par.fallback));
        const double tol = 1e-6 * std::max(1.0, std::abs(v));
        const bool on_lower = std::isfinite(par.lower) && v - par.lower <= tol;
        const bool on_upper = !on_lower && std::isfinite(par.upper) && par.upper - v <= tol;
        const bool determined = std::isfinite(se) && se <= o_.max_relative_se * size;
        if ((on_lower || on_upper) && determined)
          // The registry's bound is the end of the quantity's physical range: the logs, which
          // determine the parameter, would take it beyond.
          why[k] = par.name + " = " + text(v) + " is on its bound " + text(on_lower ? par.lower : par.upper) +
                   ", the end of its physical range (" + text(par.lower) + " to " + text(par.upper) +
                   "), with a standard error of " + text(se) + ": the logs take it there, " + detail::kOutsidePhysicalRange;
        else if (on_lower || on_upper)
          why[k] = par.name + " = " + text(v) + " is on its bound " + text(on_lower ? par.lower : par.upper);
        else if (!std::isfinite(se))
          why[k] = par.name + " = " + text(v) + " has no standard error";
        else if (se > o_.max_relative_se * size)
          why[k] = par.name + " = " + text(v) + " ± " + text(se) + ": a standard error beyond " + text(o_.max_relative_se) +
                   " times its size";
      }
    const Eigen::MatrixXd& c = current_.result.covariance;
    for (std::size_t a = 0; a < F; ++a)
      for (std::size_t b = a + 1; b < F; ++b)
        for (int i : order_[a].params)
          for (int j : order_[b].params) {
            if (static_cast<Eigen::Index>(std::max(i, j)) >= c.rows()) continue;
            const double r = c(i, j) / std::sqrt(c(i, i) * c(j, j));
            if (!(std::abs(r) > o_.max_correlation)) continue;
            const std::string same = "these logs cannot tell " + report_.findings[a].cause + " from " +
                                     report_.findings[b].cause + " (" + p.params[static_cast<std::size_t>(i)].name + " and " +
                                     p.params[static_cast<std::size_t>(j)].name + " correlate at " + text(r) + ")";
            if (why[a].empty()) why[a] = same;
            if (why[b].empty()) why[b] = same;
          }
    if (std::all_of(why.begin(), why.end(), [](const std::string& w) { return w.empty(); })) return false;
    std::vector<int> free;
    std::vector<double> start = current_.values;
    std::vector<Finding> kept;
    std::vector<detail::Effect> kept_order;
    for (std::size_t k = 0; k < F; ++k) {
      Finding& f = report_.findings[k];
      if (why[k].empty()) {
        kept.push_back(std::move(f));
        kept_order.push_back(order_[k]);
        continue;
      }
      f.undetermined = why[k];
      f.outside_physical_range = why[k].find(detail::kOutsidePhysicalRange) != std::string::npos;
      for (int j : order_[k].params) start[static_cast<std::size_t>(j)] = p.params[static_cast<std::size_t>(j)].fallback;
      report_.possible.push_back(std::move(f));
    }
    for (int j : free_) {
      bool in_possible = false;
      for (std::size_t k = 0; k < F; ++k)
        if (!why[k].empty() && std::find(order_[k].params.begin(), order_[k].params.end(), j) != order_[k].params.end())
          in_possible = true;
      if (!in_possible) free.push_back(j);
    }
    report_.findings = std::move(kept);
    order_ = std::move(kept_order);
    free_ = free;
    current_ = engine_->fit(free_, start, engine_->all(), true);
    settle_noise(*engine_, free_, current_);
    current_h_ = engine_->heldout_mse(free_, current_.values);
    return true;
  }

  /// A log's rows are a time series: the covariance's standard errors assume independent
  /// residuals and are too small by the autocorrelation's factor; each log is also a cluster
  /// (robust to a misfit that lasts a whole log, which the lag-1 factor misses).
  void correct_for_time_series(const Eigen::MatrixXd* jacobian) {
    const Problem& p = *problem_;
    report_.time_series = true;
    fit::AutocorrelationCorrection& a = report_.autocorrelation;
    a = residual_autocorrelation(*engine_, p, current_.values, report_.autocorrelation_channel);
    if (jacobian != nullptr) {
      const std::vector<double> log_of_row = log_of_rows(p);
      std::vector<int> log_of(engine_->size());
      for (std::size_t i = 0; i < engine_->size(); ++i) log_of[i] = static_cast<int>(log_of_row[p.row[i]]);
      fit::apply_cluster_robust(a, current_.result, *jacobian, engine_->loss_residuals(current_.values), log_of);
    } else {
      fit::apply_ar1(a, current_.result);
      a.cluster_why_not = "the Jacobian could not be evaluated";
    }
    // By parameter index: two effects may name their parameter alike (drive: k).
    for_each_reported(p, [&](NamedValue& v, int j) {
      const double c = static_cast<std::size_t>(j) < a.std_errors.size() ? a.std_errors[static_cast<std::size_t>(j)]
                                                                        : std::numeric_limits<double>::quiet_NaN();
      if (std::isfinite(c) && c > 0) v.std_error_corrected = c;
    });
  }

  /// Step 5: what the residuals still depend on, before (recalibrated base) and after (final
  /// model), and the verdict.
  void score_residual_structure() {
    const Problem& p = *problem_;
    progress("residual structure", 0, 0, 0, "");
    report_.residual_before = engine_->residuals(base_values_);
    report_.residual_after = engine_->residuals(current_.values);
    report_.structure_before =
        structure(p, report_.residual_before, engine_->predict(base_values_), o_.structure_threshold, engine_->sigma());
    report_.structure_after =
        structure(p, report_.residual_after, engine_->predict(current_.values), o_.structure_threshold, engine_->sigma());
    bool left = false;
    for (const auto& s : report_.structure_after) left = left || s.significant;
    report_.verdict = left ? Verdict::unexplained : report_.findings.empty() ? Verdict::none : Verdict::effect;
  }

  /// For the figure: the covariate it is drawn against (Report::covariates), one, not every one
  /// again; the residuals in their channels' own units (the weights were for the fits and scores).
  void keep_figure_data() {
    Problem& p = *problem_;
    // With no structure to show: time where the logs are time series (battery, drive), else the
    // row number within the log.
    std::string wanted = "log_row";
    for (const auto& c : p.covariates)
      if (c.first == "time_s") wanted = "time_s";
    if (report_.verdict == Verdict::unexplained) wanted = report_.structure_after.front().covariate;
    else if (!report_.structure_before.empty() && report_.structure_before.front().significant)
      wanted = report_.structure_before.front().covariate;
    if (wanted == "predicted") report_.covariates.emplace_back(wanted, engine_->predict(base_values_));
    for (std::size_t k = 0; k < p.covariates.size(); ++k)
      if (p.covariates[k].first == wanted)
        report_.covariates.emplace_back(wanted, p.is_per_row(k) ? p.covariate_values(k) : std::move(p.covariates[k].second));
    if (p.channel_names.size() > 1) {
      report_.residual_channel.assign(p.channel.begin(), p.channel.end());
      for (std::size_t i = 0; i < engine_->size(); ++i) {
        report_.residual_before[i] /= engine_->weight(i);
        report_.residual_after[i] /= engine_->weight(i);
      }
    }
  }

  /// Calls f(value, parameter index) for every reported parameter: the recalibrated base's and
  /// each finding's.
  template <class F>
  void for_each_reported(const Problem& p, F f) {
    for (std::size_t q = 0; q < report_.recalibrated.size() && q < p.base_free.size(); ++q) f(report_.recalibrated[q], p.base_free[q]);
    for (std::size_t k = 0; k < order_.size(); ++k)
      for (std::size_t q = 0; q < report_.findings[k].parameters.size() && q < order_[k].params.size(); ++q)
        f(report_.findings[k].parameters[q], order_[k].params[q]);
  }

  void progress(const char* stage, int step, int done, int total, const std::string& detail) const {
    if (o_.progress) o_.progress(Progress{stage, step, done, total, detail});
  }

  const Options& o_;
  Report report_;
  std::unique_ptr<Problem> problem_;
  std::unique_ptr<Engine> engine_;
  std::vector<detail::Effect> searched_;  ///< the effects the search tries (Options::effects, or all)
  std::vector<int> free_;                 ///< the current model's free parameters
  Engine::Fitted current_;                ///< its fit to every row
  Engine::Heldout current_h_;             ///< its held-out error
  std::vector<double> base_values_;       ///< the recalibrated base model (step 2)
  std::set<std::size_t> kept_;            ///< indices into searched_ of the effects found
  std::vector<detail::Effect> order_;     ///< the findings' effects, in the order found
};

}  // namespace

logs::Kind base_model_kind(const BaseModel& m) {
  if (std::holds_alternative<std::monostate>(m)) throw std::invalid_argument("no base model");
  const std::string kind = std::visit(
      [](const auto& model) -> std::string {
        if constexpr (std::is_same_v<std::decay_t<decltype(model)>, std::monostate>) return "";
        else return coefficients::kind_of(model);
      },
      m);
  return *logs::parse_kind(kind);
}

void set_base_model(Options& o, const coefficients::AnyModel& m, bool discharge_model) {
  std::visit(
      [&](const auto& model) {
        using Model = std::decay_t<decltype(model)>;
        if constexpr (std::is_same_v<Model, models::sensors::BatteryModel>) {
          o.battery_tables = model.tables;
          o.battery_capacity_k = model.capacity.k;
          if (discharge_model) o.battery_model = model.model;
        } else {
          o.base_model = model;
        }
      },
      m);
}

const Finding* Report::dominant() const {
  const Finding* best = nullptr;
  for (const Finding& f : findings)
    if (best == nullptr || f.removal_delta_bic > best->removal_delta_bic) best = &f;
  return best;
}

std::string Report::verdict_name() const {
  switch (verdict) {
    case Verdict::none: return "none";
    case Verdict::not_judged:
      return "not judged (too few rows: " + std::to_string(rows) + " of " + std::to_string(minimum_rows) + ")";
    case Verdict::unexplained: return "unexplained";
    case Verdict::effect: return findings.empty() ? "none" : dominant()->cause;
  }
  return "none";
}

namespace {
bool by_path(const logs::Log& a, const logs::Log& b) { return taken_before(a.path, b.path); }
}  // namespace

Report diagnose(const std::vector<logs::Log>& logs, const Options& options) {
  if (std::is_sorted(logs.begin(), logs.end(), by_path)) return Diagnosis(options).run(logs, nullptr);
  std::vector<logs::Log> sorted = logs;
  std::stable_sort(sorted.begin(), sorted.end(), by_path);
  return Diagnosis(options).run(sorted, &sorted);
}

Report diagnose(std::vector<logs::Log>&& logs, const Options& options) {
  std::stable_sort(logs.begin(), logs.end(), by_path);
  return Diagnosis(options).run(logs, &logs);
}

}  // namespace epuck2::diagnose