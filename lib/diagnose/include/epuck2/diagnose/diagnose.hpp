// Diagnosis (docs/diagnose.md): what the plug-in's model of a sensor gets wrong on a set of
// logs of one kind, why, and what fixing it gains on rows the fit did not see.
//
// For every row the base model of the kind (the plug-in's formula, lib/models) predicts the
// reading; the base model's free parameters are recalibrated; every effect of the catalogue that
// the logs can show is fitted jointly with them (Ceres) and evaluated on held-out rows (contiguous
// blocks of rows dealt round-robin into folds, so that neighbouring rows do not leak); an effect
// is kept only when the Bayesian information criterion on all rows and the held-out error agree.
// A greedy forward search keeps several. What the residuals still depend on is scored against
// every covariate (log columns and derived quantities).
//
// Supported kinds: every kind of docs/logs.md (see src/kinds.cpp; their effects: lib/models effects.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/fit/report.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/battery.hpp"
#include "epuck2/models/kinds.hpp"

namespace epuck2::diagnose {

struct NamedValue {
  NamedValue() = default;
  NamedValue(std::string name_, double value_, double std_error_, std::string why = {})
      : name(std::move(name_)), value(value_), std_error(std_error_), std_error_why(std::move(why)) {}
  std::string name;
  double value = 0;
  double std_error = 0;  ///< NaN when the covariance could not be computed
  std::string std_error_why;  ///< why std_error is NaN (ParameterEstimate::std_error_why)
  /// Time series (battery, drive): std_error times the residuals' autocorrelation correction
  /// (Report::autocorrelation); NaN for the other kinds or without a standard error.
  double std_error_corrected = std::numeric_limits<double>::quiet_NaN();
  /// Every kind: the delete-a-fold jackknife over the held-out folds' fits (contiguous blocks of
  /// rows), sqrt((G - 1)/G sum (theta_g - mean)^2); NaN with fewer than 3 folds.
  double std_error_jackknife = std::numeric_limits<double>::quiet_NaN();
};

struct Finding {
  /// What the misfit is: a catalogue name (lib/models effects.hpp), "covariate:COLUMN", or the
  /// name a finding gets when its fitted parameters make it something else (Problem::identify:
  /// "near_field_curve" for a long tail that replaces the near-field curve).
  std::string cause;
  /// The catalogue effect whose formula and parameters the finding carries into the extended
  /// model: `cause` unless the finding was renamed without changing its formula.
  std::string effect;
  /// The effect the search found, when the finding was renamed (empty otherwise); notes say why.
  std::string renamed_from;
  std::vector<NamedValue> parameters;  ///< the effect's parameters (catalogue names) in the final joint fit
  double heldout_mse_before = 0;       ///< held-out MSE of the reading (channel 0) without this effect
  double heldout_mse_after = 0;        ///< ... with it
  /// Held-out MSE of every residual, weighted by its channel's noise (what the decision uses);
  /// the same as the above with one channel.
  double heldout_weighted_before = 0, heldout_weighted_after = 0;
  double delta_bic = 0;                ///< BIC(with) - BIC(without), on all rows (negative = better)
  /// Other effects that fitted almost as well at the same step (BIC within Options::min_delta_bic
  /// and a held-out gain too): the data cannot tell them from this one.
  std::vector<std::string> alternatives;
  /// The model with this finding and those before it, fitted to all rows at its step: n, k,
  /// RSS (weighted residuals, in the reading's units squared), reduced chi^2, R^2, AIC, BIC
  /// (fit::FitStatistics conventions).
  fit::FitStatistics fit;
  /// Why the logs cannot determine it (Report::possible); empty for a finding that is kept.
  std::string undetermined;
  /// Report::possible: the reason is the physical-range rule's (the finding lies outside the
  /// physical range of its quantity: "not written"), not merely "possible, not determined".
  bool outside_physical_range = false;
  /// BIC(final model without it) - BIC(final model): what it carries of the gain in the end (the
  /// largest names the verdict; its delta_bic is what it gained at the step it joined).
  double removal_delta_bic = 0;
  /// The other effect of a pair accepted together (the pair search: neither passed alone);
  /// empty for a finding that passed alone. delta_bic is then the pair's, counted for both.
  std::string accepted_with;
};

struct CovariateScore {
  std::string covariate;
  double score = 0;         ///< fraction of the residual variance explained by the covariate's binned means
  bool significant = false; ///< both statistically (F test, p < 1e-6) and practically (score >= threshold)
  std::string channel;      ///< with several measured quantities (drive: tof_mm, steps): where it was scored
  double size = 0;          ///< RMS of the binned means (in the residuals' units: channel 0's)
};

/// One candidate's evaluation during the search (for the report's "search" section).
struct Trial {
  int step = 0;
  std::string cause;
  double delta_bic = 0;
  double heldout_mse = 0;
  bool kept = false;
  bool screened_out = false;  ///< long logs: no gain on the leading residuals, not fitted to all
  /// The pair search: the other effect fitted jointly with `cause` (delta_bic and heldout_mse are
  /// the pair's); empty for a single effect.
  std::string with;
};

/// The base model a diagnosis starts from in place of the plug-in's published one (a calibration's
/// or an earlier diagnosis's coefficient file, `--coefficients FILE`): a kind's model type
/// (lib/models kinds.hpp). Its values are the model with every effect off: the recalibration
/// starts from them, and an effect found is a change from them. Battery tables: Options::
/// battery_tables.
using BaseModel = std::variant<std::monostate, models::sensors::ProximityModel, models::sensors::LightModel,
                               models::sensors::GroundModel, models::sensors::CameraModel, models::sensors::DriveModel>;

/// The kind of a base model's logs (std::monostate: none; throws std::invalid_argument).
logs::Kind base_model_kind(const BaseModel& m);

/// What a diagnosis concludes.
enum class Verdict {
  none,         ///< no effect found and nothing left in the residuals
  not_judged,   ///< too few rows to judge any effect (Report::too_few_rows): never "none"
  effect,       ///< effects found (the first, the largest gain, names the verdict) and nothing left
  unexplained,  ///< the residuals still depend on a covariate (structure_after says which)
};

struct Report {
  logs::Kind kind = logs::Kind::ground;
  bool supported = false;
  /// Too few rows to judge any effect (`message` says how many there are and how many are
  /// needed, `minimum_rows`): the report holds the plug-in's error on every row and verdict
  /// `not_judged` ("not judged (too few rows: N of M)", never "none"), with no recalibration, search or finding. The minimum is Options::folds times
  /// Options::rows_per_parameter times the parameters of the largest model the search tries
  /// first (the base model's free ones and the largest effect's), and at least one row in every
  /// block of every fold; the problem must also hold more residuals than twice all its
  /// parameters.
  bool too_few_rows = false;
  std::size_t minimum_rows = 0;  ///< rows needed to judge effects on these logs (0: not known)
  std::string message;  ///< why not supported, or notes
  std::size_t rows = 0;       ///< data rows in all logs
  std::size_t residuals = 0;  ///< residuals fitted (camera: two per row)
  /// The base model the logs were diagnosed against (Options::base_model; std::monostate: the
  /// plug-in's published one). The extended model is built on it.
  BaseModel base_model;
  Verdict verdict = Verdict::none;
  /// The finding that carries most of the gain (largest removal_delta_bic; null when none).
  const Finding* dominant() const;
  /// The verdict as the report writes it: "none", "unexplained", the dominant finding's cause, or
  /// "not judged (too few rows: N of M)" (N rows, M the minimum_rows).
  std::string verdict_name() const;
  std::vector<NamedValue> recalibrated;  ///< the base model's free parameters recalibrated alone (empty: none)
  /// The base model's free parameters in the final joint fit with every finding (what the extended
  /// model carries; the same as `recalibrated` without findings).
  std::vector<NamedValue> final_base;
  /// Goodness of fit of the recalibrated base model and of the final one (all rows), under the
  /// conventions of fit::FitStatistics; R^2 of the weighted residuals against the readings'
  /// spread about their channel's mean.
  fit::FitStatistics base_fit, final_fit;
  /// Correlations (|r| > 0.1) between the final model's free parameters.
  std::vector<fit::Correlation> correlations;
  /// The residuals are a time series (battery, drive): their lag-1 autocorrelation within each
  /// log, per channel, and the correction applied to every standard error (the largest channel's
  /// factor; NamedValue::std_error_corrected).
  bool time_series = false;
  fit::AutocorrelationCorrection autocorrelation;
  std::string autocorrelation_channel;  ///< the channel whose factor is applied
  std::size_t jackknife_folds = 0;      ///< folds behind NamedValue::std_error_jackknife
  /// Readings on a clamp, per rail (the residuals' readings at or below the low clamp, at or
  /// above the high one).
  std::size_t censored_below = 0, censored_above = 0;
  double noise_sd = 0;                   ///< residual standard deviation of the final model
  /// With several measured quantities (drive: ToF in mm, encoders in steps): each one's noise
  /// standard deviation, in its own units. Residuals are weighted by them and MSEs are given in
  /// the first one's units.
  std::vector<NamedValue> channel_noise_sd;
  double heldout_mse_plugin = 0;         ///< the plug-in's model with its published coefficients
  /// The same model's MSE against its reading itself, clamp(model) to the rails with no noise (what
  /// `simulate --like` writes without --noise), on every row: the number a user computes by hand.
  /// heldout_mse_plugin, like every held-out MSE, compares with the expected reading
  /// E[clamp(model + noise)], the noise sd estimated from the model's residuals.
  double mse_plugin_reading = 0;
  double heldout_mse_base = 0;           ///< the base model recalibrated
  double heldout_mse_final = 0;          ///< with every finding (these three: the reading, channel 0)
  double heldout_weighted_base = 0, heldout_weighted_final = 0;  ///< every channel, weighted
  std::vector<Finding> findings;
  /// Findings the search kept but the logs cannot determine (Finding::undetermined says why: a
  /// relative standard error beyond Options::max_relative_se, a parameter on its bound, or two
  /// findings whose parameters correlate beyond Options::max_correlation): "possible, not
  /// determined". They are left out of the final model and of the extended model (`-o`); their
  /// parameters are those of the joint fit in which they were judged.
  std::vector<Finding> possible;
  std::vector<CovariateScore> structure_before;  ///< residuals of the recalibrated base model
  std::vector<CovariateScore> structure_after;   ///< residuals after the findings (the JSON report's residual_structure)
  std::vector<Trial> trials;
  std::vector<std::string> effects_considered;
  std::vector<std::string> notes;  ///< decisions worth telling (e.g. a finding undone)
  /// Wild readings left out before anything was fitted (file:line and why; static kinds only).
  std::vector<std::string> outliers;
  std::size_t censored = 0;          ///< readings on a sensor's rails (censored: the Tobit likelihood)
  std::vector<std::string> warnings;  ///< sentences: what the report should not be read without
  /// For the figure (lib/plot): per residual, measured minus model before (recalibrated base) and
  /// after (final model), each in its own channel's units (drive: ToF in mm, encoders in steps;
  /// camera: two residuals per row, px then py), and the values of one covariate: the one the
  /// verdict names (unexplained), else the one the residuals depended on most before the findings
  /// when significant, else `row` ("predicted": the recalibrated base model's prediction).
  std::vector<double> residual_before, residual_after;
  std::vector<std::pair<std::string, std::vector<double>>> covariates;
  /// With several channels: each residual's channel (index into channel_noise_sd); empty with one.
  std::vector<std::uint8_t> residual_channel;
};

/// Where a diagnosis is (Options::progress): a stage, and within it `done` of `total` (0 of 0
/// when the stage has no count), with a detail such as the effect being fitted.
struct Progress {
  std::string stage;   ///< "screening", "recalibrating", "fitting effect", "held-out test", "residual structure"
  int step = 0;        ///< the search step (1-based) for "fitting effect" and "held-out test"
  int done = 0, total = 0;
  std::string detail;  ///< e.g. the effect's cause
};


struct Options {
  int folds = 5;
  int blocks_per_fold = 8;             ///< contiguous blocks of rows per fold
  /// Each fold must hold at least this many rows per parameter of the largest model the search
  /// tries first, or the logs are too few to judge effects (Report::too_few_rows).
  int rows_per_parameter = 3;
  double min_delta_bic = 10.0;         ///< "very strong" evidence on the BIC scale (Kass and Raftery 1995)
  double min_heldout_gain = 0.03;      ///< held-out MSE must fall by at least this fraction
  double structure_threshold = 0.03;   ///< practical size of a residual dependence (fraction of variance)
  int max_findings = 5;
  /// When no single effect passes a step, the pair search fits pairs of the pair_singles
  /// effects that gained most alone (each fitted with the current model) jointly, and accepts
  /// the best pair that passes the same two tests (docs/diagnose.md). False: greedy singles only.
  bool pair_search = true;
  int pair_singles = 4;
  /// A finding is not determined when a parameter's standard error exceeds this multiple of its
  /// size (its value, or its neutral value when that is larger: a scale near 1 is judged against 1)
  /// -- an order of magnitude: the logs say nothing of it.
  double max_relative_se = 10.0;
  /// ... or when a parameter of one finding correlates with one of another beyond this: the two
  /// are the same direction of misfit to these logs, and neither is determined.
  double max_correlation = 0.999;
  /// battery: the discharge model simulated (--battery-model, Cubic by default), in the
  /// corrected behaviour (smooth in its parameters), with these tables; none given: the plug-in's
  /// published tables.
  models::battery::Model battery_model = models::battery::Model::cubic;
  std::optional<models::battery::Tables> battery_tables;
  /// battery: the base model's capacity scale (a diagnosis file's; 1: the tables' own capacity).
  /// capacity_scale is then a change from it.
  double battery_capacity_k = 1.0;
  /// The other kinds: the base model (none: the plug-in's published one). Of the logs' kind, or
  /// the report is unsupported and says so.
  BaseModel base_model;
  /// The effects the search tries, by catalogue name (`covariate:NAME` included); empty: every
  /// effect the logs can show. A name the logs cannot show makes the report unsupported, with
  /// the names they can.
  std::vector<std::string> effects;
  /// Called as the diagnosis goes (from the calling thread; never does I/O itself): a program can
  /// show progress. Empty: not called.
  std::function<void(const Progress&)> progress;
};

/// The base model a diagnosis starts from, from a coefficient file's model of any kind
/// (coefficients::model_from_json): a battery model's tables and capacity scale into
/// Options::battery_tables and battery_capacity_k, and with `discharge_model` its discharge model
/// into battery_model; another kind's model into Options::base_model.
void set_base_model(Options& o, const coefficients::AnyModel& m, bool discharge_model);

/// The order a diagnosis takes its logs in, and lists them in its report: by path, byte order
/// (the held-out test's blocks are contiguous rows, so the order is part of the result).
inline bool taken_before(const std::string& a_path, const std::string& b_path) { return a_path < b_path; }

/// Diagnoses logs of one kind (all of `logs` must be of that kind), taken in the order of their
/// paths (taken_before) (the held-out test's blocks are contiguous rows: the same logs in any order give the same
/// report). Never throws for numerical trouble; an unsupported kind gives `supported = false`.
Report diagnose(const std::vector<logs::Log>& logs, const Options& options = {});
/// The same, releasing the logs once the diagnosis has taken what it needs from them (long logs:
/// their parsed cells are not kept beside the fits).
Report diagnose(std::vector<logs::Log>&& logs, const Options& options = {});

/// What a finding that names no catalogue effect means (a renamed finding, such as
/// near_field_curve), in plain words; the name itself for an unknown one. A catalogue effect's
/// meaning is in lib/models' registry (effects.hpp).
std::string finding_meaning(const std::string& cause);

/// Kinds that diagnose() supports.
bool supported(logs::Kind kind);

}  // namespace epuck2::diagnose
