// The diagnosis's drive kind: its base model and catalogue effects (see kinds.cpp).
#include "kind_common.hpp"
#include "epuck2/logs/drive_columns.hpp"
#include "epuck2/logs/output.hpp"
#include "epuck2/models/kind_facts.hpp"

namespace epuck2::diagnose {

using namespace epuck2::fit;  // the engine (lib/fit)

namespace detail {
using namespace kinds_shared;  // the kinds' shared helpers
namespace {

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
    double max_command = 0;
    std::vector<std::string> dropouts;  // "no target" codes where the encoders put the target in view
    const models::Channel& tof_channel = models::kind_facts("drive")->channels.front();
    for (const auto& log : logs) {
      Run r;
      const logs::DriveColumns cols = logs::drive_columns(log);
      r.obstacle_m = cols.obstacle_m;
      r.first = time_.size();
      const auto& t = cols.time_s;
      const auto& cl = cols.left_cm_s;
      const auto& cr = cols.right_cm_s;
      const auto& tof = cols.tof_mm;
      const std::size_t n = log.rows();
      r.symmetric = std::equal(cl.begin(), cl.end(), cr.begin());
      const std::vector<double> ul = s::unwrap_steps(cols.left_steps), ur = s::unwrap_steps(cols.right_steps);
      for (std::size_t i = 0; i < n; ++i) {
        time_.push_back(t[i]);
        left_.push_back(cl[i]);
        right_.push_back(cr[i]);
        max_command = std::max({max_command, std::abs(cl[i]), std::abs(cr[i])});
        // An encoder register that has not changed since the previous row adds no observation:
        // its rounding error is the previous row's again (a standing robot would otherwise count
        // one error many times). It is left out.
        // A ToF reading as the calibration reads it (the ToF channel's on_rails, lib/models
        // kind_facts.hpp): a "no target" code (>= 8190) is censored at the 2000 mm rail, where the
        // clamped model's reading is the rail itself; one where the encoders put the target in
        // view is a dropout, left out (screening.hpp).
        const bool dropout = tof_code_in_view(tof[i], 1000.0 * (r.obstacle_m - steps_metres(ul[i], ur[i])));
        if (dropout) {
          dropouts.push_back(log.path + ":" + std::to_string(log.line_of_row[i]));
          left_out_on_rails.push_back(dropouts.back() + ": a ToF \"no target\" code (" + logs::format_number(tof[i], 6) +
                                      ") where the encoders put the obstacle in view: a dropout");
        }
        const double values[3] = {tof_channel.on_rails(tof[i]), ul[i], ur[i]};
        // In a straight run with both wheels commanded alike, a right register equal to the left
        // one is the same count (and the same rounding) twice: it is left out too.
        const bool same = r.symmetric && ur[i] == ul[i];
        right_is_left_.push_back(same);
        const bool fresh[3] = {!dropout, i == 0 || ul[i] != ul[i - 1], !same && (i == 0 || ur[i] != ur[i - 1])};
        first_.push_back(static_cast<std::uint32_t>(y.size()));
        for (int c = 0; c < 3; ++c) {
          slot_[c].push_back(fresh[c] ? static_cast<std::int32_t>(y.size()) : -1);
          if (!fresh[c]) continue;
          y.push_back(values[c]);
          channel.push_back(c == 0 ? 0 : 1);
          row.push_back(static_cast<std::uint32_t>(rows));
        }
        ++rows;
      }
      r.last = time_.size();
      runs_.push_back(r);
    }
    if (!dropouts.empty()) {
      std::string at;
      for (std::size_t k = 0; k < dropouts.size() && k < 5; ++k) at += (k ? ", " : "") + dropouts[k];
      warnings.push_back(std::to_string(dropouts.size()) + " ToF \"no target\" codes (>= 8190) where the encoders put the obstacle within " +
                         std::to_string(static_cast<int>((1.0 - kTofInViewMargin) * s::kPluginTof.max_mm)) +
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
    // The residual structure's covariates are built when it is scored (late_covariates).
    for (auto* v : {&time_, &left_, &right_}) v->shrink_to_fit();
    for (auto& v : slot_) v.shrink_to_fit();
    first_.shrink_to_fit();
    right_is_left_.shrink_to_fit();
  }

  /// The covariates of the residual structure, built after the last fit from what the model keeps
  /// (not held through the fits, which never read them: 72 MB on a 1M-row log): per row the
  /// time, the command, and the measured motion from the encoders; per residual its channel.
  /// The encoder registers are the channel-1 residuals' readings: a register left out of them
  /// is the previous row's again, or the left one's (right_is_left_).
  std::vector<LateCovariate> late_covariates() const override {
    std::vector<double> cov_time, cov_cmd, cov_speed, cov_acc, cov_dist, cov_range, cov_since;
    for (auto* v : {&cov_time, &cov_cmd, &cov_speed, &cov_acc, &cov_dist, &cov_range, &cov_since}) v->reserve(rows);
    std::vector<double> cov_channel(y.size());
    for (const Run& r : runs_) {
      const std::size_t n = r.last - r.first;
      const double* t = time_.data() + r.first;
      const double* cl = left_.data() + r.first;
      const double* cr = right_.data() + r.first;
      std::vector<double> ul(n), ur(n);
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t row_i = r.first + i;
        for (std::size_t c = 0; c < 3; ++c)
          if (slot_[c][row_i] >= 0) cov_channel[static_cast<std::size_t>(slot_[c][row_i])] = static_cast<double>(c);
        const std::int32_t left = slot_[1][row_i], right = slot_[2][row_i];
        ul[i] = left >= 0 ? y[static_cast<std::size_t>(left)] : ul[i - 1];
        ur[i] = right >= 0 ? y[static_cast<std::size_t>(right)] : right_is_left_[row_i] ? ul[i] : ur[i - 1];
      }
      // Measured motion from the encoders. Each row's values come from its neighbours' registers
      // only: a row's own register carries its rounding, which would correlate with its own
      // residual.
      std::vector<double> steps_m(n);
      for (std::size_t i = 0; i < n; ++i) steps_m[i] = steps_metres(ul[i], ur[i]);
      auto at = [&](std::ptrdiff_t j) { return static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(j, 0, static_cast<std::ptrdiff_t>(n) - 1)); };
      auto slope = [&](std::size_t a, std::size_t b) { return b > a && t[b] > t[a] ? (steps_m[b] - steps_m[a]) / (t[b] - t[a]) : 0.0; };
      double since = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const auto j = static_cast<std::ptrdiff_t>(i);
        const std::size_t a = at(j - 1), b = at(j + 1);
        const double dist = a == i || b == i ? steps_m[i] : steps_m[a] + (steps_m[b] - steps_m[a]) * (t[i] - t[a]) / (t[b] - t[a]);
        // Speeds over (i-2, i-1) and (i+1, i+2).
        const std::size_t a2 = at(j - 2), b2 = at(j + 2);
        const double before = slope(a2, a), after = slope(b, b2);
        const double span = 0.5 * (t[b] + t[b2]) - 0.5 * (t[a2] + t[a]);
        if (i && (cl[i] != cl[i - 1] || cr[i] != cr[i - 1])) since = t[i];
        // Once per row, not per residual (up to three a row): spread through `row` when scored.
        cov_time.push_back(t[i]);
        cov_cmd.push_back(0.5 * (cl[i] + cr[i]));
        cov_speed.push_back(100.0 * slope(a, b));
        cov_acc.push_back(span > 0 ? 100.0 * (after - before) / span : 0.0);
        cov_dist.push_back(dist);
        cov_range.push_back(r.obstacle_m - dist);
        cov_since.push_back(t[i] - since);
      }
    }
    std::vector<LateCovariate> out;
    out.push_back({"time_s", std::move(cov_time), true});
    out.push_back({"commanded_cm_s", std::move(cov_cmd), true});
    out.push_back({"speed_cm_s", std::move(cov_speed), true});
    out.push_back({"acceleration_cm_s2", std::move(cov_acc), true});
    out.push_back({"distance_m", std::move(cov_dist), true});
    out.push_back({"range_m", std::move(cov_range), true});
    out.push_back({"time_since_command_s", std::move(cov_since), true});
    out.push_back({"channel", std::move(cov_channel), false});
    return out;
  }

  /// A calibrated base: its encoders' steps per metre and the effects it already carries, as
  /// simulate --like runs it (a calibration's firmware cap as its speed_limit: effects_as_run).
  void set_base_model(const s::DriveModel& m) {
    steps_per_m_ = m.steps_per_m;
    set_base_effects(*this, ix_, s::effects_as_run(m));
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

  /// The distance driven by the robot's centre from the two encoder registers (steps), in metres.
  static double steps_metres(double left, double right) { return 0.5 * (left + right) / s::kPluginStepsPerMetre; }

  std::vector<double> time_, left_, right_;
  /// Per row: its right register was left out of the residuals as the left one's again (a
  /// straight run with both registers equal), not as the previous row's.
  std::vector<bool> right_is_left_;
  /// Per row: the residual index of the ToF reading and of each encoder register (-1: left out).
  std::array<std::vector<std::int32_t>, 3> slot_;
  std::vector<std::uint32_t> first_;  ///< per row: the index its residuals start at (the next row's when it has none)
  std::vector<Run> runs_;
  CatalogueIndex ix_;
  double steps_per_m_ = s::kPluginStepsPerMetre;
};

}  // namespace

std::unique_ptr<Problem> make_drive(const std::vector<logs::Log>& logs, const Options& options) {
  return with_base(std::make_unique<Drive>(logs), options);
}

}  // namespace detail
}  // namespace epuck2::diagnose
