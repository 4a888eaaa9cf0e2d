// epuck2-fit drive LOGS...: encoder steps per metre (steps against the commanded distance, paper
// section 4.1.5) and the ToF's scale and offset (ToF against the obstacle distance minus the
// travelled distance, section 4.1.4), with the wheel slip as a first-order lag of the body behind
// the wheels.
#include <cstdio>

#include "epuck2/models/effects.hpp"
#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/plot/sensor_figures.hpp"
#include "sensor_support.hpp"

namespace epuck2::app {

namespace {

void print_drive_report(const calibrate::DriveFit& f) {
  std::printf("Drive runs: %zu\n\n", f.runs.size());
  std::printf("Encoders: steps = steps_per_m * commanded distance (%zu rows; commands above the firmware's 1100 steps/s = "
              "14.17 cm/s %s: %zu rows)\n",
              f.steps_rows, f.cap_kept ? "taken as that limit" : "taken as commanded (the encoders beat the limit on the BIC)",
              f.capped_rows);
  if (f.cap_tested)
    std::printf("  firmware cap tested: BIC %.1f with the cap, %.1f without: %s\n", f.bic_capped, f.bic_uncapped,
                f.cap_kept ? "kept" : "the wheels run faster, fitted as they run");
  app::sensors::print_parameter(f.steps, "steps_per_m", "steps/m", "  ", "plug-in 7763.656", &f.steps_autocorrelation);
  app::sensors::print_handling(f.steps, "steps", "  ", &f.steps_autocorrelation, /*has_rails=*/false);
  for (const auto& p : f.over_limit_runs) std::printf("  commands above the limit (capped): %s\n", p.c_str());
  std::printf("\nToF: tof_mm = scale * 1000 (D - travel) + offset, travel = encoder travel lagged by tau (%zu rows; %zu at the "
              "20/2000 mm rails or out-of-range codes, censored; %zu codes >= 8190)\n",
              f.tof_rows, f.tof_censored, f.tof_out_of_range_codes);
  const auto& t = f.tof;
  app::sensors::print_parameter(t, models::effects::file_key(models::effects::drive_catalogue(), models::effects::drive::tof_scale), "", "  ", "", &f.tof_autocorrelation);
  app::sensors::print_parameter(t, "tof_offset_mm", "mm", "  ", "", &f.tof_autocorrelation);
  app::sensors::print_parameter(t, "slip_time_constant_s", "s", "  ", "", &f.tof_autocorrelation);
  app::sensors::print_handling(t, "mm", "  ", &f.tof_autocorrelation);
  std::printf("  MSE %.3f mm^2 (plug-in: scale 1, offset 0, no slip: %.3f mm^2)\n", t.mse, f.plugin_tof_mse);
  app::sensors::print_noise_and_warnings({f.tof_noise, f.encoder_noise}, f.warnings);
}

nlohmann::json drive_json(const std::vector<logs::Log>& logs, const app::sensors::SensorOptions& o, calibrate::DriveFit* keep) {
  calibrate::DriveFit f = calibrate::fit_drive(logs, o.fit_options());
  app::sensors::require_usable(f.steps, "encoder fit");
  app::sensors::require_usable(f.tof, "ToF fit");
  app::sensors::require_fitting(f.steps, "encoder fit", o, f.warnings);
  app::sensors::require_fitting(f.tof, "ToF fit", o, f.warnings);
  nlohmann::json j = app::sensors::skeleton("drive", logs);
  j["units"] = {{"steps_per_m", "steps/m"}, {"tof_offset_mm", "mm"}, {models::effects::file_key(models::effects::drive_catalogue(), models::effects::drive::tof_scale), "1"}, {"slip_time_constant_s", "s"},
                {"mse", "mm^2 (ToF)"}, {"steps_mse", "steps^2"}, {"rss", "mm^2 (ToF)"}, {"steps_rss", "steps^2"}};
  // Rows of a run are a time series: both fits' errors get the autocorrelation correction.
  app::sensors::add_parameters(j, f.steps, "", "steps", "steps", &f.steps_autocorrelation);
  app::sensors::add_parameters(j, f.tof, "", "tof", "mm", &f.tof_autocorrelation);
  j["mse"] = f.tof.mse;
  j["steps_mse"] = f.steps.mse;
  j["observations"] = f.tof.observations;
  j["steps_observations"] = f.steps.observations;
  j["tof_out_of_range_codes"] = f.tof_out_of_range_codes;
  j["capped_rows"] = f.capped_rows;
  j["over_limit_runs"] = f.over_limit_runs;
  if (f.cap_tested)
    j["firmware_cap"] = {{"kept", f.cap_kept}, {"bic_capped", f.bic_capped}, {"bic_uncapped", f.bic_uncapped}};
  j["reference_mse"] = {{"plugin_tof", f.plugin_tof_mse}};
  app::sensors::add_noise(j, {f.tof_noise, f.encoder_noise});
  app::sensors::add_warnings(j, f.warnings);
  if (keep != nullptr) *keep = std::move(f);
  return j;
}

}  // namespace

void setup_drive(CLI::App& app, Action& action) {
  app::sensors::add_sensor_command<calibrate::DriveFit>(
      app, action,
      {"drive", logs::Kind::drive, "Calibrate encoders and ToF from straight runs towards/away from an obstacle", "Drive",
       "Required metadata: '# obstacle_distance_m: D' (m, at time 0). tof_mm 20..2000."},
      drive_json, print_drive_report, plot::drive_figure);
}

}  // namespace epuck2::app
