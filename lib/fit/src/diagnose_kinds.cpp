// The kinds' base models and catalogue effects for the diagnosis (shared/spec/diagnose.md, "The
// catalogue"), each written once, templated on the scalar, over every row of the logs. Every
// effect is a parameter set whose neutral values give back the base model, so that the engine
// switches effects on by freeing their parameters.
#include <algorithm>
#include <cmath>
#include <set>

#include "diagnose_problem.hpp"
#include "epuck2/fit/diagnose.hpp"
#include "epuck2/models/sensors.hpp"

namespace epuck2::fit::diagnose {

namespace detail {
namespace {

namespace s = models::sensors;

int add_param(Problem& p, const std::string& name, double neutral, double start, double lower = -kInf, double upper = kInf) {
  p.params.push_back({name, neutral, start, lower, upper});
  p.plugin_values.push_back(neutral);
  return static_cast<int>(p.params.size()) - 1;
}

std::vector<int> sensors_seen(const std::vector<double>& sensor) {
  std::set<int> seen;
  for (double v : sensor) seen.insert(static_cast<int>(v));
  return {seen.begin(), seen.end()};
}

template <typename T>
T pow_data(double base, const T& exponent) {
  // base^exponent for base >= 0 from the data; 0 for base 0 (no log of 0 in the derivative).
  using std::exp;
  if (!(base > 0)) return T(0.0);
  return exp(exponent * std::log(base));
}

// ---------------------------------------------------------------------------------------------
// ground: v = 1023 grey (reference section 2.3); catalogue: black_offset, white_level,
// sensor_gain, nonlinear_response. Combined: v = offset + (level - offset) g_s grey^p.
class Ground : public ProblemOf<Ground> {
 public:
  explicit Ground(const std::vector<logs::Log>& logs) {
    for (const auto& log : logs) {
      const auto& g = log.col("grey");
      const auto& sn = log.col("sensor");
      const auto& v = log.col("value");
      for (std::size_t i = 0; i < log.rows(); ++i) {
        grey_.push_back(g[i]);
        sensor_.push_back(static_cast<int>(sn[i]));
        y.push_back(v[i]);
        lo.push_back(0.0);
        hi.push_back(s::kGroundFullScale_raw);
        row.push_back(rows++);
      }
    }
    offset_ = add_param(*this, "offset", 0.0, 20.0, -s::kGroundFullScale_raw, s::kGroundFullScale_raw);
    level_ = add_param(*this, "level", s::kGroundFullScale_raw, s::kGroundFullScale_raw, 1.0, 4.0 * s::kGroundFullScale_raw);
    Effect gains{"sensor_gain", {}};
    for (int k = 0; k < s::kGroundCount; ++k) gain_[static_cast<std::size_t>(k)] = add_param(*this, "gains[" + std::to_string(k) + "]", 1.0, 1.0, 0.05, 5.0);
    for (int k : sensors_seen(std::vector<double>(sensor_.begin(), sensor_.end())))
      if (k >= 0 && k < s::kGroundCount) gains.params.push_back(gain_[static_cast<std::size_t>(k)]);
    exponent_ = add_param(*this, "exponent", 1.0, 1.0, 0.05, 20.0);
    effects = {{"black_offset", {offset_}}, {"white_level", {level_}}, {"nonlinear_response", {exponent_}}};
    if (gains.params.size() >= 2) effects.push_back(gains);
    std::vector<double> sensor_d(sensor_.begin(), sensor_.end());
    covariates.emplace_back("grey", grey_);
    covariates.emplace_back("sensor", sensor_d);
  }
  template <typename T>
  void eval(const T* p, T* out) const {
    for (std::size_t i = 0; i < grey_.size(); ++i)
      out[i] = p[offset_] + (p[level_] - p[offset_]) * p[gain_[static_cast<std::size_t>(sensor_[i])]] * pow_data(grey_[i], p[exponent_]);
  }

 private:
  std::vector<double> grey_;
  std::vector<int> sensor_;
  int offset_ = 0, level_ = 0, exponent_ = 0;
  std::array<int, s::kGroundCount> gain_{};
};

// ---------------------------------------------------------------------------------------------
// proximity: v = 4095 clamp01(a d^2 + b d + c) for d <= 0.05 m, else 0 (paper Eq. 1, reference
// section 2.1); a, b, c free. Catalogue: ambient_offset, sensor_gain, long_tail, incidence_angle,
// saturation. Combined: v = min(g_s cos(theta)^k 4095 clamp01(poly) [d <= range] + offset
// + amplitude exp(-d / length), level).
class Proximity : public ProblemOf<Proximity> {
 public:
  explicit Proximity(const std::vector<logs::Log>& logs) {
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
        lo.push_back(0.0);
        hi.push_back(s::kProximityFullScale_raw);
        row.push_back(rows++);
      }
    }
    const auto& k = s::kPluginProximity;
    a_ = add_param(*this, "a", k.a_per_m2, k.a_per_m2);
    add_param(*this, "b", k.b_per_m, k.b_per_m);
    add_param(*this, "c", k.c, k.c);
    base_free = {a_, a_ + 1, a_ + 2};
    offset_ = add_param(*this, "offset", 0.0, 10.0, -s::kProximityFullScale_raw, s::kProximityFullScale_raw);
    for (int j = 0; j < s::kProximityCount; ++j)
      gain_[static_cast<std::size_t>(j)] = add_param(*this, "gains[" + std::to_string(j) + "]", 1.0, 1.0, 0.05, 20.0);
    amplitude_ = add_param(*this, "amplitude", 0.0, 200.0, 0.0, 20.0 * s::kProximityFullScale_raw);
    length_ = add_param(*this, "length_m", 0.02, 0.02, 0.001, 1.0);
    k_ = add_param(*this, "k", 0.0, 1.0, 0.0, 50.0);
    double top = 0;
    for (double v : y) top = std::max(top, v);
    level_ = add_param(*this, "level", 1e9, top, 1.0, 1e9);
    effects = {{"ambient_offset", {offset_}}, {"long_tail", {amplitude_, length_}}, {"saturation", {level_}}};
    // With a, b, c free the overall gain is theirs: the first sensor seen is the reference (1).
    const auto seen = sensors_seen(std::vector<double>(sensor_.begin(), sensor_.end()));
    if (seen.size() >= 2) {
      Effect g{"sensor_gain", {}};
      for (std::size_t j = 1; j < seen.size(); ++j) g.params.push_back(gain_[static_cast<std::size_t>(seen[j])]);
      effects.push_back(g);
    }
    bool angles_vary = false;
    for (double c : cos_) angles_vary = angles_vary || std::abs(c - cos_.front()) > 1e-9 || c < 1.0 - 1e-12;
    if (angle && angles_vary) effects.push_back({"incidence_angle", {k_}});
    range_m_ = k.range_m;
    std::vector<double> sensor_d(sensor_.begin(), sensor_.end());
    covariates.emplace_back("distance_m", distance_);
    covariates.emplace_back("sensor", sensor_d);
    if (angle) {
      std::vector<double> a;
      for (const auto& log : logs)
        for (double x : log.col("angle_deg")) a.push_back(x);
      covariates.emplace_back("angle_deg", a);
    }
  }
  template <typename T>
  void eval(const T* p, T* out) const {
    using std::exp;
    using std::fmax;
    using std::fmin;
    for (std::size_t i = 0; i < distance_.size(); ++i) {
      const double d = distance_[i];
      T v = p[offset_] + p[amplitude_] * exp(-d / p[length_]);
      if (d <= range_m_) {
        T poly = s::proximity_polynomial(p + a_, d);
        poly = fmin(fmax(poly, T(0.0)), T(1.0));
        v += p[gain_[static_cast<std::size_t>(sensor_[i])]] * pow_data(cos_[i], p[k_]) * s::kProximityFullScale_raw * poly;
      }
      out[i] = fmin(v, p[level_]);
    }
  }

 private:
  std::vector<double> distance_, cos_;
  std::vector<int> sensor_;
  int a_ = 0, offset_ = 0, amplitude_ = 0, length_ = 0, k_ = 0, level_ = 0;
  std::array<int, s::kProximityCount> gain_{};
  double range_m_ = 0.05;
};

// ---------------------------------------------------------------------------------------------
// light: v = 4095 clamp01(1 - (gamma I / d)^2) for d <= 0.5 m, else 4095 (paper Eq. 2, reference
// section 2.2); gamma free. Catalogue: ambient_offset, falloff_exponent, sensor_gain. Combined:
// v = 4095 (1 - g_s (gamma I / d)^p) - offset.
class Light : public ProblemOf<Light> {
 public:
  explicit Light(const std::vector<logs::Log>& logs) {
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
        lo.push_back(0.0);
        hi.push_back(s::kProximityFullScale_raw);
        row.push_back(rows++);
      }
    }
    gamma_ = add_param(*this, "gamma_m", s::kPluginLight.gamma_m, s::kPluginLight.gamma_m, 1e-4, 10.0);
    base_free = {gamma_};
    offset_ = add_param(*this, "offset", 0.0, 10.0, -s::kProximityFullScale_raw, s::kProximityFullScale_raw);
    exponent_ = add_param(*this, "exponent", 2.0, 2.0, 0.2, 10.0);
    for (int j = 0; j < s::kProximityCount; ++j)
      gain_[static_cast<std::size_t>(j)] = add_param(*this, "gains[" + std::to_string(j) + "]", 1.0, 1.0, 0.05, 20.0);
    effects = {{"ambient_offset", {offset_}}, {"falloff_exponent", {exponent_}}};
    const auto seen = sensors_seen(std::vector<double>(sensor_.begin(), sensor_.end()));
    if (seen.size() >= 2) {
      Effect g{"sensor_gain", {}};
      for (std::size_t j = 1; j < seen.size(); ++j) g.params.push_back(gain_[static_cast<std::size_t>(seen[j])]);
      effects.push_back(g);
    }
    range_m_ = s::kPluginLight.range_m;
    std::vector<double> sensor_d(sensor_.begin(), sensor_.end());
    covariates.emplace_back("distance_m", distance_);
    covariates.emplace_back("intensity", intensity_);
    covariates.emplace_back("sensor", sensor_d);
  }
  template <typename T>
  void eval(const T* p, T* out) const {
    using std::exp;
    using std::log;
    for (std::size_t i = 0; i < distance_.size(); ++i) {
      T v(s::kProximityFullScale_raw);
      if (distance_[i] <= range_m_ && intensity_[i] > 0) {
        const T ratio = p[gamma_] * intensity_[i] / distance_[i];
        v = s::kProximityFullScale_raw * (1.0 - p[gain_[static_cast<std::size_t>(sensor_[i])]] * exp(p[exponent_] * log(ratio)));
      }
      out[i] = v - p[offset_];
    }
  }

 private:
  std::vector<double> distance_, intensity_;
  std::vector<int> sensor_;
  int gamma_ = 0, offset_ = 0, exponent_ = 0;
  std::array<int, s::kProximityCount> gain_{};
  double range_m_ = 0.5;
};

// ---------------------------------------------------------------------------------------------
// camera: pinhole with square pixels, centre (80, 60), f = 80 / tan(h/2) (reference section 1);
// h free (fov_deg, 30 nominal). Catalogue: principal_offset, radial_distortion. Two residuals per
// row: px then py.
class Camera : public ProblemOf<Camera> {
 public:
  explicit Camera(const std::vector<logs::Log>& logs) {
    std::vector<double> fw, lat, ver, axis, r2;
    for (const auto& log : logs) {
      const auto& f = log.col("forward_m");
      const auto& l = log.col("lateral_m");
      const auto& v = log.col("vertical_m");
      const auto& px = log.col("px");
      const auto& py = log.col("py");
      for (std::size_t i = 0; i < log.rows(); ++i) {
        x_.push_back(l[i] / f[i]);
        z_.push_back(v[i] / f[i]);
        for (int a = 0; a < 2; ++a) {
          y.push_back(a == 0 ? px[i] : py[i]);
          lo.push_back(-kInf);
          hi.push_back(kInf);
          row.push_back(rows);
          fw.push_back(f[i]);
          lat.push_back(l[i]);
          ver.push_back(v[i]);
          axis.push_back(a);
          r2.push_back(x_.back() * x_.back() + z_.back() * z_.back());
        }
        ++rows;
      }
    }
    // Nominal horizontal field of view: 30 deg (shared/spec/diagnose.md; the plug-in's 18.5 deg
    // aperture on the diagonal gives 29.97 deg, reference section 1).
    constexpr double kNominalFov_deg = 30.0;
    fov_ = add_param(*this, "fov_deg", kNominalFov_deg, kNominalFov_deg, 1.0, 170.0);
    base_free = {fov_};
    dx_ = add_param(*this, "dx_px", 0.0, 0.0);
    dy_ = add_param(*this, "dy_px", 0.0, 0.0);
    k1_ = add_param(*this, "k1", 0.0, 0.0, -10.0, 10.0);
    effects = {{"principal_offset", {dx_, dy_}}, {"radial_distortion", {k1_}}};
    covariates.emplace_back("forward_m", fw);
    covariates.emplace_back("lateral_m", lat);
    covariates.emplace_back("vertical_m", ver);
    covariates.emplace_back("axis", axis);
    covariates.emplace_back("radius2", r2);
  }
  template <typename T>
  void eval(const T* p, T* out) const {
    using std::tan;
    const T f_px = T(s::kCameraWidth_px / 2.0) / tan(p[fov_] * (s::kPi / 360.0));
    const double cx = s::kCameraWidth_px / 2.0, cy = s::kCameraHeight_px / 2.0;
    for (std::size_t i = 0; i < x_.size(); ++i) {
      const T scale = 1.0 + p[k1_] * (x_[i] * x_[i] + z_[i] * z_[i]);
      out[2 * i] = cx + p[dx_] - f_px * x_[i] * scale;
      out[2 * i + 1] = cy + p[dy_] - f_px * z_[i] * scale;
    }
  }

 private:
  std::vector<double> x_, z_;
  int fov_ = 0, dx_ = 0, dy_ = 0, k1_ = 0;
};

}  // namespace

std::unique_ptr<Problem> make_problem(const std::vector<logs::Log>& logs, std::string& why) {
  const logs::Kind kind = logs.front().kind;
  for (const auto& l : logs)
    if (l.kind != kind) {
      why = "the logs are not all of one kind";
      return nullptr;
    }
  std::unique_ptr<Problem> p;
  int per_row = 1;
  switch (kind) {
    case logs::Kind::ground: p = std::make_unique<Ground>(logs); break;
    case logs::Kind::proximity: p = std::make_unique<Proximity>(logs); break;
    case logs::Kind::light: p = std::make_unique<Light>(logs); break;
    case logs::Kind::camera:
      p = std::make_unique<Camera>(logs);
      per_row = 2;
      break;
    default:
      why = "diagnose does not support the kind '" + std::string(logs::to_string(kind)) + "' yet";
      return nullptr;
  }
  add_common_covariates(*p, logs, per_row);
  return p;
}

}  // namespace detail

bool supported(logs::Kind kind) {
  return kind == logs::Kind::ground || kind == logs::Kind::proximity || kind == logs::Kind::light || kind == logs::Kind::camera;
}

}  // namespace epuck2::fit::diagnose
