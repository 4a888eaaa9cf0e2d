// The engine's one treatment of readings (docs/fitting.md, "Readings on a rail"): readings clipped
// at a sensor's rails (censoring) and readings of several channels in different units (channel
// weights). Every fit that meets a rail or several channels goes through here: the censored
// robust fit of the calibration (fit_robust) and the diagnosis's joint fit alike.
//
// A reading is the latent prediction f plus Gaussian noise of sd `sd`, clipped by the register at
// its rails: clamp(f + e, rail_lo, rail_hi). A reading inside the rails is exact; one on a rail
// says only that f + e lies at or beyond it. The likelihood is Tobit's, written as residuals whose
// half sum of squares is the negative log-likelihood (up to constants):
//
//   none:         r = scale / sd (y - f)
//   at_or_above:  r =  scale sqrt(-2 log Phi((f - rail) / sd))
//   at_or_below:  r = -scale sqrt(-2 log Phi((rail - f) / sd))
//
// signed like y - f (a reading on the high rail lies above a curve below it). `scale` is the
// square root of the observation's weight: 1 for residuals in noise sd, or the reference channel's
// sd for residuals in that channel's units (Channels). A sensor that saturates *before* its noise
// (a phototransistor at 0 in bright light) is a model term, not a loss: the latent prediction is
// then the saturated model (lib/models saturation.hpp), and its readings on the rail are censored
// here like any other.
//
// Ceres-free: a caller may include it without the solver.
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

namespace epuck2::fit {

enum class Censoring { none, at_or_below, at_or_above };

/// A reading's censoring against a sensor's two rails: at or below `low`, at or above `high`, or
/// none (±inf: no rail on that side).
Censoring censoring_at(double value, double low, double high);

/// One observation's residual and its derivative over the latent prediction.
struct Residual {
  double value = 0;
  double d_prediction = 0;
};

/// The residual of the reading `reading` (the rail itself when censored) against the latent
/// prediction `prediction`, with noise sd `sd` and weight scale^2 (the formulas at the top).
Residual reading_residual(double prediction, double reading, Censoring censoring, double sd, double scale);

/// log Phi(z), accurate far into the lower tail.
double log_normal_cdf(double z);
/// phi(z) / Phi(z), accurate far into the lower tail.
double normal_hazard_lower(double z);

/// One channel's rails and noise.
struct Channel {
  double rail_lo = -std::numeric_limits<double>::infinity();
  double rail_hi = std::numeric_limits<double>::infinity();
  double noise_sd = 1.0;
};

/// Channel weights and rails: readings of several channels (the drive's ToF in mm and encoders in
/// steps) in one fit. Channel c's residuals are weighted by sd_0 / sd_c, i.e. expressed in channel
/// 0's units: a reading one of its own noise sd off counts as one of channel 0's. Its readings at
/// or beyond its rails are censored there (reading_residual).
class Channels {
 public:
  Channels() : Channels(std::vector<Channel>(1)) {}
  explicit Channels(std::vector<Channel> channels);

  std::size_t size() const { return channels_.size(); }
  const Channel& operator[](std::size_t c) const { return channels_[c]; }
  /// Sets every channel's noise sd (one per channel).
  void set_noise_sd(const std::vector<double>& sd);
  const std::vector<double>& noise_sd() const { return sd_; }
  /// Channel c's weight on a residual in its units, sd_0 / sd_c.
  double weight(std::size_t c) const { return weight_[c]; }

  /// A reading of channel c against the latent prediction: censored at the channel's rails.
  Residual residual(double prediction, double reading, std::size_t c) const;
  /// The weighted difference between a reading and a prediction of the reading itself (its
  /// expected value, not the latent one), in channel 0's units: no censoring.
  double weighted_error(double predicted_reading, double reading, std::size_t c) const {
    return reading_residual(predicted_reading, reading, Censoring::none, sd_[c], sd_[0]).value;
  }

 private:
  std::vector<Channel> channels_;
  std::vector<double> sd_, weight_;
};

}  // namespace epuck2::fit
