// The effect registry (lib/models effects.hpp) and the coefficient file's one owner
// (lib/coefficients): every effect of every kind through the file and back bit for bit, every
// value outside its physical range refused at its file:line:column, unknown effect names refused
// with "did you mean", the noise section round-tripping where its squares overflow, and a new
// effect (the camera's distortion_k2) reaching codegen and `simulate --like` without either
// naming it. The expected values are the ones each test sets, or positions found in the text.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>

#include "cli_harness.hpp"
#include "diagnose_generators.hpp"
#include "epuck2/coefficients/codegen.hpp"
#include "epuck2/coefficients/model_file.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/logs/log.hpp"
#include "epuck2/models/effects.hpp"
#include "epuck2/models/kind_facts.hpp"

// This file's `using namespace` stays in its own named namespace, so it opens nothing to the
// files compiled after it in the same unity unit (tests/CMakeLists.txt).
namespace test_coefficients_cpp {
namespace {

using namespace epuck2;
namespace s = models::sensors;
namespace fx = models::effects;
namespace co = epuck2::coefficients;
using nlohmann::json;

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// ----- the registry ------------------------------------------------------------------------------

/// Every (effect, parameter, element) the visitor reaches, with the value it holds.
template <class Effects>
std::map<std::tuple<std::size_t, int, int>, double> visited(Effects e) {
  std::map<std::tuple<std::size_t, int, int>, double> out;
  fx::for_each_param(e, [&](std::size_t id, int p, int k, double& v) {
    EXPECT_TRUE(out.emplace(std::make_tuple(id, p, k), v).second) << "visited twice: effect " << id << " param " << p << "[" << k << "]";
  });
  return out;
}

/// The visitor reaches every element of every parameter of every effect that lives in the model,
/// exactly once, and the model's default struct holds the registry's neutral value there.
template <class Effects>
void check_catalogue(const fx::Catalogue& c, std::size_t handles) {
  EXPECT_EQ(c.size(), handles) << "the handles and the catalogue disagree";
  const auto seen = visited(Effects{});
  std::size_t expected = 0;
  std::set<std::string> names;
  for (std::size_t id = 0; id < c.size(); ++id) {
    EXPECT_TRUE(names.insert(c[id].name).second) << "two effects named " << c[id].name;
    EXPECT_GT(std::string(c[id].meaning).size(), 10u) << c[id].name;
    for (std::size_t p = 0; p < c[id].params.size(); ++p) {
      const fx::Param& q = c[id].params[p];
      EXPECT_TRUE(fx::Effect::admissible(q, q.neutral)) << c[id].name << "." << q.key;
      EXPECT_TRUE(q.start >= q.lower && q.start <= q.upper) << c[id].name << "." << q.key << " starts outside its range";
      EXPECT_LT(q.lower, q.upper) << c[id].name << "." << q.key;
      if (c[id].home == fx::Home::base) {
        EXPECT_EQ(std::string(q.member), "") << c[id].name;
        continue;
      }
      EXPECT_NE(std::string(q.member), "") << c[id].name << "." << q.key << " has no C++ member";
      if (c[id].home == fx::Home::parameters) EXPECT_NE(std::string(q.file_key), "") << c[id].name;
      for (int k = 0; k < q.count; ++k) {
        ++expected;
        const auto it = seen.find({id, static_cast<int>(p), k});
        ASSERT_NE(it, seen.end()) << c[id].name << "." << q.key << "[" << k << "] is not visited";
        EXPECT_EQ(it->second, q.neutral) << c[id].name << "." << q.key << ": the struct's default is not the registry's neutral";
      }
    }
  }
  EXPECT_EQ(seen.size(), expected) << "the visitor reaches parameters the registry does not list";
}

TEST(EffectRegistry, EveryKindsCatalogueMatchesItsStructsAndVisitor) {
  check_catalogue<s::ProximityEffects<double>>(fx::proximity_catalogue(), fx::proximity::count);
  check_catalogue<s::LightEffects<double>>(fx::light_catalogue(), fx::light::count);
  check_catalogue<s::GroundNonlinear<double>>(fx::ground_catalogue(), fx::ground::count);
  check_catalogue<s::CameraRadialDistortion<double>>(fx::camera_catalogue(), fx::camera::count);
  check_catalogue<s::DriveEffects<double>>(fx::drive_catalogue(), fx::drive::count);
  check_catalogue<models::battery::CapacityScale>(fx::battery_catalogue(), fx::battery::count);
}

TEST(EffectRegistry, EveryEffectHasItsLineInTheDocs) {
  const std::string doc = read_text(std::string(EPUCK2_SOURCE_DIR) + "/docs/diagnose.md");
  for (const char* kind : fx::kinds())
    for (const fx::Effect& e : *fx::catalogue(kind))
      EXPECT_NE(doc.find(std::string("`") + e.name + "`"), std::string::npos) << e.name << " is not in docs/diagnose.md";
}

/// What `command` prints on standard output, and its exit status.
std::pair<std::string, int> guard_output(const std::string& command) {
  std::string out;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return {"", -1};
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) out += buffer;
  return {out, ::pclose(pipe)};
}

// The guard that no source names an effect outside the registry (tests/check_effect_names.py)
// reads the registry's entries from effects.hpp's text: it reads every entry the C++ registry
// holds, kind by kind, so that an entry written in a form its pattern misses cannot drop out of
// the check.
TEST(EffectRegistry, TheNameGuardReadsEveryEntry) {
  const std::string src = EPUCK2_SOURCE_DIR;
  const auto [listed, status] = guard_output("/usr/bin/python3 " + src + "/tests/check_effect_names.py --list " + src);
  ASSERT_EQ(status, 0) << listed;
  std::multiset<std::string> expected, read;
  for (const char* kind : fx::kinds())
    for (const fx::Effect& e : *fx::catalogue(kind)) expected.insert(std::string(kind) + " " + e.name);
  std::istringstream in(listed);
  for (std::string line; std::getline(in, line);) read.insert(line);
  EXPECT_EQ(read, expected) << "the guard reads:\n" << listed;
}

// ----- every effect through the file and back ---------------------------------------------------

/// A value inside parameter q's range, not neutral, different for each (effect, parameter,
/// element): the test's own, so that a swapped or dropped value shows.
double test_value(const fx::Param& q, std::size_t id, int p, int k) {
  const double lo = std::max(q.lower, -1e4), hi = std::min(q.upper, 1e4);
  double v = lo + (hi - lo) * (0.1 + 0.05 * static_cast<double>(id) + 0.013 * p + 0.031 * k);
  if (v == q.neutral) v = 0.5 * (v + hi);
  return std::min(v, hi);
}

template <class Model>
void set_every_effect(Model& m) {
  const fx::Catalogue& c = fx::catalogue_of(m);
  fx::for_each_param(fx::effects_of(m), [&](std::size_t id, int p, int k, double& v) {
    v = test_value(c[id].params[static_cast<std::size_t>(p)], id, p, k);
  });
}

template <class Model>
void expect_same_effects(Model a, Model b) {
  const auto va = visited(fx::effects_of(a)), vb = visited(fx::effects_of(b));
  ASSERT_EQ(va.size(), vb.size());
  for (const auto& [key, v] : va) EXPECT_EQ(vb.at(key), v) << "effect " << std::get<0>(key) << " param " << std::get<1>(key);
}

TEST(CoefficientFile, EveryEffectOfEveryKindRoundTripsBitForBit) {
  {
    s::ProximityModel m;
    m.base = {201.5, -31.25, 1.0078125, 0.05};
    set_every_effect(m);
    m.noise_sd_raw = {1, 2, 3, 4, 5, 6, 7, 8};
    m.covariates = {{"temperature_c", 0.75, 30.5}};
    const auto back = co::proximity_model_from_json(co::model_to_json(m), "p.json");
    expect_same_effects(m, back);
    EXPECT_EQ(back.base.a_per_m2, 201.5);
    EXPECT_EQ(back.noise_sd_raw, m.noise_sd_raw);
    ASSERT_EQ(back.covariates.size(), 1u);
    EXPECT_EQ(back.covariates[0].slope, 0.75);
  }
  {
    s::LightModel m;
    m.base.gamma_m = 0.0625;
    set_every_effect(m);
    expect_same_effects(m, co::light_model_from_json(co::model_to_json(m), "l.json"));
  }
  {
    s::GroundModel m;
    m.sensors = {{{900.5, 60.25}, {940.0, 47.5}, {870.25, 75.0}}};
    set_every_effect(m);
    const auto back = co::ground_model_from_json(co::model_to_json(m), "g.json");
    expect_same_effects(m, back);
    EXPECT_EQ(back.sensors[2].gain_raw, 870.25);
    EXPECT_EQ(back.sensors[1].offset_raw, 47.5);
  }
  {
    s::CameraModel m;
    m.base.cx_px = 81.5;
    set_every_effect(m);
    EXPECT_NE(m.distortion.k2, 0.0);
    EXPECT_NE(m.distortion.k3, 0.0);
    expect_same_effects(m, co::camera_model_from_json(co::model_to_json(m), "c.json"));
  }
  {
    s::DriveModel m;
    m.steps_per_m = 7700.5;
    set_every_effect(m);
    m.tof_noise_sd_mm = 3.5;
    m.encoder_noise_sd_steps = 0.25;
    const auto back = co::drive_model_from_json(co::model_to_json(m), "d.json");
    expect_same_effects(m, back);
    EXPECT_EQ(back.encoder_noise_sd_steps, 0.25);
  }
  {
    s::BatteryModel m;
    set_every_effect(m);
    EXPECT_NE(m.capacity.k, 1.0);
    expect_same_effects(m, co::battery_model_from_json(co::model_to_json(m), "b.json"));
  }
}

TEST(CoefficientFile, ARobotsSetIsReadOverThePooledOne) {
  s::GroundModel m;
  json j = co::model_to_json(m);
  j["robots"] = {{"r2", {{"parameters", {{"gain", {800.0, 810.0, 820.0}}}}}}};
  const auto pooled = co::ground_model_from_json(j, "g.json");
  const auto r2 = co::ground_model_from_json(j, "g.json", "r2");
  EXPECT_EQ(pooled.sensors[1].gain_raw, s::kPluginGround.gain_raw);
  EXPECT_EQ(r2.sensors[1].gain_raw, 810.0);
  EXPECT_EQ(r2.sensors[1].offset_raw, s::kPluginGround.offset_raw);  // from the pooled set
  EXPECT_EQ(co::robot_ids(j), std::vector<std::string>{"r2"});
  try {
    (void)co::ground_model_from_json(j, "g.json", "r7");
    FAIL() << "a robot the file does not have was accepted";
  } catch (const logs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("r2"), std::string::npos) << e.what();
  }
}

// ----- one validation, located --------------------------------------------------------------------

/// The message of the error reading `j` as a model of `kind` throws ("" when it reads).
std::string error_of_coeff(const std::string& kind, const json& j, const std::string& path = "x.json") {
  try {
    if (kind == "proximity") (void)co::proximity_model_from_json(j, path);
    else if (kind == "light") (void)co::light_model_from_json(j, path);
    else if (kind == "ground") (void)co::ground_model_from_json(j, path);
    else if (kind == "camera") (void)co::camera_model_from_json(j, path);
    else if (kind == "drive") (void)co::drive_model_from_json(j, path);
    else (void)co::battery_model_from_json(j, path);
  } catch (const logs::InputError& e) {
    return e.what();
  }
  return "";
}

json neutral_file(const std::string& kind) {
  if (kind == "proximity") return co::model_to_json(s::ProximityModel{});
  if (kind == "light") return co::model_to_json(s::LightModel{});
  if (kind == "ground") return co::model_to_json(s::GroundModel{});
  if (kind == "camera") return co::model_to_json(s::CameraModel{});
  if (kind == "drive") return co::model_to_json(s::DriveModel{});
  return co::model_to_json(s::BatteryModel{});
}

TEST(CoefficientFile, EveryEffectParameterOutsideItsRangeIsRefusedWithItsPath) {
  for (const char* kind : fx::kinds())
    for (const fx::Effect& e : *fx::catalogue(kind)) {
      if (e.home == fx::Home::base) continue;
      for (const fx::Param& q : e.params) {
        for (const double bad : {q.upper + std::abs(q.upper) + 1.0, q.lower - std::abs(q.lower) - 1.0}) {
          if (bad == q.neutral) continue;
          json j = neutral_file(kind);
          const json value = q.count == 1 ? json(bad) : json(std::vector<double>(static_cast<std::size_t>(q.count), bad));
          std::string pointer;
          if (e.home == fx::Home::parameters) {
            j["parameters"][q.file_key] = value;
            pointer = std::string("/parameters/") + q.file_key;
          } else {
            json o = json::object();
            for (const fx::Param& other : e.params)
              o[other.key] = other.count == 1 ? json(other.neutral) : json(std::vector<double>(static_cast<std::size_t>(other.count), other.neutral));
            o[q.key] = value;
            j["effects"][e.name] = o;
            pointer = std::string("/effects/") + e.name + "/" + q.key;
          }
          const std::string msg = error_of_coeff(kind, j);
          EXPECT_NE(msg.find("physical range"), std::string::npos) << kind << " " << e.name << "." << q.key << " = " << bad << ": " << msg;
          EXPECT_NE(msg.find(pointer), std::string::npos) << msg;
        }
      }
    }
}

TEST(CoefficientFile, UnknownAndMisspeltEffectsAreRefused) {
  json g = neutral_file("ground");
  g["effects"]["nonlinear_respones"] = {{"exponent", 1.2}};
  const std::string msg = error_of_coeff("ground", g);
  EXPECT_NE(msg.find("unknown effect 'nonlinear_respones'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("did you mean 'nonlinear_response'"), std::string::npos) << msg;
  json p = neutral_file("proximity");
  p["effects"]["warp_drive"] = {{"k", 1.0}};
  EXPECT_NE(error_of_coeff("proximity", p).find("unknown effect 'warp_drive'"), std::string::npos);
  json t = neutral_file("proximity");
  t["effects"]["long_tail"] = {{"amplitude", 10.0}, {"lenght_m", 0.02}};
  EXPECT_NE(error_of_coeff("proximity", t).find("has no parameter 'lenght_m'"), std::string::npos) << error_of_coeff("proximity", t);
  // A finding folded into the base is no effect a model file holds.
  json b = neutral_file("ground");
  b["effects"]["black_offset"] = {{"offset", 5.0}};
  EXPECT_NE(error_of_coeff("ground", b).find("folds it into the base"), std::string::npos) << error_of_coeff("ground", b);
}

TEST(CoefficientFile, HostileValuesAreRefused) {
  struct Case {
    std::string kind, pointer;
    json value;
    std::string says;
  };
  const std::vector<Case> cases{
      {"camera", "/parameters/fov_deg", 0.0, "physical range"},
      {"camera", "/parameters/fov_deg", 360.0, "physical range"},
      {"camera", "/parameters/cx_px", 1e300, "physical range"},
      {"camera", "/noise/camera/sd", 1e308, "noise sd"},
      {"drive", "/parameters/steps_per_m", 0.0, "physical range"},
      {"drive", "/parameters/steps_per_m", -5.0, "physical range"},
      {"drive", "/parameters/steps_per_m", 1e308, "physical range"},
      {"drive", "/parameters/tof_scale", 0.0, "physical range"},
      {"proximity", "/noise/proximity/sd", 1e308, "noise sd"},
      {"proximity", "/parameters/range_m", -0.05, "physical range"},
      {"light", "/parameters/gamma", 0.0, "physical range"},
      {"ground", "/parameters/gain", json::array({900.0, -5.0, 900.0}), "physical range"},
      {"battery", "/speeds/3/lifetime_s", 0.0, "positive"},
      {"battery", "/speeds/3/lifetime_s", -100.0, "positive"},
      {"battery", "/speeds/3/linear_slope", 1e-4, "negative"},
      {"battery", "/effects/capacity_scale", json{{"k", 0.0}}, "physical range"},
  };
  for (const Case& c : cases) {
    json j = neutral_file(c.kind);
    j[json::json_pointer(c.pointer)] = c.value;
    const std::string msg = error_of_coeff(c.kind, j);
    EXPECT_NE(msg.find(c.says), std::string::npos) << c.kind << " " << c.pointer << " = " << c.value.dump() << ": " << msg;
  }
}

TEST(CoefficientFile, ErrorsInAFileNameItsLineAndColumn) {
  const std::string dir = ::testing::TempDir();
  json j = neutral_file("camera");
  j["parameters"]["fov_deg"] = 360.0;
  const std::string path = dir + "/located.json";
  const std::string text = j.dump(2);
  std::ofstream(path) << text;
  // The value's position, found in the text independently: the line of "fov_deg" and the column
  // after `"fov_deg": `.
  int line = 1;
  const std::size_t at = text.find("\"fov_deg\"");
  for (std::size_t i = 0; i < at; ++i) line += text[i] == '\n';
  const std::size_t line_start = text.rfind('\n', at) + 1;
  const int column = static_cast<int>(at - line_start) + 1 + static_cast<int>(std::string("\"fov_deg\": ").size());
  try {
    (void)co::read_model_file<s::CameraModel>(path);
    FAIL() << "a field of view of 360 degrees was accepted";
  } catch (const logs::InputError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.column(), column) << e.what();
    EXPECT_NE(std::string(e.what()).find("/parameters/fov_deg"), std::string::npos) << e.what();
  }
  // A number too large for a double is located too.
  std::string huge = text;
  huge.replace(huge.find("360.0"), 5, "1e999");
  std::ofstream(path) << huge;
  try {
    (void)co::read_model_file<s::CameraModel>(path);
    FAIL() << "1e999 was accepted";
  } catch (const logs::InputError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
  }
}

TEST(CoefficientFile, NoiseWhoseSquaresOverflowRoundTrips) {
  s::ProximityModel m;
  m.noise_sd_raw = {1e200, 2e200, 1e200, 1e200, 1e200, 1e200, 1e200, 1e200};
  const json n = co::noise_json(std::vector<double>(m.noise_sd_raw.begin(), m.noise_sd_raw.end()), "counts");
  ASSERT_TRUE(n.at("sd").is_number()) << n.dump();
  // RMS by hand: sqrt((7 + 4) / 8) 1e200.
  EXPECT_NEAR(n.at("sd").get<double>() / 1e200, std::sqrt(11.0 / 8.0), 1e-12);
  EXPECT_EQ(n.at("per_sensor_sd").at(1).get<double>(), 2e200);
  EXPECT_THROW(co::noise_json({std::nan("")}, "px"), std::domain_error);
  s::CameraModel bad;
  bad.base.cx_px = std::numeric_limits<double>::infinity();
  EXPECT_THROW(co::model_to_json(bad), std::domain_error);
  EXPECT_THROW(co::model_to_cpp(bad, "x.json"), std::domain_error);
}

// ----- a new effect through codegen, simulate --like and the diagnosis --------------------------

class NewEffect : public epuck2::testing::CliTest {};

TEST_F(NewEffect, CameraDistortionK2ThroughCodegenAndSimulate) {
  s::CameraModel m;
  m.base.horizontal_fov_rad = s::deg_to_rad(30.0);
  m.base.cx_px = 81.25;
  m.base.cy_px = 58.5;
  m.distortion.k2 = 12.5;
  const std::string model = write("camera_k2.json", co::model_to_json(m).dump(2));
  // codegen: the header states k2, and a program compiled against it reads it back.
  const std::string header = (dir_ / "k2.hpp").string();
  const auto cg = run("codegen \"" + model + "\" -o \"" + header + "\"");
  ASSERT_EQ(cg.exit_code, 0) << cg.err;
  const std::string main_cpp = write("main.cpp", "#include \"" + header + "\"\n#include <cstdio>\nint main() { std::printf(\"%.17g\\n\", epuck2::fitted::camera_model().distortion.k2); }\n");
  const std::string exe = (dir_ / "k2").string();
  const std::string cmd = std::string(EPUCK2_CXX) + " -std=c++17 -I\"" + EPUCK2_SOURCE_DIR + "/lib/models/include\" -I/usr/include/eigen3 \"" +
                          main_cpp + "\" -o \"" + exe + "\" > \"" + (dir_ / "cc.txt").string() + "\" 2>&1 && \"" + exe + "\" > \"" +
                          (dir_ / "k2.txt").string() + "\"";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << epuck2::testing::slurp(dir_ / "cc.txt");
  EXPECT_EQ(std::stod(epuck2::testing::slurp(dir_ / "k2.txt")), 12.5);
  // simulate --like: the expected image position by hand (pinhole with r^4 distortion).
  const std::string log = write("cam.csv", "forward_m,lateral_m,vertical_m,px,py\n0.5,0.1,0.05,0,0\n0.4,-0.08,0.03,0,0\n");
  const std::string sim = (dir_ / "sim.csv").string();
  const auto r = run("simulate camera --like \"" + log + "\" --coefficients \"" + model + "\" -o \"" + sim + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The simulated log's px and py columns, row by row.
  std::istringstream csv(epuck2::testing::slurp(sim));
  std::string line, columns;
  while (std::getline(csv, columns) && (columns.empty() || columns[0] == '#')) {
  }
  auto cells = [](const std::string& l) {
    std::vector<std::string> c;
    std::string cell;
    std::istringstream ls(l);
    while (std::getline(ls, cell, ',')) c.push_back(cell);
    return c;
  };
  const auto names = cells(columns);
  const auto col = [&](const std::string& n) { return std::find(names.begin(), names.end(), n) - names.begin(); };
  const std::size_t cpx = static_cast<std::size_t>(col("px")), cpy = static_cast<std::size_t>(col("py"));
  ASSERT_LT(cpx, names.size()) << columns;
  const double f = 80.0 / std::tan(s::deg_to_rad(15.0));
  int rows = 0;
  for (const auto& [fw, lat, ver] : {std::array<double, 3>{0.5, 0.1, 0.05}, std::array<double, 3>{0.4, -0.08, 0.03}}) {
    ASSERT_TRUE(std::getline(csv, line));
    const auto c = cells(line);
    // The expected image position by hand: the pinhole with the r^4 term.
    const double x = lat / fw, z = ver / fw, r2 = x * x + z * z, sc = 1 + 12.5 * r2 * r2;
    const double px = 81.25 - f * x * sc, py = 58.5 - f * z * sc;
    EXPECT_LE(std::abs(std::stod(c.at(cpx)) - px), 0.5 + 1e-9) << line << " (expected px " << px << ")";
    EXPECT_LE(std::abs(std::stod(c.at(cpy)) - py), 0.5 + 1e-9) << line << " (expected py " << py << ")";
    // Without k2 the point lands more than a pixel away: the check can fail.
    EXPECT_GT(std::abs(std::stod(c.at(cpx)) - (81.25 - f * x)), 1.0) << line;
    ++rows;
  }
  EXPECT_EQ(rows, 2);
}

TEST(NewEffectDiagnosis, CameraDistortionK2IsFoundAndSized) {
  namespace gen = epuck2::testing::diagnose;
  int found = 0, sized = 0;
  const int seeds = 6;
  for (int sd = 0; sd < seeds; ++sd) {
    gen::Hidden h = gen::hidden("distortion_k2");
    const auto log = logs::parse_log(gen::make_log(logs::Kind::camera, 4242 + 17 * sd, h), "k2.csv", logs::Kind::camera);
    const auto r = diagnose::diagnose({log});
    EXPECT_NE(r.verdict_name(), "unexplained") << "seed " << sd;
    for (const auto& f : r.findings) {
      if (f.cause != "distortion_k2") continue;
      ++found;
      for (const auto& v : f.parameters)
        if (v.name == "k2" && std::abs(v.value - h.truth.at("k2")) <= 0.10 * std::abs(h.truth.at("k2"))) ++sized;
    }
  }
  EXPECT_GE(found, seeds - 1) << "distortion_k2 found in " << found << " of " << seeds << " logs";
  EXPECT_GE(sized, found - 1) << "k2 within 10 % of the truth in " << sized << " of " << found;
}

}  // namespace
}  // namespace test_coefficients_cpp
