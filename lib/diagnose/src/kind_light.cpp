// The diagnosis's light kind: its base model and catalogue effects (see kinds.cpp).
#include "kind_common.hpp"

namespace epuck2::diagnose {

using namespace epuck2::fit;  // the engine (lib/fit)

namespace detail {
using namespace kinds_shared;  // the kinds' shared helpers
namespace {

// ---------------------------------------------------------------------------------------------
// light: v = 4095 clamp01(1 - (gamma I / d)^2) for d <= 0.5 m, else 4095 (paper Eq. 2, reference
// section 2.2); gamma free (a base model's per-sensor gammas: gamma r_s, r_s held). Catalogue: ambient_offset, falloff_exponent, sensor_gain. Combined:
// v = 4095 (1 - g_s (gamma I / d)^p) - offset.
class Light : public ProblemOf<Light> {
 public:
  using BaseModel = s::LightModel;
  explicit Light(const std::vector<logs::Log>& logs) {
    channel_lo = {0.0};
    channel_hi = {s::kProximityFullScale_raw};
    // The phototransistor saturates at 0 in bright light before its noise (docs/diagnose.md);
    // in the dark its reading is the register's rail.
    channel_saturation_lo = {0.0};
    for (const auto& log : logs) {
      const auto& d = log.col("distance_m");
      const auto& in = log.col("intensity");
      const auto& sn = log.col("sensor");
      const auto& v = log.col("value");
      for (std::size_t i = 0; i < log.rows(); ++i) {
        distance_.push_back(d[i]);
        intensity_.push_back(in[i]);
        sensor_.push_back(static_cast<int>(sn[i]));
        y.push_back(v[i]);
        row.push_back(rows++);
      }
    }
    gamma_ = add_param(*this, "gamma_m", s::kPluginLight.gamma_m, s::kPluginLight.gamma_m, 1e-4, 10.0);
    base_free = {gamma_};
    const fx::Catalogue& c = fx::light_catalogue();
    ix_ = add_catalogue(*this, c);
    const auto seen = sensors_seen(std::vector<double>(sensor_.begin(), sensor_.end()));
    std::vector<int> gains;
    for (std::size_t j = 1; j < seen.size(); ++j) gains.push_back(ix_[fx::light::sensor_gain][0][static_cast<std::size_t>(seen[j])]);
    effect_of(*this, c, fx::light::sensor_gain).params = gains;
    if (gains.empty()) drop_effect(*this, c, fx::light::sensor_gain);
    range_m_ = s::kPluginLight.range_m;
    std::vector<double> sensor_d(sensor_.begin(), sensor_.end());
    covariates.emplace_back("distance_m", distance_);
    covariates.emplace_back("intensity", intensity_);
    covariates.emplace_back("sensor", std::move(sensor_d));
  }
  /// A calibrated base: its gamma, its per-sensor gammas (held in proportion to the pooled one,
  /// which the recalibration fits: s::light_gamma_ratio, exactly 1 for a sensor without its own)
  /// and the effects it already carries.
  void set_base_model(const s::LightModel& m) {
    set_base(*this, gamma_, m.base.gamma_m);
    for (std::size_t k = 0; k < ratio_.size(); ++k) ratio_[k] = s::light_gamma_ratio(m, static_cast<int>(k));
    range_m_ = m.base.range_m;
    set_base_effects(*this, ix_, m.effects);
  }

  template <typename T>
  void eval(const T* p, T* out, std::size_t /*needed: every row is computed*/) const {
    s::LightEffects<T> e;
    fill_effects(ix_, p, e);
    for (std::size_t i = 0; i < distance_.size(); ++i)
      out[i] = s::light_mean_raw(T(p[gamma_] * ratio_[static_cast<std::size_t>(sensor_[i])]), range_m_, e, sensor_[i], intensity_[i],
                                 distance_[i]);
  }

 private:
  std::vector<double> distance_, intensity_;
  std::vector<int> sensor_;
  CatalogueIndex ix_;
  int gamma_ = 0;
  std::array<double, s::kProximityCount> ratio_{1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0};  ///< sensor's gamma / pooled
  double range_m_ = 0.5;
};

}  // namespace

std::unique_ptr<Problem> make_light(const std::vector<logs::Log>& logs, const Options& options) {
  return with_base(std::make_unique<Light>(logs), options);
}

}  // namespace detail
}  // namespace epuck2::diagnose
