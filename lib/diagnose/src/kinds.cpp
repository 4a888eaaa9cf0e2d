// The kinds' base models and catalogue effects for the diagnosis (docs/diagnose.md, "The
// catalogue"), each written once, templated on the scalar, over every row of the logs. Every
// effect is a parameter set whose neutral values give back the base model, so that the engine
// switches effects on by freeing their parameters.
#include <algorithm>
#include <cstdio>
#include <deque>
#include <mutex>
#include <optional>
#include <cmath>
#include <cstdint>
#include <set>
#include <type_traits>
#include <variant>

#include "problem.hpp"
#include "epuck2/calibrate/screening.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/fit/robust.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/models/plugin_battery_tables.hpp"
#include "epuck2/models/sensors.hpp"

namespace epuck2::diagnose {

using namespace epuck2::fit;  // the engine (lib/fit)

namespace detail {
namespace {

namespace s = models::sensors;
namespace fx = models::effects;

/// Sensor gains whose equality the Wald test of their differences does not reject at this level are one common gain.
constexpr double kEqualGainsP = 0.01;
/// A long tail carrying more than this share of the modelled near-field reading replaces it.
constexpr double kTailShareOfNearField = 0.5;

/// The base model given (Options::base_model) in place of the plug-in's published one: parameter
/// j's value with its effect off, and in the published model, is the base's `v`; a start that was
/// the old neutral value moves with it.
void set_base(Problem& p, int j, double v) {
  fit::Parameter& q = p.params[static_cast<std::size_t>(j)];
  if (q.value == q.fallback) q.value = v;
  q.fallback = v;
  q.lower = std::min(q.lower, v);
  q.upper = std::max(q.upper, v);
  p.plugin_values[static_cast<std::size_t>(j)] = v;
}

int add_param(Problem& p, const std::string& name, double neutral, double start, double lower = -kInf, double upper = kInf) {
  p.params.push_back({name, start, neutral, lower, upper, false, {}});
  p.plugin_values.push_back(neutral);
  return static_cast<int>(p.params.size()) - 1;
}

/// Every parameter of a kind's catalogue effects (lib/models' registry): one per element, named
/// KEY or KEY[k], with the registry's neutral value, start and range; the kind's effects list the
/// effect with all of them (kinds narrow per-sensor effects to the sensors the logs hold).
/// [effect][parameter][element] -> index into Problem::params.
using CatalogueIndex = std::vector<std::vector<std::vector<int>>>;
CatalogueIndex add_catalogue(Problem& p, const fx::Catalogue& catalogue) {
  CatalogueIndex ix(catalogue.size());
  for (std::size_t id = 0; id < catalogue.size(); ++id) {
    const fx::Effect& e = catalogue[id];
    Effect effect{e.name, {}};
    for (const fx::Param& q : e.params) {
      ix[id].emplace_back();
      for (int k = 0; k < q.count; ++k) {
        const std::string name = q.count == 1 ? std::string(q.key) : std::string(q.key) + "[" + std::to_string(k) + "]";
        ix[id].back().push_back(add_param(p, name, q.neutral, q.start, q.lower, q.upper));
        p.param_units.resize(p.params.size());
        p.param_units.back() = q.unit;
        effect.params.push_back(ix[id].back().back());
      }
    }
    p.effects.push_back(effect);
  }
  return ix;
}

/// The effect of the catalogue in p.effects (added by add_catalogue).
Effect& effect_of(Problem& p, const fx::Catalogue& catalogue, std::size_t id) {
  for (Effect& e : p.effects)
    if (e.cause == catalogue[id].name) return e;
  throw std::logic_error("the catalogue's effect " + std::string(catalogue[id].name) + " is not in the problem");
}
void drop_effect(Problem& p, const fx::Catalogue& catalogue, std::size_t id) {
  p.effects.erase(std::remove_if(p.effects.begin(), p.effects.end(), [&](const Effect& e) { return e.cause == catalogue[id].name; }),
                  p.effects.end());
}

/// The kind's effect struct (lib/models) at the parameters p, through the registry's visitor.
template <class Effects, class T>
void fill_effects(const CatalogueIndex& ix, const T* p, Effects& e) {
  fx::for_each_param(e, [&](std::size_t id, int q, int k, auto& slot) {
    slot = p[ix[id][static_cast<std::size_t>(q)][static_cast<std::size_t>(k)]];
  });
}

/// A base model's effects (a calibration's or a diagnosis's file) as the parameters' off values.
template <class Effects>
void set_base_effects(Problem& p, const CatalogueIndex& ix, Effects e) {
  fx::for_each_param(e, [&](std::size_t id, int q, int k, double& v) {
    set_base(p, ix[id][static_cast<std::size_t>(q)][static_cast<std::size_t>(k)], v);
  });
}

std::vector<int> sensors_seen(const std::vector<double>& sensor) {
  std::set<int> seen;
  for (double v : sensor) seen.insert(static_cast<int>(v));
  return {seen.begin(), seen.end()};
}

// ---------------------------------------------------------------------------------------------
// ground: v = 1023 grey (the plug-in's source); catalogue: black_offset, white_level,
// sensor_gain, nonlinear_response, sensor_offset (each sensor's own black offset, relative to the
// first sensor seen). Combined: v = o_s + (level - o_s) g_s grey^p with o_s = offset + offsets[s].
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
    // sensors differ over black) relative to the first sensor seen, whose offset is the common
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
    // With a, b, c free the overall gain is theirs: the first sensor seen is the reference (1).
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

// ---------------------------------------------------------------------------------------------
// light: v = 4095 clamp01(1 - (gamma I / d)^2) for d <= 0.5 m, else 4095 (paper Eq. 2, reference
// section 2.2); gamma free. Catalogue: ambient_offset, falloff_exponent, sensor_gain. Combined:
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
  /// A calibrated base: its gamma and the effects it already carries.
  void set_base_model(const s::LightModel& m) {
    set_base(*this, gamma_, m.base.gamma_m);
    range_m_ = m.base.range_m;
    set_base_effects(*this, ix_, m.effects);
  }

  template <typename T>
  void eval(const T* p, T* out, std::size_t /*needed: every row is computed*/) const {
    s::LightEffects<T> e;
    fill_effects(ix_, p, e);
    for (std::size_t i = 0; i < distance_.size(); ++i)
      out[i] = s::light_mean_raw(p[gamma_], range_m_, e, sensor_[i], intensity_[i], distance_[i]);
  }

 private:
  std::vector<double> distance_, intensity_;
  std::vector<int> sensor_;
  CatalogueIndex ix_;
  int gamma_ = 0;
  double range_m_ = 0.5;
};

// ---------------------------------------------------------------------------------------------
// camera: pinhole with square pixels, centre (80, 60), f = 80 / tan(h/2) (the plug-in's source);
// h free (fov_deg, 30 nominal). Catalogue: principal_offset, radial_distortion. Two residuals per
// row: px then py.
class Camera : public ProblemOf<Camera> {
 public:
  using BaseModel = s::CameraModel;
  explicit Camera(const std::vector<logs::Log>& logs) {
    std::vector<double> fw, lat, ver, axis, r2, image_row;
    for (const auto& log : logs) {
      const auto& f = log.col("forward_m");
      const auto& l = log.col("lateral_m");
      const auto& v = log.col("vertical_m");
      const auto& px = log.col("px");
      const auto& py = log.col("py");
      for (std::size_t i = 0; i < log.rows(); ++i) {
        // The image row the LED falls on (0 = top), as the plug-in's camera projects it: where in
        // the image, from the geometry, not the measured py (whose own noise its residual shares).
        double nominal_column = 0, nominal_row = 0;
        const s::CameraCoefficients plugin = s::plugin_camera();
        s::camera_projection(plugin.horizontal_fov_rad, plugin.cx_px, plugin.cy_px, s::kCameraWidth_px, f[i], l[i], v[i],
                             &nominal_column, &nominal_row);
        x_.push_back(l[i] / f[i]);
        z_.push_back(v[i] / f[i]);
        for (int a = 0; a < 2; ++a) {
          y.push_back(a == 0 ? px[i] : py[i]);
          row.push_back(rows);
          fw.push_back(f[i]);
          lat.push_back(l[i]);
          ver.push_back(v[i]);
          axis.push_back(a);
          r2.push_back(x_.back() * x_.back() + z_.back() * z_.back());
          image_row.push_back(nominal_row);
        }
        ++rows;
      }
    }
    // Nominal horizontal field of view: 30 deg (docs/diagnose.md; the plug-in's 18.5 deg
    // aperture on the diagonal gives 29.97 deg, the plug-in's source).
    constexpr double kNominalFov_deg = 30.0;
    fov_ = add_param(*this, "fov_deg", kNominalFov_deg, kNominalFov_deg, 1.0, 170.0);
    base_free = {fov_};
    ix_ = add_catalogue(*this, fx::camera_catalogue());
    dx_ = ix_[fx::camera::principal_offset][0][0];
    dy_ = ix_[fx::camera::principal_offset][1][0];
    covariates.emplace_back("forward_m", std::move(fw));
    covariates.emplace_back("lateral_m", std::move(lat));
    covariates.emplace_back("vertical_m", std::move(ver));
    covariates.emplace_back("axis", std::move(axis));
    covariates.emplace_back("radius2", std::move(r2));
    covariates.emplace_back("image_row", std::move(image_row));
  }
  /// A calibrated base: its field of view, centre and distortion.
  void set_base_model(const s::CameraModel& m) {
    set_base(*this, fov_, s::rad_to_deg(m.base.horizontal_fov_rad));
    set_base(*this, dx_, m.base.cx_px - s::kCameraWidth_px / 2.0);
    set_base(*this, dy_, m.base.cy_px - s::kCameraHeight_px / 2.0);
    set_base_effects(*this, ix_, m.distortion);
  }

  template <typename T>
  void eval(const T* p, T* out, std::size_t /*needed: every row is computed*/) const {
    s::CameraRadialDistortion<T> distortion;
    fill_effects(ix_, p, distortion);
    const T hfov_rad = p[fov_] * (s::kPi / 180.0);
    const T cx = s::kCameraWidth_px / 2.0 + p[dx_], cy = s::kCameraHeight_px / 2.0 + p[dy_];
    for (std::size_t i = 0; i < x_.size(); ++i)
      s::camera_projection(hfov_rad, cx, cy, s::kCameraWidth_px, 1.0, x_[i], z_[i], &out[2 * i], &out[2 * i + 1],
                           distortion);
  }

 private:
  std::vector<double> x_, z_;
  CatalogueIndex ix_;
  int fov_ = 0, dx_ = 0, dy_ = 0;
};


// ---------------------------------------------------------------------------------------------
// drive: v_w = v_c (zero-order hold between rows), v_g = v_w; steps = floor(7763.656 x_w), int16
// wrap; tof = clamp(round(1000 (D - x_g)), 20, 2000) (docs/diagnose.md; the plug-in's
// ToF and encoder models). Free parameters: none. Catalogue: speed_limit, accel_limit, wheel_slip,
// speed_scale, latency, tof_offset, tof_scale, all in one model:
//   u_w = clamp(v_c, -max, max); v_w follows u_w with |dv_w/dt| <= accel;
//   dv_g/dt = (k_speed v_w - v_g) / tau; tof(t) = k_tof 1000 (D - x_g(t - delay)) + offset.
// Within a row's interval every wheel speed is piecewise linear in time (a ramp, then constant),
// and the lag is integrated exactly over each piece, so any sampling is simulated without a time
// step. Residuals per row: the ToF reading (channel 0, mm), then the left and right encoder
// registers unwrapped (channel 1, steps; predicted as the mean of floor: 7763.656 x - 1/2, and 0
// before the wheel has moved), each only when it changed since the previous row.
class Drive : public ProblemOf<Drive> {
 public:
  using BaseModel = s::DriveModel;
  // "No limit": the neutral value of max_cm_s and accel_cm_s2 (lib/models drive.hpp).
  static constexpr double kNoLimit = s::kDriveNoLimit;

 public:
  explicit Drive(const std::vector<logs::Log>& logs) {
    channel_names = {"tof_mm", "steps"};
    channel_lo = {s::kPluginTof.min_mm, -kInf};
    channel_hi = {s::kPluginTof.max_mm, kInf};
    // ToF readings are whole mm; encoder registers whole steps (rounding: sqrt(1/12)).
    channel_min_sd = {0.3, 0.29};
    // An encoder register's error is its rounding, the same for every row until the wheel turns
    // on (not independent noise): a dependence below half a step is that rounding, not an effect.
    channel_min_structure = {0.0, 0.5};
    noise_from_differences = true;
    time_series = true;
    std::vector<double> cov_time, cov_cmd, cov_speed, cov_acc, cov_dist, cov_range, cov_since, cov_channel;
    double max_command = 0;
    std::vector<std::string> dropouts;  // "no target" codes where the encoders put the target in view
    for (const auto& log : logs) {
      Run r;
      r.obstacle_m = log.metadata_number("obstacle_distance_m");
      r.first = time_.size();
      const auto& t = log.col("time_s");
      const auto& cl = log.col("left_speed_cm_s");
      const auto& cr = log.col("right_speed_cm_s");
      const auto& sl = log.col("left_steps");
      const auto& sr = log.col("right_steps");
      const auto& tof = log.col("tof_mm");
      const std::size_t n = log.rows();
      r.symmetric = std::equal(cl.begin(), cl.end(), cr.begin());
      const std::vector<double> ul = s::unwrap_steps(sl), ur = s::unwrap_steps(sr);
      // Measured motion from the encoders, for the residual structure. Each row's values come
      // from its neighbours' registers only: a row's own register carries its rounding, which
      // would correlate with its own residual.
      std::vector<double> steps_m(n), dist(n), speed(n), acc(n);
      for (std::size_t i = 0; i < n; ++i) steps_m[i] = 0.5 * (ul[i] + ur[i]) / s::kPluginStepsPerMetre;
      auto at = [&](std::ptrdiff_t j) { return static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(j, 0, static_cast<std::ptrdiff_t>(n) - 1)); };
      auto slope = [&](std::size_t a, std::size_t b) { return b > a && t[b] > t[a] ? (steps_m[b] - steps_m[a]) / (t[b] - t[a]) : 0.0; };
      for (std::size_t i = 0; i < n; ++i) {
        const auto j = static_cast<std::ptrdiff_t>(i);
        const std::size_t a = at(j - 1), b = at(j + 1);
        dist[i] = a == i || b == i ? steps_m[i] : steps_m[a] + (steps_m[b] - steps_m[a]) * (t[i] - t[a]) / (t[b] - t[a]);
        speed[i] = 100.0 * slope(a, b);
        // Speeds over (i-2, i-1) and (i+1, i+2).
        const std::size_t a2 = at(j - 2), b2 = at(j + 2);
        const double before = slope(a2, a), after = slope(b, b2);
        const double span = 0.5 * (t[b] + t[b2]) - 0.5 * (t[a2] + t[a]);
        acc[i] = span > 0 ? 100.0 * (after - before) / span : 0.0;
      }
      double since = 0;
      for (std::size_t i = 0; i < n; ++i) {
        if (i && (cl[i] != cl[i - 1] || cr[i] != cr[i - 1])) since = t[i];
        time_.push_back(t[i]);
        left_.push_back(cl[i]);
        right_.push_back(cr[i]);
        max_command = std::max({max_command, std::abs(cl[i]), std::abs(cr[i])});
        // An encoder register that has not changed since the previous row adds no observation:
        // its rounding error is the previous row's again (a standing robot would otherwise count
        // one error many times). It is left out.
        // A ToF reading as the calibration reads it (calibrate::read_tof): a "no target" code
        // (>= 8190) is censored at the 2000 mm rail, where the clamped model's reading is the
        // rail itself; one where the encoders put the target in view is a dropout, left out.
        const bool dropout = calibrate::tof_code_in_view(tof[i], 1000.0 * (r.obstacle_m - steps_m[i]));
        if (dropout) dropouts.push_back(log.path + ":" + std::to_string(log.line_of_row[i]));
        const double values[3] = {calibrate::read_tof(tof[i]).observation.value, ul[i], ur[i]};
        // In a straight run with both wheels commanded alike, a right register equal to the left
        // one is the same count (and the same rounding) twice: it is left out too.
        const bool same = r.symmetric && ur[i] == ul[i];
        const bool fresh[3] = {!dropout, i == 0 || ul[i] != ul[i - 1], !same && (i == 0 || ur[i] != ur[i - 1])};
        first_.push_back(static_cast<std::uint32_t>(y.size()));
        for (int c = 0; c < 3; ++c) {
          slot_[c].push_back(fresh[c] ? static_cast<std::int32_t>(y.size()) : -1);
          if (!fresh[c]) continue;
          y.push_back(values[c]);
          channel.push_back(c == 0 ? 0 : 1);
          row.push_back(static_cast<std::uint32_t>(rows));
          cov_channel.push_back(c);
        }
        // Once per row, not per residual (up to three a row): spread through `row` when scored.
        cov_time.push_back(t[i]);
        cov_cmd.push_back(0.5 * (cl[i] + cr[i]));
        cov_speed.push_back(speed[i]);
        cov_acc.push_back(acc[i]);
        cov_dist.push_back(dist[i]);
        cov_range.push_back(r.obstacle_m - dist[i]);
        cov_since.push_back(t[i] - since);
        ++rows;
      }
      r.last = time_.size();
      runs_.push_back(r);
    }
    if (!dropouts.empty()) {
      std::string at;
      for (std::size_t k = 0; k < dropouts.size() && k < 5; ++k) at += (k ? ", " : "") + dropouts[k];
      warnings.push_back(std::to_string(dropouts.size()) + " ToF \"no target\" codes (>= 8190) where the encoders put the obstacle within " +
                         std::to_string(static_cast<int>((1.0 - calibrate::kTofInViewMargin) * s::kPluginTof.max_mm)) +
                         " mm: dropouts, left out of the ToF residuals as the drive calibration leaves them out (" + at +
                         (dropouts.size() > 5 ? ", ..." : "") + ")");
    }
    // A limit above every command changes nothing (a flat cost): start from several fractions of
    // the largest command.
    ix_ = add_catalogue(*this, fx::drive_catalogue());
    const std::size_t max = static_cast<std::size_t>(ix_[fx::drive::speed_limit][0][0]);
    const std::size_t accel = static_cast<std::size_t>(ix_[fx::drive::accel_limit][0][0]);
    params[max].value = std::max(0.5, 0.9 * max_command);
    params[max].other_starts = {std::max(0.5, 0.65 * max_command), std::max(0.5, 0.4 * max_command)};
    params[accel].other_starts = {10.0};
    add_row_covariate("time_s", std::move(cov_time));
    add_row_covariate("commanded_cm_s", std::move(cov_cmd));
    add_row_covariate("speed_cm_s", std::move(cov_speed));
    add_row_covariate("acceleration_cm_s2", std::move(cov_acc));
    add_row_covariate("distance_m", std::move(cov_dist));
    add_row_covariate("range_m", std::move(cov_range));
    add_row_covariate("time_since_command_s", std::move(cov_since));
    covariates.emplace_back("channel", std::move(cov_channel));
    for (auto* v : {&time_, &left_, &right_}) v->shrink_to_fit();
    for (auto& v : slot_) v.shrink_to_fit();
    first_.shrink_to_fit();
  }

  /// A calibrated base: its encoders' steps per metre and the effects it already carries.
  void set_base_model(const s::DriveModel& m) {
    steps_per_m_ = m.steps_per_m;
    set_base_effects(*this, ix_, m.effects);
  }

  /// The catalogue's drive effects (lib/models drive.hpp) at the parameters p.
  template <typename T>
  s::DriveEffects<T> effects_at(const T* p) const {
    s::DriveEffects<T> e;
    fill_effects(ix_, p, e);
    return e;
  }

  template <typename T>
  void eval(const T* p, T* out, std::size_t needed) const {
    const s::DriveEffects<T> e = effects_at(p);
    const double steps_per_m = steps_per_m_;
    auto encoder = [steps_per_m](const T& x) { return s::encoder_mean_steps(steps_per_m, x); };
    // With a latency, the ToF reading at t is the true one at t - delay: the state at the start of
    // the row k in which t - delay falls, advanced to it. Only the states of rows k..i are kept
    // (a window of delay / dt rows), not one per row of the log (144 B a row with 2-wide Jets).
    std::deque<s::DriveState<T>> window;
    const bool delayed = value_of(e.latency.delay_s) > 0;
    for (const Run& r : runs_) {
      if (first_[r.first] >= needed) break;
      s::DriveState<T> st;
      window.clear();
      std::size_t k = r.first;  // window.front() is the state at the start of row k
      for (std::size_t i = r.first; i < r.last; ++i) {
        if (first_[i] >= needed) break;
        if (slot_[1][i] >= 0) out[slot_[1][i]] = encoder(st.xl);
        if (slot_[2][i] >= 0) out[slot_[2][i]] = encoder(st.xr);
        if (slot_[0][i] < 0) {  // a ToF dropout: no reading to predict (the state still advances)
          if (delayed) window.push_back(st);
        } else if (!delayed) {
          out[slot_[0][i]] = s::drive_tof_mean_mm(e, r.obstacle_m, st.xg);
        } else {
          window.push_back(st);
          const T when = time_[i] - e.latency.delay_s;
          while (k + 1 < i + 1 && value_of(when) >= time_[k + 1]) {
            ++k;
            window.pop_front();
          }
          if (value_of(when) < time_[r.first]) {
            out[slot_[0][i]] = s::drive_tof_mean_mm(e, r.obstacle_m, T(0.0));
          } else {
            s::DriveState<T> at = window.front();
            s::drive_advance(e, left_[k], right_[k], T(when - time_[k]), at, r.symmetric);
            out[slot_[0][i]] = s::drive_tof_mean_mm(e, r.obstacle_m, at.xg);
          }
        }
        if (i + 1 < r.last) s::drive_advance(e, left_[i], right_[i], T(time_[i + 1] - time_[i]), st, r.symmetric);
      }
    }
  }

 private:
  struct Run {
    double obstacle_m = 0;
    std::size_t first = 0, last = 0;
    bool symmetric = false;  ///< both wheels commanded alike on every row: one wheel simulated
  };

  std::vector<double> time_, left_, right_;
  /// Per row: the residual index of the ToF reading and of each encoder register (-1: left out).
  std::array<std::vector<std::int32_t>, 3> slot_;
  std::vector<std::uint32_t> first_;  ///< per row: the index its residuals start at (the next row's when it has none)
  std::vector<Run> runs_;
  CatalogueIndex ix_;
  double steps_per_m_ = s::kPluginStepsPerMetre;
};


// ---------------------------------------------------------------------------------------------
// battery: the chosen discharge model (corrected behaviour: lib/models battery.hpp) run over each
// log's own speed profile (a speed holds from its row to the next) and time steps, from the first
// row's charge (full when that reading is near full, see below). Free parameters: none. Catalogue: capacity_scale (the model with time running
// 1/k times as fast). The charge depends on k through a whole simulation, so its derivative is a
// central difference of two simulations (relative step 1e-6: ~1e-10 relative error).
class Battery : public ProblemOf<Battery> {
 public:
  /// A base model's capacity scale (a diagnosis file's): the model with capacity_scale off.
  void set_base_capacity(double k) {
    if (k != 1.0) set_base(*this, k_, k);  // the registry's neutral capacity_scale is 1
  }

  Battery(const std::vector<logs::Log>& logs, models::battery::Model model, const models::battery::Tables& tables)
      : model_(model), tables_(tables) {
    // A charge is a fraction: no rounding floor on its noise.
    channel_min_sd = {1e-6};
    time_series = true;  // a discharge run
    // (Not the measured charge: the residual's own noise correlates with it.)
    std::vector<double> cov_time, cov_speed;
    for (const auto& log : logs) {
      Run r;
      r.first = time_.size();
      const auto& t = log.col("time_s");
      const auto& v = log.col("speed_cm_s");
      if (!log.has("charge"))
        throw logs::InputError(log.path, log.header_line, 1,
                               "no 'charge' column, only 'voltage_v': diagnose compares the discharge models' charge with the "
                               "logged one; `battery` and `table5` take voltage-only logs (--charge-map), diagnose does not");
      const auto& c = log.col("charge");
      // A discharge run starts fully charged (docs/logs.md): a first reading near full is
      // that full charge seen through the sensor's noise, and starting from the noisy reading
      // would shift the whole curve in time (the Cubic starts at its intercept d ~ 1). A run
      // that starts part-way (first reading below 0.9) starts from its first reading.
      r.start_charge = c.front() >= s::kBatteryStartsFull ? 1.0 : c.front();
      for (std::size_t i = 0; i < log.rows(); ++i) {
        time_.push_back(t[i]);
        speed_.push_back(std::abs(v[i]));
        // The last row is the moment the robot stopped (docs/logs.md): its time is the
        // lifetime, and the model's charge there sits on the edge where it drops to 0 at its own
        // lifetime. It is simulated, not compared.
        if (i + 1 < log.rows() || log.rows() == 1) {
          simulated_row_.push_back(time_.size() - 1);
          y.push_back(c[i]);
          row.push_back(rows);
          cov_time.push_back(t[i]);
          cov_speed.push_back(std::abs(v[i]));
        }
        ++rows;
      }
      r.last = time_.size();
      runs_.push_back(r);
    }
    k_ = add_catalogue(*this, fx::battery_catalogue())[fx::battery::capacity_scale][0][0];
    covariates.emplace_back("time_s", std::move(cov_time));
    covariates.emplace_back("speed_cm_s", std::move(cov_speed));
  }

  template <typename T>
  void eval(const T* p, T* out, std::size_t needed) const {
    const double k = value_of(p[k_]);
    // Only the rows up to the last residual asked for (a long log's screening fits ask for the
    // leading ones): the discharge runs forward from each run's start, so the rows before are the
    // same without the ones after.
    const std::size_t residuals = std::min(needed, simulated_row_.size());
    if (residuals == 0) return;
    const std::size_t rows = simulated_row_[residuals - 1] + 1;
    constexpr bool derivative = !std::is_same_v<T, double>;
    const std::lock_guard<std::mutex> lock(memo_mutex_);
    const Simulated& sim = simulated(k, rows, derivative);
    for (std::size_t r = 0; r < residuals; ++r) {
      const std::size_t i = simulated_row_[r];
      if constexpr (!derivative) {
        out[r] = sim.at[i];
      } else {
        const double h = 1e-6 * k;
        out[r] = T(sim.at[i]);
        out[r].v = p[k_].v * ((sim.up[i] - sim.down[i]) / (2.0 * h));
      }
    }
  }

 private:
  /// A simulation of rows [0, rows) at capacity scale k, and at k +- h (h = 1e-6 k) when the
  /// derivative was asked for (else up and down are empty).
  struct Simulated {
    double k = 1;
    std::size_t rows = 0;
    std::vector<double> at, up, down;
  };
  /// Simulations kept from one evaluation to the next: a diagnosis evaluates the same capacity
  /// scale again and again (k = 1, the base model, in every noise round and held-out fold; a
  /// fit's optimum in the folds that start from it: 61 of the 67 evaluations on a 1M-row log),
  /// and each is the discharge of every row (1M rows: ~0.1 s). A simulation is deterministic, so
  /// a kept one is bit for bit a new one. The last kMemo are kept; evaluations take turns.
  static constexpr std::size_t kMemo = 2;
  mutable std::mutex memo_mutex_;
  mutable std::deque<Simulated> memo_;  ///< the most recently used first

  /// The simulation at k of at least `rows` rows (with k +- h when `derivative`), kept or run.
  const Simulated& simulated(double k, std::size_t rows, bool derivative) const {
    for (auto it = memo_.begin(); it != memo_.end(); ++it) {
      if (it->k != k) continue;
      if (it->rows < rows) {  // too short: simulated again below, longer
        memo_.erase(it);
        break;
      }
      if (it != memo_.begin()) {
        Simulated kept = std::move(*it);
        memo_.erase(it);
        memo_.push_front(std::move(kept));
      }
      Simulated& s = memo_.front();
      if (derivative && s.up.empty()) {
        // k and k +- h stepped side by side (battery_mean_charges): the chains overlap.
        const double h = 1e-6 * k;
        s.up.resize(s.rows);
        s.down.resize(s.rows);
        simulate<2>({k + h, k - h}, {s.up.data(), s.down.data()}, s.rows);
      }
      return s;
    }
    Simulated s;
    s.k = k;
    s.rows = rows;
    s.at.resize(rows);
    if (derivative) {
      const double h = 1e-6 * k;
      s.up.resize(rows);
      s.down.resize(rows);
      simulate<3>({k, k + h, k - h}, {s.at.data(), s.up.data(), s.down.data()}, rows);
    } else {
      simulate<1>({k}, {s.at.data()}, rows);
    }
    memo_.push_front(std::move(s));
    if (memo_.size() > kMemo) memo_.pop_back();
    return memo_.front();
  }

  struct Run {
    double start_charge = 1;
    std::size_t first = 0, last = 0;
  };
  /// The charge of rows [0, rows) with capacity scale k[s] into out[s].
  template <std::size_t N>
  void simulate(const std::array<double, N>& k, const std::array<double*, N>& out, std::size_t rows) const {
    // The runtime library's discharge of a log (lib/models kinds.hpp battery_mean_charges): the
    // calibration protocol spins in place, each wheel at the logged speed, from the run's start.
    s::BatteryModel m;
    m.model = model_;
    m.tables = tables_;
    struct Slice {  // rows [first, last) of one of the log's columns
      const std::vector<double>& v;
      std::size_t first, last;
      std::size_t size() const { return last - first; }
      double operator[](std::size_t i) const { return v[first + i]; }
    };
    for (const Run& r : runs_) {
      if (r.first >= rows) break;
      const std::size_t last = std::min(r.last, rows);
      std::array<double*, N> at;
      for (std::size_t s = 0; s < N; ++s) at[s] = out[s] + r.first;
      s::battery_mean_charges<N>(m, k, Slice{time_, r.first, last}, Slice{speed_, r.first, last}, r.start_charge, at);
    }
  }
  models::battery::Model model_;
  models::battery::Tables tables_;
  std::vector<double> time_, speed_;
  std::vector<std::size_t> simulated_row_;  ///< per residual: its row in time_
  std::vector<Run> runs_;
  int k_ = 0;
};

}  // namespace

std::unique_ptr<Problem> make_problem(const std::vector<logs::Log>& logs, const Options& options, std::string& why) {
  const logs::Kind kind = logs.front().kind;
  for (const auto& l : logs)
    if (l.kind != kind) {
      why = "the logs are not all of one kind";
      return nullptr;
    }
  // The base model given in place of the plug-in's: it must be of the logs' kind.
  auto with_base = [&](auto problem) -> std::unique_ptr<Problem> {
    using Model = typename std::remove_reference_t<decltype(*problem)>::BaseModel;
    if (std::holds_alternative<Model>(options.base_model)) problem->set_base_model(std::get<Model>(options.base_model));
    return problem;
  };
  if (options.base_model.index() != 0 && base_model_kind(options.base_model) != kind) {
    why = std::string("the base model given is of the kind ") + std::string(logs::to_string(base_model_kind(options.base_model))) +
          ", the logs of the kind " + std::string(logs::to_string(kind));
    return nullptr;
  }
  std::unique_ptr<Problem> p;
  switch (kind) {
    case logs::Kind::ground: p = with_base(std::make_unique<Ground>(logs)); break;
    case logs::Kind::proximity: p = with_base(std::make_unique<Proximity>(logs)); break;
    case logs::Kind::light: p = with_base(std::make_unique<Light>(logs)); break;
    case logs::Kind::camera: p = with_base(std::make_unique<Camera>(logs)); break;
    case logs::Kind::drive: p = with_base(std::make_unique<Drive>(logs)); break;
    case logs::Kind::battery: {
      // The tables given (--coefficients), else the plug-in's published ones: the library never
      // compiles in the project's fitted data.
      const models::battery::Tables tables = options.battery_tables ? *options.battery_tables : models::battery::plugin_tables();
      auto battery = std::make_unique<Battery>(logs, options.battery_model, tables);
      battery->set_base_capacity(options.battery_capacity_k);
      p = std::move(battery);
      break;
    }
    default:
      why = "diagnose does not support the kind '" + std::string(logs::to_string(kind)) + "' yet";
      return nullptr;
  }
  // The kinds' optional columns of docs/logs.md are inputs of the model (angle_deg) or a
  // consequence of the measured quantity (voltage_v), never `covariate:` candidates.
  add_common_covariates(*p, logs, {"angle_deg", "voltage_v"});
  // Per-residual vectors grew by push_back (up to twice their size): give the slack back before
  // the fits, which run beside them.
  p->y.shrink_to_fit();
  p->row.shrink_to_fit();
  p->channel.shrink_to_fit();
  for (auto& c : p->covariates) c.second.shrink_to_fit();
  for (auto& c : p->extra_columns) c.second.shrink_to_fit();
  return p;
}

}  // namespace detail

std::string finding_meaning(const std::string& cause) {
  if (cause == "near_field_curve")
    return "the reading's curve within the sensor's range has another shape than the model's quadratic";
  return cause;
}

bool supported(logs::Kind kind) {
  switch (kind) {
    case logs::Kind::ground:
    case logs::Kind::proximity:
    case logs::Kind::light:
    case logs::Kind::camera:
    case logs::Kind::drive:
    case logs::Kind::battery: return true;
  }
  return false;
}

}  // namespace epuck2::diagnose
