// The diagnosis's proximity kind: its base model and catalogue effects (see kinds.cpp).
#include "kind_common.hpp"

namespace epuck2::diagnose {

using namespace epuck2::fit;  // the engine (lib/fit)

namespace detail {
using namespace kinds_shared;  // the kinds' shared helpers
namespace {

/// A long tail carrying more than this share of the modelled near-field reading replaces it.
constexpr double kTailShareOfNearField = 0.5;

// ---------------------------------------------------------------------------------------------
// proximity: v = 4095 clamp01(a d^2 + b d + c) for d <= 0.05 m, else 0 (paper Eq. 1, reference
// section 2.1); a, b, c free. Catalogue: ambient_offset, sensor_gain, long_tail, incidence_angle,
// saturation. Combined: v = min(g_s cos(theta)^k 4095 clamp01(poly) [d <= range] + offset
// + amplitude exp(-d / length), level).
class Proximity : public ProblemOf<Proximity> {
 public:
  using BaseModel = s::ProximityModel;
  explicit Proximity(const std::vector<logs::Log>& logs) {
    channel_lo = {0.0};
    channel_hi = {s::kProximityFullScale_raw};
    bool angle = true;
    for (const auto& log : logs) angle = angle && log.has("angle_deg");
    for (const auto& log : logs) {
      const auto& d = log.col("distance_m");
      const auto& sn = log.col("sensor");
      const auto& v = log.col("value");
      for (std::size_t i = 0; i < log.rows(); ++i) {
        distance_.push_back(d[i]);
        sensor_.push_back(static_cast<int>(sn[i]));
        cos_.push_back(angle ? std::cos(s::deg_to_rad(log.col("angle_deg")[i])) : 1.0);
        y.push_back(v[i]);
        row.push_back(rows++);
      }
    }
    const auto& k = s::kPluginProximity;
    a_ = add_param(*this, "a", k.a_per_m2, k.a_per_m2);
    add_param(*this, "b", k.b_per_m, k.b_per_m);
    add_param(*this, "c", k.c, k.c);
    base_free = {a_, a_ + 1, a_ + 2};
    const fx::Catalogue& c = fx::proximity_catalogue();
    ix_ = add_catalogue(*this, c);
    amplitude_ = ix_[fx::proximity::long_tail][0][0];
    // The saturation level starts at the highest reading.
    double top = 0;
    for (double v : y) top = std::max(top, v);
    params[static_cast<std::size_t>(ix_[fx::proximity::saturation][0][0])].value = top;
    // A tail may carry the whole response (a sensor whose curve is an exponential, not Eq. 1's
    // quadratic): from the registry's small start alone the fit stays in a local minimum where
    // the quadratic keeps most of it. More starts: the tail at the highest reading, short to long.
    params[static_cast<std::size_t>(amplitude_)].other_starts = {top, top, top};
    params[static_cast<std::size_t>(ix_[fx::proximity::long_tail][1][0])].other_starts = {0.005, 0.01, 0.04};
    identifiable = {c[fx::proximity::long_tail].name};
    // With a, b, c free the overall gain is theirs: the lowest-numbered sensor logged is the reference (1).
    const auto seen = sensors_seen(std::vector<double>(sensor_.begin(), sensor_.end()));
    std::vector<int> gains;
    for (std::size_t j = 1; j < seen.size(); ++j) gains.push_back(ix_[fx::proximity::sensor_gain][0][static_cast<std::size_t>(seen[j])]);
    effect_of(*this, c, fx::proximity::sensor_gain).params = gains;
    if (gains.empty()) drop_effect(*this, c, fx::proximity::sensor_gain);
    bool angles_vary = false;
    for (double v : cos_) angles_vary = angles_vary || std::abs(v - cos_.front()) > 1e-9 || v < 1.0 - 1e-12;
    if (!(angle && angles_vary)) drop_effect(*this, c, fx::proximity::incidence_angle);
    // The order the engine tries them in (as before the registry): the common effects first.
    std::stable_partition(effects.begin(), effects.end(), [&](const Effect& e) {
      return e.cause != c[fx::proximity::sensor_gain].name && e.cause != c[fx::proximity::incidence_angle].name;
    });
    range_m_ = k.range_m;
    std::vector<double> sensor_d(sensor_.begin(), sensor_.end());
    covariates.emplace_back("distance_m", distance_);
    covariates.emplace_back("sensor", std::move(sensor_d));
    if (angle) {
      std::vector<double> a;
      for (const auto& log : logs)
        for (double x : log.col("angle_deg")) a.push_back(x);
      covariates.emplace_back("angle_deg", std::move(a));
    }
  }
  /// A calibrated base: its quadratic and the effects it already carries.
  void set_base_model(const s::ProximityModel& m) {
    set_base(*this, a_, m.base.a_per_m2);
    set_base(*this, a_ + 1, m.base.b_per_m);
    set_base(*this, a_ + 2, m.base.c);
    range_m_ = m.base.range_m;
    set_base_effects(*this, ix_, m.effects);
  }

  /// A long tail that carries most of the modelled reading within the base model's range
  /// (d <= its cut-off) replaces the near-field curve instead of extending it beyond the cut-off:
  /// the finding is the near-field curve's shape (near_field_curve), the same formula renamed.
  std::optional<Identity> identify(const std::string& cause, const std::vector<double>& values,
                                   const Eigen::MatrixXd& /*covariance*/) const override {
    if (cause != fx::proximity_catalogue()[fx::proximity::long_tail].name) return std::nullopt;
    std::vector<double> with(distance_.size()), without(distance_.size());
    eval<double>(values.data(), with.data(), kAllResiduals);
    std::vector<double> off = values;
    off[static_cast<std::size_t>(amplitude_)] = params[static_cast<std::size_t>(amplitude_)].fallback;
    eval<double>(off.data(), without.data(), kAllResiduals);
    double tail = 0, total = 0, beyond = 0;
    std::size_t near = 0;
    for (std::size_t i = 0; i < distance_.size(); ++i) {
      // The tail's share of the reading as the sensor reports it (both clipped at full scale).
      const double t = std::max(0.0, std::min(with[i], s::kProximityFullScale_raw) - std::min(without[i], s::kProximityFullScale_raw));
      if (distance_[i] <= range_m_) {
        tail += t;
        total += std::max(0.0, std::min(with[i], s::kProximityFullScale_raw));
        ++near;
      } else {
        beyond = std::max(beyond, t);
      }
    }
    if (near == 0 || !(total > 0) || tail <= kTailShareOfNearField * total) return std::nullopt;
    char why[300];
    std::snprintf(why, sizeof why,
                  "the fitted tail carries %.0f %% of the modelled reading within the base model's range (d <= %.3g m, %zu "
                  "rows) and at most %.3g counts beyond it: it replaces the near-field curve, it is not a tail",
                  100.0 * tail / total, range_m_, near, beyond);
    return Identity{"near_field_curve", why, "", {}};
  }

  template <typename T>
  void eval(const T* p, T* out, std::size_t /*needed: every row is computed*/) const {
    s::ProximityEffects<T> e;
    fill_effects(ix_, p, e);
    for (std::size_t i = 0; i < distance_.size(); ++i)
      out[i] = s::proximity_mean_raw(p + a_, range_m_, e, sensor_[i], distance_[i], cos_[i]);
  }

 private:
  std::vector<double> distance_, cos_;
  std::vector<int> sensor_;
  CatalogueIndex ix_;
  int a_ = 0, amplitude_ = 0;
  double range_m_ = 0.05;
};

}  // namespace

std::unique_ptr<Problem> make_proximity(const std::vector<logs::Log>& logs, const Options& options) {
  return with_base(std::make_unique<Proximity>(logs), options);
}

}  // namespace detail
}  // namespace epuck2::diagnose
