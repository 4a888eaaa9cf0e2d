// The diagnosis's ground kind: its base model and catalogue effects (see kinds.cpp).
#include "kind_common.hpp"

namespace epuck2::diagnose {

using namespace epuck2::fit;  // the engine (lib/fit)

namespace detail {
using namespace kinds_shared;  // the kinds' shared helpers
namespace {

/// Sensor gains whose equality the Wald test of their differences does not reject at this level are one common gain.
constexpr double kEqualGainsP = 0.01;

// ---------------------------------------------------------------------------------------------
// ground: v = 1023 grey (the plug-in's source); catalogue: black_offset, white_level,
// sensor_gain, nonlinear_response, sensor_offset (each sensor's own black offset, relative to the
// lowest-numbered sensor logged). Combined: v = o_s + (level - o_s) g_s grey^p with o_s = offset + offsets[s].
class Ground : public ProblemOf<Ground> {
 public:
  using BaseModel = s::GroundModel;
  explicit Ground(const std::vector<logs::Log>& logs) {
    for (const auto& log : logs) {
      const auto& g = log.col("grey");
      const auto& sn = log.col("sensor");
      const auto& v = log.col("value");
      for (std::size_t i = 0; i < log.rows(); ++i) {
        grey_.push_back(g[i]);
        sensor_.push_back(static_cast<int>(sn[i]));
        y.push_back(v[i]);
        row.push_back(rows++);
      }
    }
    channel_lo = {0.0};
    channel_hi = {s::kGroundFullScale_raw};
    const fx::Catalogue& c = fx::ground_catalogue();
    ix_ = add_catalogue(*this, c);
    offset_ = ix_[fx::ground::black_offset][0][0];
    level_ = ix_[fx::ground::white_level][0][0];
    for (std::size_t k = 0; k < gain_.size(); ++k) gain_[k] = ix_[fx::ground::sensor_gain][0][k];
    for (std::size_t k = 0; k < sensor_offset_.size(); ++k) sensor_offset_[k] = ix_[fx::ground::sensor_offset][0][k];
    // Per-sensor gains of the sensors seen; per-sensor black offsets (the real robots' ground
    // sensors differ over black) relative to the lowest-numbered sensor logged, whose offset is the common
    // black_offset.
    const auto seen = sensors_seen(std::vector<double>(sensor_.begin(), sensor_.end()));
    std::vector<int> gains, offsets;
    for (int k : seen)
      if (k >= 0 && k < s::kGroundCount) gains.push_back(gain_[static_cast<std::size_t>(k)]);
    for (std::size_t j = 1; j < seen.size(); ++j)
      if (seen[j] >= 0 && seen[j] < s::kGroundCount) offsets.push_back(sensor_offset_[static_cast<std::size_t>(seen[j])]);
    effect_of(*this, c, fx::ground::sensor_gain).params = gains;
    effect_of(*this, c, fx::ground::sensor_offset).params = offsets;
    // The order the engine tries them in: the common offset and level first.
    if (offsets.empty()) drop_effect(*this, c, fx::ground::sensor_offset);
    if (gains.size() < 2) drop_effect(*this, c, fx::ground::sensor_gain);
    std::stable_partition(effects.begin(), effects.end(), [&](const Effect& e) {
      return e.cause != c[fx::ground::sensor_gain].name && e.cause != c[fx::ground::sensor_offset].name;
    });
    identifiable = {c[fx::ground::sensor_gain].name};
    std::vector<double> sensor_d(sensor_.begin(), sensor_.end());
    covariates.emplace_back("grey", grey_);
    covariates.emplace_back("sensor", std::move(sensor_d));
  }
  /// Sensor gains equal within their errors are one white level common to every sensor: the
  /// finding is white_level, level = offset + (level - offset) g with g the gains' mean. Equal
  /// within their errors: the Wald test of the S - 1 differences from the first sensor's gain,
  /// with their covariance (the gains are correlated through the offsets), does not reject at
  /// kEqualGainsP.
  std::optional<Identity> identify(const std::string& cause, const std::vector<double>& values,
                                   const Eigen::MatrixXd& covariance) const override {
    const fx::Catalogue& c = fx::ground_catalogue();
    if (cause != c[fx::ground::sensor_gain].name || values[static_cast<std::size_t>(level_)] != params[static_cast<std::size_t>(level_)].fallback)
      return std::nullopt;  // a white level already in the model: the gains are its sensors' spread
    std::vector<std::size_t> g;  // the gains' parameter indices, sensors seen
    for (int k : sensors_seen(std::vector<double>(sensor_.begin(), sensor_.end())))
      if (k >= 0 && k < s::kGroundCount) g.push_back(static_cast<std::size_t>(gain_[static_cast<std::size_t>(k)]));
    const Eigen::Index P = static_cast<Eigen::Index>(params.size());
    if (g.size() < 2 || covariance.rows() != P || covariance.cols() != P) return std::nullopt;
    const Eigen::Index m = static_cast<Eigen::Index>(g.size()) - 1;
    Eigen::VectorXd d(m);
    Eigen::MatrixXd V(m, m);
    const auto cov = [&](std::size_t a, std::size_t b) { return covariance(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)); };
    for (Eigen::Index a = 0; a < m; ++a) {
      const std::size_t ia = g[static_cast<std::size_t>(a) + 1];
      d(a) = values[ia] - values[g[0]];
      for (Eigen::Index b = 0; b < m; ++b) {
        const std::size_t ib = g[static_cast<std::size_t>(b) + 1];
        V(a, b) = cov(ia, ib) - cov(ia, g[0]) - cov(g[0], ib) + cov(g[0], g[0]);
      }
    }
    if (!V.allFinite() || !d.allFinite()) return std::nullopt;
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(V);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) return std::nullopt;  // no errors: no test
    const double wald = d.dot(ldlt.solve(d));
    const double dof = static_cast<double>(m);
    const double p_value = chi2_upper_tail(wald, dof);
    if (!(p_value >= kEqualGainsP)) return std::nullopt;
    double mean = 0;
    for (std::size_t j : g) mean += values[j] / static_cast<double>(g.size());
    const double offset = values[static_cast<std::size_t>(offset_)];
    const double level = offset + (values[static_cast<std::size_t>(level_)] - offset) * mean;
    char why[300];
    std::snprintf(why, sizeof why,
                  "the %zu sensor gains are equal within their errors (Wald test of their differences with their covariance: "
                  "%.3g on %g degrees of freedom, p = %.2g): one white level common to every sensor, %.4g",
                  g.size(), wald, dof, p_value, level);
    return Identity{c[fx::ground::white_level].name, why, c[fx::ground::white_level].name, {{level_, level}}};
  }

  /// A calibrated base: each sensor's own offset and gain, and its nonlinear response.
  void set_base_model(const s::GroundModel& m) {
    base_ = m.sensors;
    set_base_effects(*this, ix_, m.effects);
  }

  // The catalogue's parameters map onto lib/models' ground response, relative to each sensor's
  // base (B_s over black, G_s from black to white; the plug-in's: 0 and 1023): sensor s has the
  // black offset B_s + o_s and the gain G_s (level - o_s) / 1023 g_s, with o_s = offset +
  // offsets[s]; exponent is the nonlinear response. With the plug-in's base: o_s and
  // (level - o_s) g_s.
  template <typename T>
  void eval(const T* p, T* out, std::size_t /*needed: every row is computed*/) const {
    s::GroundNonlinear<T> nonlinear;
    fill_effects(ix_, p, nonlinear);
    std::array<T, s::kGroundCount> gain, offset;
    for (std::size_t k = 0; k < gain.size(); ++k) {
      const T black = p[offset_] + p[sensor_offset_[k]];
      gain[k] = (p[level_] - black) * p[gain_[k]] * (base_[k].gain_raw / s::kGroundFullScale_raw);
      offset[k] = black + base_[k].offset_raw;
    }
    for (std::size_t i = 0; i < grey_.size(); ++i) {
      const std::size_t k = static_cast<std::size_t>(sensor_[i]);
      out[i] = s::ground_mean_raw(offset[k], gain[k], nonlinear, grey_[i]);
    }
  }

 private:
  std::vector<double> grey_;
  std::vector<int> sensor_;
  std::array<s::GroundCoefficients, s::kGroundCount> base_{s::kPluginGround, s::kPluginGround, s::kPluginGround};
  CatalogueIndex ix_;
  int offset_ = 0, level_ = 0;
  std::array<int, s::kGroundCount> gain_{}, sensor_offset_{};
};

}  // namespace

std::unique_ptr<Problem> make_ground(const std::vector<logs::Log>& logs, const Options& options) {
  return with_base(std::make_unique<Ground>(logs), options);
}

}  // namespace detail
}  // namespace epuck2::diagnose
