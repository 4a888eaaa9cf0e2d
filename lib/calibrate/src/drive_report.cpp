// The drive calibration (encoders, ToF, slip) as its two outputs: the human report and the
// coefficient file (docs/coefficient-files.md), from the fit's result (calibrate::fit_drive).
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "epuck2/models/kind_facts.hpp"
#include "epuck2/calibrate/report_json.hpp"
#include "epuck2/calibrate/report_text.hpp"
#include "epuck2/calibrate/sensor_reports.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/models/effects.hpp"

namespace epuck2::calibrate {

std::string report_text(const DriveFit& f) {
  Text out;
  out("Drive runs: %zu\n\n", f.runs.size());
  out("Encoders: steps = steps_per_m * commanded distance (%zu rows; commands above the firmware's 1100 steps/s = "
      "1100 / steps_per_m = %.3f cm/s %s: %zu rows)\n",
      f.steps_rows, 100 * f.cap_m_s, f.cap_kept ? "taken as that limit" : "taken as commanded (the encoders beat the limit on the BIC)",
      f.capped_rows);
  if (f.cap_tested)
    out("  firmware cap tested: BIC %.1f with the cap, %.1f without: %s\n", f.bic_capped, f.bic_uncapped,
        f.cap_kept ? "kept" : "the wheels run faster, fitted as they run");
  write_parameter(out, f.steps, "steps_per_m", "steps/m", "  ", "plug-in 7763.656", &f.steps_autocorrelation);
  write_handling(out, f.steps, "steps", "  ", &f.steps_autocorrelation, /*has_rails=*/false);
  for (const auto& p : f.over_limit_runs)
    out("  commands above the limit (%s): %s\n", f.cap_kept ? "capped" : "not capped: the wheels ran them", p.c_str());
  const models::Channel& tof = models::kind_facts("drive")->channels.front();
  out("\nToF: tof_mm = scale * 1000 (D - travel) + offset, travel = encoder travel lagged by tau (%zu rows; %zu at the "
      "%g/%g %s rails or out-of-range codes, censored; %zu codes >= %g%s)\n",
      f.tof_rows, f.tof_censored, tof.low_rail, tof.high_rail, tof.unit, f.tof_out_of_range_codes, logs::kTofOutOfRangeCode_mm,
      f.tof_code_dropouts == 0 ? ""
                               : (", of which " + std::to_string(f.tof_code_dropouts) +
                                  " left out as dropouts: the fitted curve puts the obstacle in view there").c_str());
  const auto& t = f.tof;
  write_parameter(out, t, models::effects::file_key(models::effects::drive_catalogue(), models::effects::drive::tof_scale), "", "  ", "", &f.tof_autocorrelation);
  write_parameter(out, t, "tof_offset_mm", "mm", "  ", "", &f.tof_autocorrelation);
  write_parameter(out, t, "slip_time_constant_s", "s", "  ", "", &f.tof_autocorrelation);
  write_handling(out, t, "mm", "  ", &f.tof_autocorrelation);
  out("  MSE %.3f mm^2 (plug-in: scale 1, offset 0, no slip: %.3f mm^2 on the same %zu rows, those inside the rails "
      "that the fit kept)\n",
      t.mse, f.plugin_tof_mse, f.plugin_tof_rows);
  write_noise_sections(out, {f.tof_noise, f.encoder_noise});
  return out.str();
}

models::sensors::DriveModel model_of(const DriveFit& f) {
  namespace fx = models::effects;
  models::sensors::DriveModel m;
  m.steps_per_m = f.steps.value("steps_per_m");
  // The ToF fit's parameters are the effects whose home is the file's parameters (tof_scale,
  // tof_offset_mm, slip_time_constant_s), by the registry's file keys.
  const fx::Catalogue& catalogue = fx::drive_catalogue();
  fx::for_each_param(m.effects, [&](std::size_t id, int p, int /*element*/, double& v) {
    if (catalogue[id].home != fx::Home::parameters) return;
    const fx::Param& q = catalogue[id].params[static_cast<std::size_t>(p)];
    v = f.tof.value(q.file_key);
    // Between the neutral value and the physical range (a slip lag under 1 ms, finer than any
    // log's rows): no effect the logs resolve, written neutral (the fit's warning says so).
    if (fx::between_neutral_and_range(q, v)) v = q.neutral;
  });
  m.tof_noise_sd_mm = f.tof_noise.sd;
  m.encoder_noise_sd_steps = f.encoder_noise.sd;
  return m;
}

std::vector<fit::ParameterEstimate> robot_estimates(const DriveFit& f) {
  std::vector<fit::ParameterEstimate> out = named_estimates(f.steps);
  for (auto& p : named_estimates(f.tof)) out.push_back(p);
  return out;
}

nlohmann::json coefficient_json(const DriveFit& f, const std::vector<logs::Log>& logs) {
  nlohmann::json j = skeleton(owned_model([&] { return coefficients::calibration_model_json(model_of(f), measured_noise({f.tof_noise, f.encoder_noise})); }), logs);
  j["units"] = {{"steps_per_m", "steps/m"}, {"tof_offset_mm", "mm"}, {models::effects::file_key(models::effects::drive_catalogue(), models::effects::drive::tof_scale), "1"}, {"slip_time_constant_s", "s"},
                {"mse", "mm^2 (ToF)"}, {"steps_mse", "steps^2"}, {"rss", "mm^2 (ToF)"}, {"steps_rss", "steps^2"}};
  // Rows of a run are a time series: both fits' errors get the autocorrelation correction.
  add_estimates(j, f.steps, "", "steps", "steps^2", &f.steps_autocorrelation);
  add_estimates(j, f.tof, "", "tof", "mm^2", &f.tof_autocorrelation);
  j["mse"] = f.tof.mse;
  j["steps_mse"] = f.steps.mse;
  j["observations"] = f.tof.observations;
  j["steps_observations"] = f.steps.observations;
  j["tof_out_of_range_codes"] = f.tof_out_of_range_codes;
  j["tof_code_dropouts"] = f.tof_code_dropouts;
  j["capped_rows"] = f.capped_rows;
  j["over_limit_runs"] = f.over_limit_runs;
  // The cap in m/s of command: the firmware's 1100 steps/s over the fitted steps_per_m.
  j["firmware_cap"] = {{"steps_s", models::sensors::kFirmwareSpeedLimit_steps_s}, {"limit_m_s", f.cap_m_s},
                       {"tested", f.cap_tested}, {"kept", f.cap_kept}};
  if (f.cap_tested) {
    j["firmware_cap"]["bic_capped"] = f.bic_capped;
    j["firmware_cap"]["bic_uncapped"] = f.bic_uncapped;
  }
  j["reference_mse"] = {{"plugin_tof", f.plugin_tof_mse}, {"plugin_tof_rows", f.plugin_tof_rows}};
  add_noise(j, {f.tof_noise, f.encoder_noise});
  add_warnings(j, f.warnings);
  return j;
}
}  // namespace epuck2::calibrate
