#include "epuck2/calibrate/charge_map.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "epuck2/fit/problem.hpp"
#include "epuck2/logs/json_location.hpp"
#include "epuck2/logs/output.hpp"

namespace epuck2::calibrate {

using nlohmann::json;

namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

long speed_key(double speed_cm_s) { return std::lround(std::abs(speed_cm_s) * 100.0); }

// The segment of strictly ascending knots t that x falls in (the end segments extend beyond).
std::size_t segment_of(const std::vector<double>& t, double x) {
  const auto it = std::upper_bound(t.begin(), t.end(), x);
  const std::ptrdiff_t k = (it - t.begin()) - 1;
  return static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(k, 0, static_cast<std::ptrdiff_t>(t.size()) - 2));
}

struct Data {
  std::vector<double> v, q;
  std::vector<std::size_t> speed;  // index into speeds
  std::vector<double> speeds;      // ascending
};

// Residuals q - f(v + delta[speed]) of every row, with f through knots t, parametrised by its
// value at the first knot and its non-negative increments (block 0, size K) and, with the load
// term, the offsets of speeds 1.. (block 1, size S - 1; speed 0's is 0). Analytic Jacobian
// (the engine's ResidualBlock: the segment a row falls in is chosen on values).
class MapResidual {
 public:
  MapResidual(const Data& d, const std::vector<double>& knots, bool load) : d_(d), t_(knots), load_(load) {}
  fit::ResidualBlock block() const {
    fit::ResidualBlock b;
    b.residuals = static_cast<int>(d_.v.size());
    b.sizes.push_back(static_cast<int>(t_.size()));
    if (load_) b.sizes.push_back(static_cast<int>(d_.speeds.size()) - 1);
    b.evaluate = *this;
    return b;
  }
  bool operator()(double const* const* p, double* residuals, double** jacobians) const {
    const std::size_t K = t_.size(), n = d_.v.size();
    const double* a = p[0];
    std::vector<double> y(K);
    y[0] = a[0];
    for (std::size_t k = 1; k < K; ++k) y[k] = y[k - 1] + a[k];
    double* j0 = jacobians != nullptr ? jacobians[0] : nullptr;
    double* j1 = load_ && jacobians != nullptr ? jacobians[1] : nullptr;
    const std::size_t S1 = load_ ? d_.speeds.size() - 1 : 0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t s = d_.speed[i];
      const double x = d_.v[i] + (load_ && s > 0 ? p[1][s - 1] : 0.0);
      const std::size_t k = segment_of(t_, x);
      const double h = t_[k + 1] - t_[k];
      const double w = (x - t_[k]) / h;
      residuals[i] = d_.q[i] - (y[k] + w * a[k + 1]);
      if (!std::isfinite(residuals[i])) return false;
      if (j0 != nullptr) {
        double* row = j0 + i * K;
        for (std::size_t j = 0; j < K; ++j) row[j] = j <= k ? -1.0 : (j == k + 1 ? -w : 0.0);
      }
      if (j1 != nullptr) {
        double* row = j1 + i * S1;
        std::fill(row, row + S1, 0.0);
        if (s > 0) row[s - 1] = -a[k + 1] / h;
      }
    }
    return true;
  }

 private:
  const Data& d_;
  const std::vector<double> t_;
  const bool load_;
};

struct Candidate {
  bool ok = false;
  std::vector<double> knots, increments, offsets;  // offsets: speeds 1.. (load only)
  double rss = 0, bic = 0;
  std::size_t parameters = 0;
};

double bic_of(std::size_t n, double rss, std::size_t p) {
  const double nd = static_cast<double>(n);
  return nd * std::log(std::max(rss, 1e-300) / nd) + static_cast<double>(p) * std::log(nd);
}

// K knots at quantiles of the voltages (the extremes included), duplicates dropped.
std::vector<double> quantile_knots(std::vector<double> sorted_v, int K) {
  std::vector<double> t;
  const std::size_t n = sorted_v.size();
  for (int k = 0; k < K; ++k) {
    const auto idx = static_cast<std::size_t>(std::llround(static_cast<double>(k) * static_cast<double>(n - 1) / (K - 1)));
    const double x = sorted_v[idx];
    if (t.empty() || x > t.back() + 1e-9) t.push_back(x);
  }
  return t;
}

Candidate fit_candidate(const Data& d, const std::vector<double>& knots, bool load, const Candidate* start) {
  Candidate c;
  c.knots = knots;
  const std::size_t K = knots.size(), n = d.v.size();
  std::vector<double> a(K, 0.0), delta(load ? d.speeds.size() - 1 : 0, 0.0);
  if (start != nullptr && start->knots == knots) {
    a = start->increments;
    if (start->offsets.size() == delta.size()) delta = start->offsets;
  } else {
    // A straight line by least squares (slope held >= 0) gives the start.
    double mv = 0, mq = 0;
    for (std::size_t i = 0; i < n; ++i) {
      mv += d.v[i];
      mq += d.q[i];
    }
    mv /= static_cast<double>(n);
    mq /= static_cast<double>(n);
    double sxy = 0, sxx = 0;
    for (std::size_t i = 0; i < n; ++i) {
      sxy += (d.v[i] - mv) * (d.q[i] - mq);
      sxx += (d.v[i] - mv) * (d.v[i] - mv);
    }
    const double slope = sxx > 0 ? std::max(0.0, sxy / sxx) : 0.0;
    a[0] = mq + slope * (knots[0] - mv);
    for (std::size_t k = 1; k < K; ++k) a[k] = slope * (knots[k] - knots[k - 1]);
  }
  const MapResidual cost(d, knots, load);
  fit::Problem problem;
  if (load) problem.add(cost.block(), {a.data(), delta.data()});
  else problem.add(cost.block(), {a.data()});
  for (std::size_t k = 1; k < K; ++k) problem.set_lower_bound(a.data(), static_cast<int>(k), 0.0);
  fit::FitOptions o = fit::FitOptions::calibration();
  // Thousands of rows, at most a few dozen parameters on well-scaled columns (knot weights in
  // [0, 1], offsets' slopes): the normal equations are cheap and lose no digits that matter.
  o.linear_solver = fit::FitOptions::LinearSolver::dense_normal_cholesky;
  o.compute_covariance = false;
  if (!problem.solve(o).usable) return c;
  std::vector<double> r(n);
  const double* blocks[2] = {a.data(), delta.data()};
  if (!cost(blocks, r.data(), nullptr)) return c;
  for (double e : r) c.rss += e * e;
  c.increments = a;
  c.offsets = delta;
  c.parameters = K + delta.size();
  c.bic = bic_of(n, c.rss, c.parameters);
  c.ok = std::isfinite(c.bic);
  return c;
}

// The corrected voltages v + offset(speed) of a candidate with the load term, ascending.
std::vector<double> corrected_sorted(const Data& d, const std::vector<double>& offsets) {
  std::vector<double> x(d.v.size());
  for (std::size_t i = 0; i < d.v.size(); ++i) x[i] = d.v[i] + (d.speed[i] > 0 ? offsets[d.speed[i] - 1] : 0.0);
  std::sort(x.begin(), x.end());
  return x;
}

// A candidate with the load term, its knots moved to the same quantiles of the *corrected*
// voltages (the map's domain: f is a function of them) and fitted again, until the knots the
// offsets give are the knots fitted (the offsets move a little with the knots). Started from the
// load fit on the logged voltages' knots, whose map and offsets give the start.
Candidate on_corrected_knots(const Data& d, Candidate c) {
  constexpr int kPasses = 10;
  constexpr double kSameKnot_v = 1e-9;
  const int K = static_cast<int>(c.knots.size());
  for (int pass = 0; pass < kPasses; ++pass) {
    const std::vector<double> knots = quantile_knots(corrected_sorted(d, c.offsets), K);
    if (knots.size() < 2) break;
    if (knots.size() == c.knots.size() &&
        std::equal(knots.begin(), knots.end(), c.knots.begin(), [&](double a, double b) { return std::abs(a - b) <= kSameKnot_v; }))
      break;
    // The start: the current map's values at the new knots (as increments, the first its value),
    // and the current offsets.
    std::vector<double> value(c.knots.size());
    value[0] = c.increments[0];
    for (std::size_t k = 1; k < c.knots.size(); ++k) value[k] = value[k - 1] + c.increments[k];
    Candidate start;
    start.knots = knots;
    start.offsets = c.offsets;
    double previous = 0;
    for (std::size_t k = 0; k < knots.size(); ++k) {
      const std::size_t j = segment_of(c.knots, knots[k]);
      const double w = (knots[k] - c.knots[j]) / (c.knots[j + 1] - c.knots[j]);
      const double f = value[j] + w * (value[j + 1] - value[j]);
      start.increments.push_back(k == 0 ? f : std::max(0.0, f - previous));
      previous = k == 0 ? f : previous + start.increments.back();
    }
    Candidate next = fit_candidate(d, knots, true, &start);
    if (!next.ok) break;
    c = std::move(next);
  }
  return c;
}

// Fills the map from a candidate (the domain and residuals at its solution).
ChargeMap map_of(const Data& d, const Candidate& c, bool load) {
  ChargeMap m;
  m.knots_v = c.knots;
  m.knot_charge.resize(c.knots.size());
  m.knot_charge[0] = c.increments[0];
  for (std::size_t k = 1; k < c.knots.size(); ++k) m.knot_charge[k] = m.knot_charge[k - 1] + c.increments[k];
  if (load) {
    m.load_speeds_cm_s = d.speeds;
    m.load_offset_v.assign(1, 0.0);
    m.load_offset_v.insert(m.load_offset_v.end(), c.offsets.begin(), c.offsets.end());
  }
  m.voltage_min_v = std::numeric_limits<double>::infinity();
  m.voltage_max_v = -std::numeric_limits<double>::infinity();
  m.max_abs_residual = 0;
  for (std::size_t i = 0; i < d.v.size(); ++i) {
    const double x = d.v[i] + (load && d.speed[i] > 0 ? c.offsets[d.speed[i] - 1] : 0.0);
    m.voltage_min_v = std::min(m.voltage_min_v, x);
    m.voltage_max_v = std::max(m.voltage_max_v, x);
    const std::size_t k = segment_of(m.knots_v, x);
    const double w = (x - m.knots_v[k]) / (m.knots_v[k + 1] - m.knots_v[k]);
    m.max_abs_residual = std::max(m.max_abs_residual, std::abs(d.q[i] - (m.knot_charge[k] + w * (m.knot_charge[k + 1] - m.knot_charge[k]))));
  }
  m.observations = d.v.size();
  m.residual_sd = std::sqrt(c.rss / static_cast<double>(d.v.size() - c.parameters));
  return m;
}

}  // namespace

std::vector<ChargeSample> charge_samples(const std::vector<logs::Log>& logs, std::vector<std::string>* sources) {
  std::vector<ChargeSample> out;
  for (const logs::Log& log : logs) {
    if (log.kind != logs::Kind::battery || !log.has("charge") || !log.has("voltage_v") || !log.has("speed_cm_s")) continue;
    const auto& v = log.col("voltage_v");
    const auto& q = log.col("charge");
    const auto& s = log.col("speed_cm_s");
    for (std::size_t i = 0; i < log.rows(); ++i) out.push_back({v[i], std::abs(s[i]), q[i]});
    if (sources != nullptr) sources->push_back(log.path);
  }
  return out;
}

ChargeMapFit fit_charge_map(const std::vector<ChargeSample>& rows, const std::vector<std::string>& sources,
                            const ChargeMapOptions& options) {
  ChargeMapFit out;
  const std::size_t per = std::max<std::size_t>(1, options.rows_per_parameter);
  if (rows.size() < 2 * per) {
    out.message = "too few rows with both charge and voltage_v (" + std::to_string(rows.size()) + ") for a voltage->charge map: at least " +
                  std::to_string(2 * per) + " (" + std::to_string(per) + " per parameter of a straight line)";
    return out;
  }
  Data d;
  std::map<long, std::size_t> index;
  for (const ChargeSample& r : rows) index.emplace(speed_key(r.speed_cm_s), 0);
  for (auto& [key, i] : index) {
    i = d.speeds.size();
    d.speeds.push_back(static_cast<double>(key) / 100.0);
  }
  for (const ChargeSample& r : rows) {
    d.v.push_back(r.voltage_v);
    d.q.push_back(r.charge);
    d.speed.push_back(index.at(speed_key(r.speed_cm_s)));
  }
  std::vector<double> sorted_v = d.v;
  std::sort(sorted_v.begin(), sorted_v.end());
  if (!(sorted_v.back() > sorted_v.front() + 1e-9)) {
    out.message = "voltage_v does not vary in the rows with both columns (all " +
                  logs::format_number(sorted_v.front(), 4) +
                  " V): no voltage->charge map can be fitted";
    return out;
  }
  const std::size_t n = d.v.size();

  // Without a load term: the number of knots by BIC.
  // Counts in increasing order, until two in a row fail to lower the BIC (it rises once the
  // knots only follow the noise).
  std::map<std::vector<double>, Candidate> plain;  // by knots (two counts may give the same knots)
  const Candidate* best_plain = nullptr;
  int worse = 0;
  std::vector<int> counts = options.knot_counts;
  std::sort(counts.begin(), counts.end());
  for (int K : counts) {
    if (K < 2 || n < per * static_cast<std::size_t>(K) || worse >= 2) continue;
    const std::vector<double> knots = quantile_knots(sorted_v, K);
    if (knots.size() < 2 || plain.count(knots)) continue;
    const Candidate c = fit_candidate(d, knots, false, nullptr);
    if (!c.ok) continue;
    const Candidate& kept = plain.emplace(knots, c).first->second;
    if (best_plain == nullptr || kept.bic < best_plain->bic) {
      best_plain = &kept;
      worse = 0;
    } else {
      ++worse;
    }
  }
  if (best_plain == nullptr) {
    out.message = "the voltage->charge map could not be fitted (the solver found no usable solution)";
    return out;
  }
  ChargeMap m = map_of(d, *best_plain, false);
  m.knots_by_bic = static_cast<int>(best_plain->knots.size());
  m.residual_sd_without_load = m.residual_sd;

  // With one voltage offset per speed: the knots by BIC again, then kept only when the BIC falls
  // by min_delta_bic against the best map without it.
  const std::size_t S = d.speeds.size();
  if (!options.try_load) {
    m.load_why = "not tried (switched off)";
  } else if (S < 2) {
    m.load_why = "not tried: the rows cover one speed (" + logs::format_number(d.speeds.front(), 4) + " cm/s)";
  } else {
    const Candidate* best_load = nullptr;
    std::vector<Candidate> loaded;
    loaded.reserve(plain.size());
    // The knots of the best map without the load term, and the next larger count tried: a load
    // term that only helps by bending the curve shows as no gain over more knots.
    std::vector<const std::vector<double>*> knot_sets{&best_plain->knots};
    for (const auto& [knots, c] : plain)
      if (knots.size() > best_plain->knots.size()) {
        if (knot_sets.size() == 1 || knots.size() < knot_sets[1]->size()) knot_sets.resize(1), knot_sets.push_back(&knots);
      }
    for (const std::vector<double>* ks : knot_sets) {
      const std::vector<double>& knots = *ks;
      const Candidate& c = plain.at(knots);
      if (n < per * (knots.size() + S - 1)) continue;
      Candidate l = fit_candidate(d, knots, true, &c);
      if (!l.ok) continue;
      // The knots at the corrected voltages' quantiles (first and last at their extremes), as
      // the map without the load term has them at the logged ones.
      loaded.push_back(on_corrected_knots(d, std::move(l)));
    }
    for (const Candidate& l : loaded)
      if (best_load == nullptr || l.bic < best_load->bic) best_load = &l;
    if (best_load == nullptr) {
      m.load_why = "not tried: too few rows for one offset per speed (" + std::to_string(S) + " speeds)";
    } else {
      const ChargeMap with = map_of(d, *best_load, true);
      m.residual_sd_with_load = with.residual_sd;
      m.delta_bic_load = best_load->bic - best_plain->bic;
      if (m.delta_bic_load <= -options.min_delta_bic) {
        const ChargeMap plain_map = m;
        m = with;
        m.knots_by_bic = plain_map.knots_by_bic;
        m.residual_sd_without_load = plain_map.residual_sd_without_load;
        m.residual_sd_with_load = with.residual_sd;
        m.delta_bic_load = best_load->bic - best_plain->bic;
        m.load_why = "kept: one voltage offset per speed lowers the BIC by " + logs::format_number(-m.delta_bic_load, 3) +
                     " (residual sd " + logs::format_number(m.residual_sd_without_load, 3) + " -> " +
                     logs::format_number(with.residual_sd, 3) + ")";
      } else {
        m.load_why = std::string("dropped: one voltage offset per speed ") +
                     (m.delta_bic_load > 0 ? "raises the BIC by " + logs::format_number(m.delta_bic_load, 3)
                                           : "lowers the BIC by only " + logs::format_number(-m.delta_bic_load, 3)) +
                     " (it must lower it by " + logs::format_number(options.min_delta_bic, 3) +
                     " or more): charge does not depend on the speed beyond the voltage (residual sd " +
                     logs::format_number(m.residual_sd_without_load, 3) + " without, " +
                     logs::format_number(with.residual_sd, 3) + " with)";
      }
    }
  }
  m.sources = sources;
  out.map = std::move(m);
  out.usable = true;
  return out;
}

double load_offset_v(const ChargeMap& m, double speed_cm_s) {
  if (!m.has_load()) return 0.0;
  const double s = std::abs(speed_cm_s);
  const auto& x = m.load_speeds_cm_s;
  const auto& y = m.load_offset_v;
  if (x.size() == 1 || s <= x.front()) return y.front();
  if (s >= x.back()) return y.back();
  const std::size_t k = segment_of(x, s);
  return y[k] + (y[k + 1] - y[k]) * (s - x[k]) / (x[k + 1] - x[k]);
}

bool covers_speed(const ChargeMap& m, double speed_cm_s) {
  if (!m.has_load()) return true;
  const double s = std::round(std::abs(speed_cm_s) * 100.0) / 100.0;
  return s >= m.load_speeds_cm_s.front() - 1e-9 && s <= m.load_speeds_cm_s.back() + 1e-9;
}

ChargeConversion convert_voltage(const ChargeMap& m, double voltage_v, double speed_cm_s) {
  ChargeConversion c;
  double x = voltage_v + load_offset_v(m, speed_cm_s);
  c.corrected_v = x;
  if (x < m.voltage_min_v) {
    c.side = -1;
    x = m.voltage_min_v;
  } else if (x > m.voltage_max_v) {
    c.side = 1;
    x = m.voltage_max_v;
  }
  const std::size_t k = segment_of(m.knots_v, x);
  const double w = (x - m.knots_v[k]) / (m.knots_v[k + 1] - m.knots_v[k]);
  c.charge = m.knot_charge[k] + w * (m.knot_charge[k + 1] - m.knot_charge[k]);
  return c;
}

json charge_map_to_json(const ChargeMap& m) {
  auto number = [](double x) { return std::isfinite(x) ? json(x) : json(nullptr); };
  json j{
      {"form", kChargeMapForm},
      {"formula", "charge = f(voltage_v + load_offset_v(speed)); f linear between the knots, non-decreasing; "
                  "load_offset_v linear between load_speeds_cm_s; a corrected voltage outside voltage_range_v is "
                  "clamped to the range (and counted)"},
      {"knots_v", m.knots_v},
      {"knot_charge", m.knot_charge},
      {"load", m.has_load() ? "per_speed" : "none"},
      {"load_speeds_cm_s", m.load_speeds_cm_s},
      {"load_offset_v", m.load_offset_v},
      {"voltage_range_v", {m.voltage_min_v, m.voltage_max_v}},
      {"residual_sd", number(m.residual_sd)},
      {"max_abs_residual", number(m.max_abs_residual)},
      {"observations", m.observations},
      {"parameters", m.parameters()},
      {"sources", m.sources},
  };
  if (!std::isfinite(m.residual_sd)) j["residual_sd_why"] = "the map was not fitted here (given by hand, without one)";
  if (!std::isfinite(m.max_abs_residual)) j["max_abs_residual_why"] = "the map was not fitted here (given by hand, without one)";
  if (m.knots_by_bic > 0) {
    json sel{{"criterion", "BIC (n ln(RSS/n) + p ln n); the load term kept when it lowers it by 10 or more"},
             {"knots_by_bic", m.knots_by_bic},
             {"residual_sd_without_load", number(m.residual_sd_without_load)},
             {"residual_sd_with_load", number(m.residual_sd_with_load)},
             {"delta_bic_load", number(m.delta_bic_load)},
             {"load_why", m.load_why}};
    if (!std::isfinite(m.residual_sd_with_load)) sel["residual_sd_with_load_why"] = m.load_why;
    if (!std::isfinite(m.delta_bic_load)) sel["delta_bic_load_why"] = m.load_why;
    j["selection"] = sel;
  }
  return j;
}

namespace {

std::vector<double> numbers_at(const json& j, const std::string& key, const std::string& path, const std::string& at,
                               bool required) {
  if (!j.contains(key)) {
    if (!required) return {};
    throw logs::json_file_error(path, at, "charge_map: expected an array of numbers '" + key + "'");
  }
  const json& a = j.at(key);
  if (!a.is_array()) throw logs::json_file_error(path, at + "/" + key, "charge_map: '" + key + "' must be an array of numbers");
  std::vector<double> out;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!a.at(i).is_number() || !std::isfinite(a.at(i).get<double>()))
      throw logs::json_file_error(path, at + "/" + key + "/" + std::to_string(i), "charge_map: '" + key + "' must hold finite numbers");
    out.push_back(a.at(i).get<double>());
  }
  return out;
}

}  // namespace

ChargeMap charge_map_from_json(const json& file, const std::string& path) {
  if (!file.is_object() || !file.contains("charge_map"))
    throw logs::json_file_error(path, "",
                                "no 'charge_map' section: expected a battery coefficient file written by `epuck2-fit battery -o` "
                                "from logs with both charge and voltage_v, or a map file {\"kind\": \"charge_map\", \"charge_map\": {...}} "
                                "(docs/coefficient-files.md#charge-map)");
  const json& j = file.at("charge_map");
  const std::string at = "/charge_map";
  if (!j.is_object()) throw logs::json_file_error(path, at, "'charge_map' must be an object");
  if (!j.contains("form") || !j.at("form").is_string() || j.at("form").get<std::string>() != kChargeMapForm)
    throw logs::json_file_error(path, j.contains("form") ? at + "/form" : at,
                                std::string("charge_map: expected \"form\": \"") + kChargeMapForm + "\"");
  ChargeMap m;
  m.knots_v = numbers_at(j, "knots_v", path, at, true);
  m.knot_charge = numbers_at(j, "knot_charge", path, at, true);
  if (m.knots_v.size() < 2) throw logs::json_file_error(path, at + "/knots_v", "charge_map: expected at least 2 knots");
  if (m.knot_charge.size() != m.knots_v.size())
    throw logs::json_file_error(path, at + "/knot_charge", "charge_map: expected one charge per knot (" + std::to_string(m.knots_v.size()) + ")");
  for (std::size_t k = 1; k < m.knots_v.size(); ++k) {
    if (!(m.knots_v[k] > m.knots_v[k - 1]))
      throw logs::json_file_error(path, at + "/knots_v/" + std::to_string(k), "charge_map: knots_v must be strictly ascending");
    if (m.knot_charge[k] < m.knot_charge[k - 1])
      throw logs::json_file_error(path, at + "/knot_charge/" + std::to_string(k),
                                  "charge_map: knot_charge must not decrease (more voltage, more charge)");
  }
  m.load_speeds_cm_s = numbers_at(j, "load_speeds_cm_s", path, at, false);
  m.load_offset_v = numbers_at(j, "load_offset_v", path, at, false);
  if (m.load_offset_v.size() != m.load_speeds_cm_s.size())
    throw logs::json_file_error(path, at + "/load_offset_v", "charge_map: expected one load_offset_v per load speed");
  for (std::size_t k = 1; k < m.load_speeds_cm_s.size(); ++k)
    if (!(m.load_speeds_cm_s[k] > m.load_speeds_cm_s[k - 1]))
      throw logs::json_file_error(path, at + "/load_speeds_cm_s/" + std::to_string(k), "charge_map: load_speeds_cm_s must be strictly ascending");
  if (j.contains("voltage_range_v")) {
    const std::vector<double> r = numbers_at(j, "voltage_range_v", path, at, true);
    if (r.size() != 2 || !(r[1] > r[0]))
      throw logs::json_file_error(path, at + "/voltage_range_v", "charge_map: voltage_range_v must be [min, max] with min < max");
    m.voltage_min_v = r[0];
    m.voltage_max_v = r[1];
  } else {
    m.voltage_min_v = m.knots_v.front();
    m.voltage_max_v = m.knots_v.back();
  }
  auto optional_number = [&](const char* key, double& out) {
    if (!j.contains(key) || j.at(key).is_null()) return;
    if (!j.at(key).is_number()) throw logs::json_file_error(path, at + "/" + key, std::string("charge_map: '") + key + "' must be a number");
    out = j.at(key).get<double>();
  };
  optional_number("residual_sd", m.residual_sd);
  optional_number("max_abs_residual", m.max_abs_residual);
  if (j.contains("observations") && j.at("observations").is_number_unsigned()) m.observations = j.at("observations").get<std::size_t>();
  if (j.contains("sources") && j.at("sources").is_array())
    for (const json& s : j.at("sources"))
      if (s.is_string()) m.sources.push_back(s.get<std::string>());
  return m;
}

}  // namespace epuck2::calibrate
