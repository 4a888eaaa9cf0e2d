// Battery calibration: from discharge logs to the four models' coefficient tables (paper §4.1.7
// and Appendix), with uncertainties, and the paper's Table 5.
//
// Per speed (the logs of every robot at that speed pooled):
//  * lifetime: the mean of the runs' stop times (their last rows), standard error over runs;
//  * Cubic: least-squares cubic charge(t) = a t^3 + b t^2 + c t + d (fitted in scaled time
//    u = t / lifetime, coefficients and covariance transformed back);
//  * Linear: the paper's line from 1 at t = 0 to 0 at the lifetime, slope -1/lifetime (the
//    plug-in's L table), and for reference a free least-squares line;
//  * Approximated: a continuous piecewise line through (0, 1), two fitted breakpoints and the
//    point at lifetime - 1 s, followed by the plug-in's 1-second drop to 0 at the lifetime: four
//    segments M1..M4 in the plug-in's format. Breakpoints by a grid search on the profile of the
//    linear sub-problem, refined jointly with the knot values in Ceres;
//  * Simple: m0 = -1/lifetime(0), m1 = -1/mean(lifetime of the moving speeds).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "epuck2/calibrate/engine.hpp"
#include "epuck2/fit/least_squares.hpp"
#include "epuck2/fit/report.hpp"
#include "epuck2/fit/robust.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/battery.hpp"
#include "epuck2/models/battery_simulation.hpp"

namespace epuck2::calibrate {

/// One discharge run at constant speed.
struct BatteryRun {
  std::string path;
  std::string robot;
  double speed_cm_s = 0;
  double lifetime_s = 0;  ///< time of the last row
  std::vector<double> time_s;
  std::vector<double> charge;
  std::vector<models::battery::ProfilePoint> profile;  ///< the logged speed profile
  std::vector<int> line;  ///< source line of each row
  bool charge_from_voltage = false;  ///< the charge was computed from voltage_v through a map
};

/// Turns validated battery logs into runs. A run must hold one speed (the calibration protocol);
/// a log whose speed changes is rejected with the line where it changes. A log without `charge`
/// (voltage only) is rejected at its header, saying how to give a voltage->charge map.
std::vector<BatteryRun> battery_runs(const std::vector<logs::Log>& logs);

struct ChargeMap;  // epuck2/calibrate/charge_map.hpp

/// What converting voltage-only logs did (battery_runs with a map).
struct ChargeConversionReport {
  std::size_t logs = 0;          ///< voltage-only logs converted
  std::size_t rows = 0;          ///< their rows
  std::size_t below_range = 0;   ///< voltages below the map's range, clamped to its lowest charge
  std::size_t above_range = 0;   ///< ... above it, clamped to its highest charge
  std::vector<std::string> clamped;  ///< the first 10 clamped rows, "file:line (V)"
};

/// battery_runs, with the charge of every log that has `voltage_v` and no `charge` computed
/// through `map` (convert_voltage); logs with a `charge` column keep it. A speed outside the
/// map's load term is rejected at that row (InputError). `report` (optional) counts the rows
/// converted and clamped.
std::vector<BatteryRun> battery_runs(const std::vector<logs::Log>& logs, const ChargeMap* map,
                                     ChargeConversionReport* report = nullptr);

struct ModelMse {
  double simple = 0, linear = 0, cubic = 0, approximated = 0;
  double get(models::battery::Model m) const;
  double& get(models::battery::Model m);
};

struct SpeedFit {
  double speed_cm_s = 0;
  std::size_t runs = 0;
  std::size_t observations = 0;
  double lifetime_s = 0;
  double lifetime_std_error_s = 0;  ///< standard error of the mean over runs (0 with one run)
  FitResult cubic;                  ///< parameters d, c, b, a (charge(t), t in s)
  FitResult free_line;              ///< parameters intercept, slope_per_s (least squares, reference only)
  double linear_slope_per_s = 0;    ///< the paper's: -1/lifetime
  double linear_slope_std_error = 0;
  FitResult piecewise;              ///< knots x1_s, x2_s, y1, y2, y3 (x0 = 0, y0 = 1, x3 = lifetime - 1)
  std::array<models::battery::Segment, models::battery::kSegmentCount> segments{};
  ModelMse mse;                     ///< analytic MSE of each model's function against these logs
  std::vector<std::string> outliers;  ///< readings left out of every model at this speed (file:line)
  double noise_sd = 0;              ///< robust sd of the cubic's residuals (1.4826 MAD)
  /// The cubic's lack of fit against the replicates: the readings of the runs at this speed taken
  /// at the same time (fit::lack_of_fit; the CLI stops on fit::misfit_verdict, as the sensors do).
  fit::LackOfFit cubic_lack_of_fit;
  /// A discharge run is a time series: each fit's residuals are autocorrelated within a run, and
  /// its covariance's standard errors need this correction (epuck2/fit/report.hpp).
  fit::AutocorrelationCorrection cubic_autocorrelation, free_line_autocorrelation, piecewise_autocorrelation;
};

struct BatteryFit {
  std::vector<SpeedFit> speeds;  ///< sorted by speed
  double simple_static_slope_per_s = 0, simple_static_std_error = 0;
  double simple_moving_slope_per_s = 0, simple_moving_std_error = 0;
  ModelMse mse;  ///< analytic MSE averaged over speeds (the paper's Table 5 "analytic")
  /// The four models' tables when the logs cover every integer speed 0..15 cm/s.
  std::optional<models::battery::Tables> tables;
  std::vector<std::string> sources;
  /// What the logs leave weak, in sentences: a speed with fewer than kBatteryRowsPerParameter rows
  /// per parameter of a model, a speed with one run (no lifetime uncertainty), no run at rest or
  /// none moving (a Simple slope taken from the other, or not determined).
  std::vector<std::string> warnings;
};

/// Why a speed's lifetime (and so its Linear slope) has no standard error, when it has none: "the
/// end of the only run's log" (one run) or "the runs end at the same time" (two or more runs
/// whose ends agree); "" when it has one.
std::string lifetime_no_error_why(const SpeedFit& s);
/// Why the Simple model's static slope m0 has no standard error, from the runs the fit had: no run
/// at 0 cm/s (m0 is m1), one run there, or runs there ending at the same time; "" when it has one.
std::string simple_static_no_error_why(const BatteryFit& f);
/// Why the moving slope m1 has none: no moving run, or every moving speed with one run or runs
/// ending at the same time (said as they are); "" when it has one.
std::string simple_moving_no_error_why(const BatteryFit& f);

/// Below this many rows per parameter at a speed (cubic: 4 parameters, approximated: 5) the fit
/// is said to be barely determined (a warning). Fewer rows than parameters + 1 and the fit is
/// refused (its FitResult is not usable, with the reason).
inline constexpr std::size_t kBatteryRowsPerParameter = 3;

/// The speeds of a fit by value (cm/s): those covered, the whole speeds 0..15 that are missing
/// (complete tables need every one), and those covered that are not one of them.
struct SpeedCoverage {
  std::vector<double> covered, missing, other;
};
SpeedCoverage speed_coverage(const BatteryFit& fit);
/// "0, 1, 2.5" (each %g); "none" when empty.
std::string speeds_text(const std::vector<double>& speeds_cm_s);

/// Fits everything. Never throws for numerical trouble: a speed whose fit is unusable carries
/// the reason in its FitResult::message.
/// Readings farther than `reject_sd` robust sd (1.4826 MAD of the cubic's residuals) from the
/// per-speed cubic are left out of every model at that speed and listed (0: keep every reading,
/// plain least squares).
inline constexpr double kBatteryRejectSd = 6.0;
BatteryFit fit_battery(const std::vector<BatteryRun>& runs, const FitOptions& options = {},
                       double reject_sd = kBatteryRejectSd);

/// Runs of more than one robot: battery pools them (one table per speed over every run) and does
/// not fit or compare the robots one by one, as the sensor fits do (docs/fitting.md, "Several
/// robots"). Said with the robots' mean run lifetimes (their last rows' times) at the speed where
/// they differ most, so that robots whose batteries differ are seen; "" for one robot.
std::string pooled_robots_warning(const std::vector<BatteryRun>& runs);

/// The four models' analytic charge at time t for one speed's fit: Simple and Linear clamped at 0,
/// Approximated as its segments M1..M4 are written (0 from the lifetime on, after M4's drop).
double analytic_charge(const SpeedFit& s, const BatteryFit& all, models::battery::Model m, double t_s);

/// Runs a runtime model over each log's own speed profile at `dt` from full charge and returns
/// the MSE against the log's charge, averaged over the speeds (runs of a speed pooled).
ModelMse simulated_mse(const std::vector<BatteryRun>& runs, const models::battery::Tables& tables,
                       models::battery::Behaviour behaviour, double dt_s = 0.1);

/// The plug-in's tables derived from a fit (requires fit.tables).
models::battery::Tables tables_from_fit(const BatteryFit& fit);

}  // namespace epuck2::calibrate
