// Internal to the diagnosis engine: what a kind hands the engine (kind_*.cpp build one per
// kind; search.cpp searches, engine_detail.hpp fits, residual_structure.cpp scores).
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/fit/jet.hpp"
#include "epuck2/fit/least_squares.hpp"
#include "epuck2/fit/parameter.hpp"
#include "epuck2/logs/log.hpp"

namespace epuck2::diagnose::detail {

using fit::FitOptions;
using fit::FitResult;


/// At most this many parameters are free in one fit (the Jet's size).
inline constexpr int kMaxFree = 24;
using Jet = fit::Jet<kMaxFree>;
/// Most fits free few parameters: a short Jet is several times faster on long logs.
inline constexpr int kFewFree = 8;
using ShortJet = fit::Jet<kFewFree>;
/// One effect on a base without free parameters (drive, battery, ground) frees one or two.
inline constexpr int kTwoFree = 2;
using PairJet = fit::Jet<kTwoFree>;

/// The value of a scalar or a Jet (models branch on values, never on derivatives).
using fit::value_of;

inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// The diagnosis's parameters are the fit engine's (epuck2/fit/parameter.hpp): `value` is where a
/// fit starts when the effect is switched on, `fallback` the value that switches it off (a base
/// parameter's: the plug-in's), `other_starts` more starting points tried when it is switched on.
using fit::Parameter;

struct Effect {
  std::string cause;
  std::vector<int> params;  ///< indices into Problem::params
};

/// The words that end the physical-range rule's reasons (engine.cpp, and Problem::implausible's):
/// such a finding is "not written", not merely "possible, not determined".
constexpr const char* kOutsidePhysicalRange = "outside the physical range of the quantity";

/// What a finding is when its fitted parameters make it another effect (Problem::identify).
struct Identity {
  std::string cause;         ///< its name
  std::string why;           ///< in words, with the numbers that decided
  /// The catalogue effect that replaces the finding's in the model (empty: the same formula,
  /// renamed only), and where that effect's parameters start.
  std::string replace_with;
  std::vector<std::pair<int, double>> starts;
};

/// A kind's model over all rows of its logs, as a function of every parameter (base and all the
/// catalogue's effects; an effect at its neutral values is off).
class Problem {
 public:
  virtual ~Problem() = default;

  std::vector<Parameter> params;
  std::vector<int> base_free;  ///< the base model's free parameters (recalibrated)
  std::vector<Effect> effects;
  std::vector<double> plugin_values;  ///< every parameter at the plug-in's published values (effects off)
  /// Per parameter: its unit in the registry (lib/models effects.hpp; missing or "": not a
  /// catalogue parameter). The physical-range rule compares a parameter in a channel's unit with
  /// that channel's full scale (kind_facts).
  std::vector<std::string> param_units;

  // Per residual (one per row; camera: two per row, px then py).
  std::vector<double> y;       ///< the measured reading
  std::vector<std::uint32_t> row;  ///< the residual's row, numbered across all logs (< 2^32)
  std::size_t rows = 0;
  /// Per residual: which measured quantity it is (drive: 0 ToF in mm, 1 and 2 the encoders in
  /// steps). Empty: one channel. Each channel has its own noise level; residuals are weighted by
  /// it and reported in the units of channel 0. `covariate:` effects act on channel 0 only (the
  /// reading; encoders count what the wheels turned).
  std::vector<int> channel;
  std::vector<std::string> channel_names{"reading"};
  /// Per channel: the reading's clamp, its rails (±inf, or missing: none). A clamp is the
  /// sensor's, the same for every residual of a channel: it is not stored per residual. A reading
  /// at or beyond a rail is censored there by the fit engine (fit::Channels, as in calibration).
  std::vector<double> channel_lo, channel_hi;
  /// Per channel: where the sensor itself saturates before its noise is added (±inf, or missing:
  /// nowhere): a model term, the latent reading is clamp(model, saturation) (lib/models
  /// saturation.hpp); the reading's expected value E[clamp(latent + noise, rails)].
  std::vector<double> channel_saturation_lo, channel_saturation_hi;
  /// Per channel: the smallest noise standard deviation believed (empty: 0.3, a whole count's
  /// rounding).
  std::vector<double> channel_min_sd;
  /// Per channel, in its units: a dependence of the residuals smaller than this does not matter
  /// (empty: 0, only the relative threshold applies).
  std::vector<double> channel_min_structure;
  /// Rows are a time series: the noise is estimated from successive residuals (drive).
  bool noise_from_differences = false;
  /// Rows of a log are a time series (battery, drive): standard errors are corrected for the
  /// residuals' autocorrelation within each log (Report::autocorrelation).
  bool time_series = false;
  /// Covariates scored against the residuals (log columns and derived ones): per residual, or per
  /// row where covariate_per_row says so (a kind with several residuals a row stores a row's value
  /// once; covariate_values spreads it through `row`).
  std::vector<std::pair<std::string, std::vector<double>>> covariates;
  std::vector<bool> covariate_per_row;  ///< parallel to covariates; missing entries: per residual
  void add_row_covariate(std::string name, std::vector<double> per_row) {
    covariate_per_row.resize(covariates.size(), false);
    covariates.emplace_back(std::move(name), std::move(per_row));
    covariate_per_row.push_back(true);
  }
  bool is_per_row(std::size_t k) const { return k < covariate_per_row.size() && covariate_per_row[k]; }
  /// Covariate k's value for every residual.
  std::vector<double> covariate_values(std::size_t k) const {
    if (!is_per_row(k)) return covariates[k].second;
    const std::vector<double>& per_row = covariates[k].second;
    std::vector<double> v(row.size());
    for (std::size_t i = 0; i < row.size(); ++i) v[i] = per_row[row[i]];
    return v;
  }
  /// A covariate a kind builds only when the residual structure is scored (after the last fit):
  /// a long log's are not held through the fits, which never read them.
  struct LateCovariate {
    std::string name;
    std::vector<double> values;
    bool per_row = false;  ///< one value per row (else per residual)
  };
  /// Puts the kind's late covariates in front of the others (where a kind that builds them at once
  /// puts them), once; the search calls it after its last fit, before scoring the structure.
  void add_late_covariates() {
    if (late_covariates_added_) return;
    late_covariates_added_ = true;
    std::vector<LateCovariate> late = late_covariates();
    if (late.empty()) return;
    covariate_per_row.resize(covariates.size(), false);
    std::vector<std::pair<std::string, std::vector<double>>> all;
    std::vector<bool> per_row;
    for (LateCovariate& c : late) {
      all.emplace_back(std::move(c.name), std::move(c.values));
      per_row.push_back(c.per_row);
    }
    for (auto& c : covariates) all.push_back(std::move(c));
    per_row.insert(per_row.end(), covariate_per_row.begin(), covariate_per_row.end());
    covariates = std::move(all);
    covariate_per_row = std::move(per_row);
  }
  /// Extra numeric columns, per residual: candidates for `covariate:NAME`.
  std::vector<std::pair<std::string, std::vector<double>>> extra_columns;
  std::string notes;
  /// What the kind left out or read specially while building the problem, for Report::warnings.
  std::vector<std::string> warnings;
  /// Readings on a rail that the kind left out instead of censoring them ("file:line: why"; the
  /// ToF's "no target" codes with the obstacle in view): Report::outliers lists them, and they
  /// are not counted among the readings on the rails.
  std::vector<std::string> left_out_on_rails;

  /// What the finding of effect `cause` is, at the parameters `values` with their covariance
  /// (every parameter's row and column; empty when it could not be computed), when its parameters
  /// make it another effect; nothing when it is what its name says (the default).
  /// The causes identify() has a rule for (the others are not asked).
  std::vector<std::string> identifiable;
  /// Why the finding of effect `cause` at the parameters `values` lies outside the physical range
  /// of its quantity by a rule of the kind's own, or "" (the default): such a finding is never
  /// written into the extended model (Report::possible, with this reason). The engine applies the
  /// registry's rule to every finding first (an amount above its channel's full scale, a bound
  /// the logs push against).
  virtual std::string implausible(const std::string& cause, const std::vector<double>& values) const {
    (void)cause;
    (void)values;
    return "";
  }
  virtual std::optional<Identity> identify(const std::string& cause, const std::vector<double>& values,
                                           const Eigen::MatrixXd& covariance) const {
    (void)cause;
    (void)values;
    (void)covariance;
    return std::nullopt;
  }

  /// The reading's mean before the clamp and before `covariate:` terms, for residuals [0, needed)
  /// at least: kinds that simulate row after row (drive) may stop there and leave the rest unset.
  /// The rows are the caller's to say (no state is kept between calls: evaluations may run
  /// concurrently).
  virtual void mean(const double* p, double* out, std::size_t needed) const = 0;
  virtual void mean(const Jet* p, Jet* out, std::size_t needed) const = 0;
  virtual void mean(const ShortJet* p, ShortJet* out, std::size_t needed) const = 0;
  virtual void mean(const PairJet* p, PairJet* out, std::size_t needed) const = 0;

 protected:
  /// The kind's late covariates (add_late_covariates), in the order they are scored; none by default.
  virtual std::vector<LateCovariate> late_covariates() const { return {}; }

 private:
  bool late_covariates_added_ = false;
};

/// Every residual: the `needed` of a call that wants them all.
inline constexpr std::size_t kAllResiduals = std::numeric_limits<std::size_t>::max();

/// The double and Jet entry points of a kind written once as
/// `template <typename T> void eval(const T* p, T* out, std::size_t needed) const`.
template <class Kind>
class ProblemOf : public Problem {
 public:
  void mean(const double* p, double* out, std::size_t needed) const override { self().template eval<double>(p, out, needed); }
  void mean(const Jet* p, Jet* out, std::size_t needed) const override { self().template eval<Jet>(p, out, needed); }
  void mean(const ShortJet* p, ShortJet* out, std::size_t needed) const override { self().template eval<ShortJet>(p, out, needed); }
  void mean(const PairJet* p, PairJet* out, std::size_t needed) const override { self().template eval<PairJet>(p, out, needed); }

 private:
  const Kind& self() const { return *static_cast<const Kind*>(this); }
};

/// The problem for these logs (nullptr when the kind is not supported; `why` says so).
std::unique_ptr<Problem> make_problem(const std::vector<logs::Log>& logs, const Options& options, std::string& why);

/// Appends the covariates every kind shares: extra numeric columns (also as `covariate:` effects),
/// the row's position in its log, and the log (when several); per residual through `row`.
/// Columns named in `skip` are left out.
void add_common_covariates(Problem& p, const std::vector<logs::Log>& logs, const std::vector<std::string>& skip = {});

}  // namespace epuck2::diagnose::detail
