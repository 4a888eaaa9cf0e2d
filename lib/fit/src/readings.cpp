// The engine's one treatment of readings on a rail and of channel weights (epuck2/fit/readings.hpp).
#include "epuck2/fit/readings.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace epuck2::fit {

namespace {
constexpr double kSqrt2 = 1.41421356237309504880;
constexpr double kLogSqrt2Pi = 0.91893853320467274178;  // log(sqrt(2 pi))
// Below this z the asymptotic series replaces erfc (erfc(21) ~ 1e-193 is still exact; the series
// is accurate to 1e-10 there).
constexpr double kTailZ = -30.0;
}  // namespace

double log_normal_cdf(double z) {
  if (z > kTailZ) return std::log(0.5 * std::erfc(-z / kSqrt2));
  const double z2 = z * z;
  return -0.5 * z2 - std::log(-z) - kLogSqrt2Pi + std::log1p(-1 / z2 + 3 / (z2 * z2) - 15 / (z2 * z2 * z2));
}

double normal_hazard_lower(double z) {
  if (z > kTailZ) {
    const double phi = std::exp(-0.5 * z * z - kLogSqrt2Pi);
    return phi / (0.5 * std::erfc(-z / kSqrt2));
  }
  const double z2 = z * z;
  return -z / (1 - 1 / z2 + 3 / (z2 * z2) - 15 / (z2 * z2 * z2));
}

Censoring censoring_at(double value, double low, double high) {
  if (value <= low) return Censoring::at_or_below;
  if (value >= high) return Censoring::at_or_above;
  return Censoring::none;
}

Residual reading_residual(double prediction, double reading, Censoring censoring, double sd, double scale) {
  Residual out;
  if (censoring == Censoring::none) {
    const double w = scale / sd;
    out.value = w * (reading - prediction);
    out.d_prediction = -w;
    return out;
  }
  // z: how far the latent prediction lies beyond the rail, in noise sd; -2 log Phi(z) is the
  // censored reading's -2 log-likelihood, signed like y - f.
  const double sign = censoring == Censoring::at_or_above ? 1.0 : -1.0;
  const double z = sign * (prediction - reading) / sd;
  const double r = std::sqrt(std::max(-2 * log_normal_cdf(z), 0.0));
  out.value = sign * scale * r;
  // d r / d z = -(phi/Phi) / r; negligible where the observation carries no information.
  out.d_prediction = r > 1e-150 ? -scale * normal_hazard_lower(z) / r / sd : 0.0;
  return out;
}

Channels::Channels(std::vector<Channel> channels) : channels_(std::move(channels)) {
  if (channels_.empty()) throw std::invalid_argument("fit::Channels: at least one channel");
  std::vector<double> sd;
  for (const Channel& c : channels_) sd.push_back(c.noise_sd);
  set_noise_sd(sd);
}

void Channels::set_noise_sd(const std::vector<double>& sd) {
  if (sd.size() != channels_.size()) throw std::invalid_argument("fit::Channels: one noise sd per channel");
  sd_ = sd;
  // Per channel, not per residual: every residual of a channel has the same weight.
  weight_.resize(sd_.size());
  for (std::size_t c = 0; c < sd_.size(); ++c) {
    channels_[c].noise_sd = sd_[c];
    weight_[c] = sd_[0] / sd_[c];
  }
}

Residual Channels::residual(double prediction, double reading, std::size_t c) const {
  const Channel& ch = channels_[c];
  const Censoring censoring = censoring_at(reading, ch.rail_lo, ch.rail_hi);
  const double at = censoring == Censoring::at_or_below ? ch.rail_lo : censoring == Censoring::at_or_above ? ch.rail_hi : reading;
  return reading_residual(prediction, at, censoring, sd_[c], sd_[0]);
}

}  // namespace epuck2::fit
