// Writes a log with one catalogue effect hidden in it (tests/diagnose_generators.hpp, the
// diagnosis tests' generators) and the generator's truth, for the closed loop through ARGoS
// (argos/tests/closed_loop.sh).
//   usage: argos_hidden_log KIND CAUSE SEED OUT.csv TRUTH.json
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

#include <nlohmann/json.hpp>

#include "../../tests/diagnose_generators.hpp"

int main(int argc, char** argv) {
  namespace gen = epuck2::testing::diagnose;
  if (argc != 6) {
    std::cerr << "usage: argos_hidden_log KIND CAUSE SEED OUT.csv TRUTH.json\n";
    return 2;
  }
  epuck2::logs::Kind kind{};
  const std::string k = argv[1];
  if (k == "drive") kind = epuck2::logs::Kind::drive;
  else if (k == "proximity") kind = epuck2::logs::Kind::proximity;
  else if (k == "ground") kind = epuck2::logs::Kind::ground;
  else if (k == "light") kind = epuck2::logs::Kind::light;
  else if (k == "camera") kind = epuck2::logs::Kind::camera;
  else if (k == "battery") kind = epuck2::logs::Kind::battery;
  else {
    std::cerr << "argos_hidden_log: unknown kind '" << k << "'\n";
    return 2;
  }
  gen::Hidden h = gen::hidden(argv[2]);
  const std::string log = gen::make_log(kind, std::stoull(argv[3]), h);
  std::ofstream(argv[4]) << log;
  nlohmann::json t = {{"kind", k}, {"cause", h.cause}, {"truth", h.truth}, {"parameters_matter", h.parameters_matter}};
  if (kind == epuck2::logs::Kind::light) {
    // The light generator's base gamma, drawn second from the seed (light_log: the row count, then
    // gamma): the closed loop's expected readings need it, and the truth holds only the effect's.
    gen::Draw d(std::stoull(argv[3]));
    d.integer(400, 1000);
    t["generator_gamma_m"] = d.uniform(0.07, 0.08);
  }
  // The reading noise's sd where the generator draws it per log (battery), else absent: the
  // kind's constant noise is the generator's, restated in closed_loop_compare.py.
  if (h.noise_sd > 0) t["noise_sd"] = h.noise_sd;
  std::ofstream(argv[5]) << t.dump(2) << "\n";
  return 0;
}
