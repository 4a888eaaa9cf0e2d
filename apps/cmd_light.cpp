// epuck2-fit light LOGS...: gamma of paper Eq. 2, reading/4095 = 1 - (gamma I / d)^2, fitted to the
// unsaturated readings (paper section 4.1.2), beside the plug-in's gamma = 1/13.333 = 0.075.
#include <cstdio>
#include <map>

#include "epuck2/fit/sensors.hpp"
#include "epuck2/plot/png.hpp"
#include "sensor_support.hpp"

namespace epuck2::app {

namespace {

namespace s = models::sensors;

void print_report(const fit::LightFit& f) {
  std::printf("Ambient light sensor, paper Eq. 2: reading/4095 = 1 - (gamma I / d)^2\n");
  std::printf("%zu readings, %zu used (%zu saturated, dark or out of range left out)\n\n", f.readings,
              f.observations.size(), f.censored);
  std::printf("gamma = %.6f +- %.2g m  (MSE %.3e, normalised units)\n", f.gamma.value("gamma"), f.gamma.std_error("gamma"),
              f.gamma.mse);
  for (std::size_t i = 0; i < f.sensors.size(); ++i)
    std::printf("  sensor %d alone: gamma = %.6f +- %.2g m  (MSE %.3e)\n", f.sensors[i], f.gamma_per_sensor[i].value("gamma"),
                f.gamma_per_sensor[i].std_error("gamma"), f.gamma_per_sensor[i].mse);
  std::printf("Plug-in: gamma = 1/13.3333 = 0.075 m, MSE on the same readings %.3e\n", f.plugin_mse);
}

void draw(logs::OutputStage& stage, const std::string& path, const fit::LightFit& f) {
  std::map<double, std::vector<std::vector<double>>> by_intensity;
  for (const auto& o : f.observations) by_intensity[o.intensity].push_back({o.distance_m * 100, o.value_raw, double(o.sensor)});
  const double g = f.gamma.value("gamma");
  plot::render_png(stage, path, [&](gnuplotio::Gnuplot& gp) {
    int k = 0;
    for (const auto& [i, rows] : by_intensity) gp << app::sensors::datablock("i" + std::to_string(k++), rows);
    gp << "set title 'Ambient light sensor (paper Eq. 2, Fig. 5): reading against distance per intensity'\n";
    gp << "set xlabel 'distance to the light (cm)'\nset ylabel 'raw reading (4095 = dark)'\n";
    gp << "set xrange [5:52]\nset yrange [-100:4200]\nset grid\nset key bottom right\nset samples 400\n";
    gp << "L(g, I, x) = (v = (1 - (g*I/(x/100.0))**2)*4095, v < 0 ? 0 : (v > 4095 ? 4095 : v))\n";
    const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};
    gp << "plot ";
    k = 0;
    for (const auto& [intensity, rows] : by_intensity) {
      const char* c = colours[k % 6];
      char buf[600];
      std::snprintf(buf, sizeof buf,
                    "%s$i%d using 1:2 with points pt 7 ps 0.6 lc rgb '%s' title 'I = %.2f readings', "
                    "L(%.8g, %.6g, x) lw 2.5 lc rgb '%s' title 'fit, gamma = %.4f', "
                    "L(%.8g, %.6g, x) lw 1.5 dt 2 lc rgb '%s' title 'plug-in, gamma = 0.075'",
                    k ? ", " : "", k, c, intensity, g, intensity, c, g, s::kPluginLight.gamma_m, intensity, c);
      gp << buf;
      ++k;
    }
    gp << "\n";
  });
}

int run_light(const app::sensors::SensorOptions& o) {
  const auto logs = logs::read_logs(o.logs, logs::Kind::light);
  const fit::LightFit f = fit::fit_light(logs);
  app::sensors::require_usable(f.gamma, "light fit");
  nlohmann::json j = app::sensors::skeleton("light", o.logs);
  app::sensors::add_parameters(j, f.gamma);
  j["parameters"]["range_m"] = s::kPluginLight.range_m;
  j["mse"] = f.gamma.mse;
  j["observations"] = f.gamma.observations;
  j["readings"] = f.readings;
  j["censored"] = f.censored;
  j["units"] = {{"gamma", "m per intensity unit"}, {"mse", "(reading / 4095)^2"}};
  nlohmann::json per = nlohmann::json::array();
  for (std::size_t i = 0; i < f.sensors.size(); ++i)
    per.push_back({{"sensor", f.sensors[i]}, {"gamma", app::sensors::number(f.gamma_per_sensor[i].value("gamma"))},
                   {"std_error", app::sensors::number(f.gamma_per_sensor[i].std_error("gamma"))},
                   {"mse", f.gamma_per_sensor[i].mse}});
  j["per_sensor"] = per;
  j["reference_mse"] = {{"plugin", f.plugin_mse}};
  return app::sensors::finish("light", o, j, [&] { print_report(f); }, [&](logs::OutputStage& stage, const std::string& path) { draw(stage, path, f); });
}

}  // namespace

void setup_light(CLI::App& app, Action& action) {
  auto o = std::make_shared<app::sensors::SensorOptions>();
  CLI::App* sub = app.add_subcommand("light", "Calibrate the ambient light sensors: gamma of Eq. 2");
  app::sensors::add_common_options(sub, *o, "Light");
  sub->callback([o, &action] { action = [o] { return run_light(*o); }; });
}

}  // namespace epuck2::app
