// The virtual E-Puck2's battery: a LiPo cell discharged by the robot's electronics and steppers,
// read by the firmware's battery monitor. It records the reference discharge logs in
// data/raw/battery (the paper's protocol: spinning in place at a fixed speed from full charge
// until the robot stops) and simulates any speed profile (a diagnosis test changes the robot's
// capacity, current draw or resistance through RobotParameters).
//
// Physics (every constant below names its source; data/raw/battery/README.md tells the story):
//  * State of charge z (1 = full) by coulomb counting: dz/dt = -I / (3600 C), C = 1800 mAh
//    (paper section 2) times the robot's capacity scale.
//  * Current draw I(speed): one calibrated value per integer speed 0..15 cm/s, linear in between.
//    It is not monotonic in speed: the stepper coils draw current all the time (paper 4.1.7).
//  * Terminal voltage V = OCV(z) - I R, with R the battery path resistance (cell, protection,
//    spring contacts, switch).
//  * The robot stops when V falls below a speed-dependent stop level (steppers stall; at 0 cm/s
//    the run ends at the low-battery level), so the published curves end at charge 0.09-0.26.
//  * Firmware battery monitor (the e-puck2 firmware): every 500 ms a burst of 32 ADC samples
//    (819.2 counts per volt through the 220k/330k divider), their mean, an exponential moving
//    average 0.8 old + 0.2 new; charge = (V_filtered - 3.4) / (4.2 - 3.4), not clamped.
//  * Measurement scatter: pulsed loads (stepper phase switching, the radio that streams the log)
//    pull the supply down through the path; a burst of ADC samples that falls inside a pulse
//    reads the dip. Bursts are 500 ms apart, the pulses are not synchronised with them: each
//    burst catches one with probability kPulseCatchProbability. Plus ADC noise per sample and
//    rounding to whole counts. The dip depth is calibrated to the scatter of the paper's logs.
//
// Calibration (calibrate(), run once from the plug-in's published tables, about 0.1 s): the OCV
// curve's knots, R and the per-speed currents are fitted with Ceres so that the noise-free reading
// follows the published cubic Q[s] over [0, end[s]]; the stop level of each speed is the model's
// terminal voltage at the published end time (so the nominal robot's lifetime is end[s]); the dip
// depth is chosen so that the pooled per-speed cubic's MSE on the logs equals the paper's
// Table 5 "Cubic" value.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "epuck2/models/battery.hpp"
#include "epuck2/models/battery_simulation.hpp"

namespace epuck2::virtual_robot::battery {

namespace mb = epuck2::models::battery;

// --- The robot (paper section 2) --------------------------------------------------------------
/// Paper section 2: "a LiPo rechargeable battery capable of providing 1800 mAh".
inline constexpr double kNominalCapacity_Ah = 1.8;
inline constexpr double kSecondsPerHour = 3600.0;

// --- Firmware battery monitor (e-puck2 firmware, e-puck2_main-processor) --------------------
inline constexpr double kAdcCountsPerVolt = 819.2;   ///< divider 220k/330k, VREF 3.0 V, 12 bit
inline constexpr int kAdcSamplesPerReading = 32;     ///< each reading is a 32-sample mean
inline constexpr double kFilterKeep = 0.8;           ///< EMA: 0.8 old + 0.2 new
inline constexpr double kFilterUpdatePeriod_s = 0.5; ///< the EMA is updated every 500 ms
inline constexpr double kEmptyVoltage_v = 3.4;       ///< percentage = (V - 3.4)/(4.2 - 3.4)
inline constexpr double kFullVoltage_v = 4.2;

// --- Measurement imperfections (assumptions, see data/raw/battery/README.md) -------------------
/// Random noise of one ADC conversion, in counts rms. Assumption: the STM32F4's 12-bit ADC is
/// good to about 11 effective bits on a divided battery line, i.e. about 1 count rms.
inline constexpr double kAdcNoise_counts = 1.0;
/// Fraction of the firmware's ADC bursts that fall inside a load pulse. Assumption (a duty cycle
/// of the pulsed loads); the pulse depth is then calibrated (Calibration::pulse_dip_v).
inline constexpr double kPulseCatchProbability = 0.1;

// --- The OCV curve -----------------------------------------------------------------------------
/// Knots of the open-circuit-voltage curve: state of charge 0, 0.05, ..., 1.
inline constexpr int kOcvKnotCount = 21;
inline constexpr double kOcvKnotStep = 0.05;
/// Prior OCV of a LiPo cell at rest (V) at the knots, state of charge 0, 0.05, ..., 1: the
/// widely published single-cell LiPo "resting voltage vs state of charge" chart (4.20 V full,
/// 3.84 V at 50 %, 3.69 V at 10 %, steep knee below). The calibration starts from it and keeps
/// close to it where the published curves say nothing (below the stop level).
inline constexpr std::array<double, kOcvKnotCount> kLipoOcvPrior_v = {
    3.27, 3.61, 3.69, 3.71, 3.73, 3.75, 3.77, 3.79, 3.80, 3.82, 3.84,
    3.85, 3.87, 3.91, 3.95, 3.98, 4.02, 4.08, 4.11, 4.15, 4.20};

/// Piecewise-linear interpolation of the knots at state of charge z (clamped to [0, 1]).
/// Templated so that the calibration differentiates it with fit::Jet (lib/fit); the segment is chosen
/// from the value of z (a kink at each knot, the exact one-sided derivative elsewhere).
template <typename T>
T ocv_at(const T* knots_v, const T& z, double z_value) {
  int k = static_cast<int>(z_value / kOcvKnotStep);
  if (k < 0) k = 0;
  if (k > kOcvKnotCount - 2) k = kOcvKnotCount - 2;
  const T w = (z - T(k * kOcvKnotStep)) / T(kOcvKnotStep);
  return knots_v[k] + (knots_v[k + 1] - knots_v[k]) * w;
}

/// Everything the calibration decides, plus the figures it measured.
struct Calibration {
  double capacity_Ah = kNominalCapacity_Ah;
  double path_resistance_ohm = 0;                       ///< fitted
  std::array<double, kOcvKnotCount> ocv_v{};            ///< fitted OCV knots (true cell voltage)
  std::array<double, mb::kSpeedCount> current_a{};      ///< fitted draw at 0..15 cm/s
  std::array<double, mb::kSpeedCount> stop_voltage_v{}; ///< terminal voltage at which it stops
  double pulse_dip_v = 0;                               ///< calibrated load-pulse dip depth
  // Figures measured during calibration (nominal robot, noise free).
  double fit_rms_charge = 0;          ///< RMS of the OCV fit against all published cubics
  double clean_pooled_cubic_mse = 0;  ///< pooled cubic MSE of robots a and b without noise
  double target_reading_variance = 0; ///< noise variance the dip was sized for (charge units^2)
};

/// Calibrates the virtual battery to published tables (cubic Q[s] and end[s]). Deterministic.
Calibration calibrate(const mb::Tables& published);
/// calibrate(models::battery::plugin_tables()), computed once (thread safe).
const Calibration& reference_calibration();

/// One robot's differences from the nominal calibrated robot. Scales multiply the calibrated
/// values; 1 everywhere is the nominal robot.
struct RobotParameters {
  std::string name = "virtual-e-puck2";
  double capacity_scale = 1.0;    ///< x 1800 mAh (an aged cell has less)
  double resistance_scale = 1.0;  ///< x the calibrated path resistance
  double current_scale = 1.0;     ///< x the calibrated current draw at every speed
  double pulse_scale = 1.0;       ///< x the calibrated load-pulse dip (0 = no pulses)
  double initial_soc = 1.0;       ///< state of charge at t = 0 (1 = freshly charged)
};

/// The two robots of the reference logs. Their cells differ by +-0.5 % in capacity and their
/// battery paths by +-10 % in resistance: together about +-1 % in lifetime, inside the 2 % to
/// which each robot must match the published end times.
RobotParameters robot_a();
RobotParameters robot_b();

struct SimulationOptions {
  double log_interval_s = 10.0;  ///< a row every this many seconds (multiple of 0.5 s)
  bool noise = true;             ///< false: mean firmware reading, no pulses, no ADC noise
  double max_time_s = 48 * 3600.0;  ///< stop simulating here if the robot still runs
};

/// One logged row (docs/logs.md battery kind, with the optional voltage_v).
struct Row {
  double time_s = 0;
  double speed_cm_s = 0;  ///< commanded wheel speed (spinning in place)
  double charge = 0;      ///< the firmware's percentage / 100, not clamped
  double voltage_v = 0;   ///< the firmware's filtered battery voltage
  /// The cell's true state of charge z (coulomb counted; not logged in the reference logs): what a
  /// fuel gauge would report, for tests of maps from voltage to charge under load.
  double state_of_charge = 1;
};

struct Run {
  std::vector<Row> rows;  ///< from t = 0 every log interval, plus the stop row
  bool stopped = false;   ///< the robot stopped (else max_time_s or the profile's end came first)
  double stop_time_s = 0; ///< the lifetime when stopped
};

/// Speed at 0..15 cm/s (clamped) -> current draw, stop level: linear between integer speeds.
double current_draw_a(const Calibration& cal, double speed_cm_s);
double stop_voltage_v(const Calibration& cal, double speed_cm_s);

/// Runs the robot over a speed profile (each point's speed holds until the next point; the last
/// one holds until the robot stops). Same arguments, same rows, bit for bit.
Run simulate(const std::vector<mb::ProfilePoint>& profile, const RobotParameters& robot,
             std::uint64_t seed, const SimulationOptions& options = {},
             const Calibration& calibration = reference_calibration());

/// The paper's protocol: spinning in place at one speed from full charge until the robot stops.
Run simulate_protocol(double speed_cm_s, const RobotParameters& robot, std::uint64_t seed,
                      const SimulationOptions& options = {},
                      const Calibration& calibration = reference_calibration());

/// Seed of one reference log (robot 0 = a, 1 = b; speed 0..15) derived from the run's seed.
std::uint64_t reference_run_seed(std::uint64_t seed, int robot_index, int speed_cm_s);

// --- Checks against the paper (used by the test and data/raw/battery/README.md) ---------------
/// Table 5 "analytic" MSEs of a set of logs, with the paper's definitions: runs[r][s] is robot r's
/// log at speed s. Cubic: least-squares cubic per speed on both robots' rows pooled. Linear: the
/// line from 1 at t = 0 to 0 at the speed's lifetime (mean of the robots' last times). Simple:
/// 1 + m t, m0 = -1/lifetime(0) at rest, m1 = -1/mean(lifetime(1..15)) moving. The lines are
/// clamped at 0, as the models never predict below an empty battery. Each is the mean over the
/// speeds of the MSE over that speed's rows.
struct Table5Check {
  double cubic = 0, linear = 0, simple = 0;
};
Table5Check table5_check(const std::vector<std::vector<Run>>& runs);

/// RMS of a run's charge against the published cubic Q[s] over its rows up to end[s].
double rms_against_cubic(const Run& run, const mb::CubicRow& published);

}  // namespace epuck2::virtual_robot::battery
