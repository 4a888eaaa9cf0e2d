// The diagnosis's battery kind: its base model and catalogue effects (see kinds.cpp).
#include "kind_common.hpp"

namespace epuck2::diagnose {

using namespace epuck2::fit;  // the engine (lib/fit)

namespace detail {
using namespace kinds_shared;  // the kinds' shared helpers
namespace {

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

std::unique_ptr<Problem> make_battery(const std::vector<logs::Log>& logs, const Options& options) {
  // The tables given (--coefficients), else the plug-in's published ones: the library never
  // compiles in the project's fitted data.
  const models::battery::Tables tables = options.battery_tables ? *options.battery_tables : models::battery::plugin_tables();
  auto battery = std::make_unique<Battery>(logs, options.battery_model, tables);
  battery->set_base_capacity(options.battery_capacity_k);
  return battery;
}

}  // namespace detail
}  // namespace epuck2::diagnose
