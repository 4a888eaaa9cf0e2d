// The voltage->charge map: what lets `battery` and `table5` take battery logs that carry the
// battery voltage (`voltage_v`) and no `charge`, as real robots report.
//
// The map is fitted to logs that carry both columns:
//
//   charge = f(voltage_v + load_offset_v(speed))
//
// f is continuous and piecewise linear in the (load-corrected) voltage, non-decreasing (more
// voltage, more charge: the fit is constrained so), with its knots at quantiles of the voltages
// fitted; the number of knots (2 = a straight line, up to 16) is chosen by the Bayesian
// information criterion (counts tried in increasing order until two in a row do not lower it). A battery's terminal voltage sags under load (V = OCV - I R, the current
// I depending on the speed), so the fit also tries one voltage offset per logged speed (the first
// speed's is 0; linear between speeds): it is kept only when it lowers the BIC by at least 10
// ("very strong" evidence), else the map has no load term. The residual standard deviation says
// how well charge follows voltage in the logs fitted.
//
// Applied to a voltage outside the corrected-voltage range of the rows fitted, the map clamps to
// its end charge and the caller counts it (ChargeConversion::side): the map is never extrapolated.
#pragma once

#include <cstddef>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "epuck2/logs/log.hpp"

namespace epuck2::calibrate {

/// The only form written and read today.
inline constexpr const char* kChargeMapForm = "monotone_piecewise_linear";

struct ChargeMap {
  std::vector<double> knots_v;          ///< corrected voltage at the knots, strictly ascending (>= 2)
  std::vector<double> knot_charge;      ///< f at the knots, non-decreasing
  /// The load term: a voltage offset per speed (ascending speeds, the first offset 0), linear in
  /// between; both empty when the map has none (then any speed is taken).
  std::vector<double> load_speeds_cm_s;
  std::vector<double> load_offset_v;
  double voltage_min_v = 0, voltage_max_v = 0;  ///< the map's domain, in corrected voltage
  /// Residual standard deviation of the fit (charge units), sqrt(RSS / (n - p)); NaN when the
  /// map was written by hand without one.
  double residual_sd = std::numeric_limits<double>::quiet_NaN();
  double max_abs_residual = std::numeric_limits<double>::quiet_NaN();
  std::size_t observations = 0;  ///< rows fitted (0: written by hand)
  std::vector<std::string> sources;  ///< the logs fitted

  // How the model was chosen (fits only).
  int knots_by_bic = 0;                 ///< knots of the map without a load term, chosen by BIC
  double residual_sd_without_load = std::numeric_limits<double>::quiet_NaN();
  double residual_sd_with_load = std::numeric_limits<double>::quiet_NaN();  ///< NaN: not tried
  double delta_bic_load = std::numeric_limits<double>::quiet_NaN();  ///< BIC(with) - BIC(without)
  std::string load_why;  ///< why the load term was kept, dropped or not tried

  bool has_load() const { return !load_speeds_cm_s.empty(); }
  std::size_t parameters() const { return knots_v.size() + (has_load() ? load_speeds_cm_s.size() - 1 : 0); }
};

/// One row with both columns.
struct ChargeSample {
  double voltage_v = 0;
  double speed_cm_s = 0;  ///< magnitude
  double charge = 0;
};

struct ChargeMapFit {
  bool usable = false;
  std::string message;  ///< why not usable
  ChargeMap map;
};

struct ChargeMapOptions {
  std::vector<int> knot_counts{2, 3, 4, 6, 8, 12, 16};  ///< candidates, chosen by BIC (tried in increasing order)
  bool try_load = true;
  double min_delta_bic = 10.0;      ///< the load term must lower the BIC by this much
  std::size_t rows_per_parameter = 3;  ///< a candidate needs this many rows per parameter
};

/// The rows of the logs that carry both `charge` and `voltage_v`; `sources` gets those logs' paths.
std::vector<ChargeSample> charge_samples(const std::vector<logs::Log>& logs, std::vector<std::string>* sources = nullptr);

/// Fits the map. Never throws for numerical trouble or too few rows: `usable` false with the
/// reason (fewer than 3 rows per parameter of a straight line, voltages that do not vary).
ChargeMapFit fit_charge_map(const std::vector<ChargeSample>& rows, const std::vector<std::string>& sources,
                            const ChargeMapOptions& options = {});

/// The load offset at a speed (0 without a load term); speeds beyond the map's are not
/// extrapolated (check covers_speed first).
double load_offset_v(const ChargeMap& map, double speed_cm_s);
/// True when the map's load term is defined at this speed (always without one).
bool covers_speed(const ChargeMap& map, double speed_cm_s);

struct ChargeConversion {
  double charge = 0;
  int side = 0;  ///< -1: below the map's voltage range, +1: above (clamped to the end charge), 0: inside
  double corrected_v = 0;  ///< the voltage plus the load offset at the row's speed: what the range is of
};
/// f(voltage + load offset), clamped to the domain.
ChargeConversion convert_voltage(const ChargeMap& map, double voltage_v, double speed_cm_s);

/// The `charge_map` section of a coefficient file (docs/coefficient-files.md#charge-map).
nlohmann::json charge_map_to_json(const ChargeMap& map);
/// Reads the map from a battery coefficient file or a dedicated map file (an object with a
/// `charge_map` section); errors name the file, line and entry (logs::InputError).
ChargeMap charge_map_from_json(const nlohmann::json& file, const std::string& path);

}  // namespace epuck2::calibrate
