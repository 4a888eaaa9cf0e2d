// The classes of round 9's survivors (bench/fresh-slips.md, "Round 9"), closed where they still
// held, against values read from the docs or worked by hand:
// - every number a coefficient file's reader reads, in every set of the file (the pooled one and
//   each robot's), has its documented range tried on both edges -- and the list of numbers is the
//   file's own, walked, so that a number the docs' table forgets fails here (round 9: the camera's
//   range_m 0 was read; round 8: ARGoS ignored it);
// - every base parameter of a calibrated file reaches the diagnosis's base as it reaches
//   `simulate --like` (round 9: the camera's principal offset taken about the wrong half-size);
// - a quantity documented as "its magnitude is used" gives the same result negated (round 9: a
//   profile's negative speed).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "epuck2/coefficients/model_file.hpp"

namespace test_classes_ten_cpp {
namespace {

namespace fs = std::filesystem;
namespace ec = epuck2::coefficients;
using nlohmann::json;

std::string c10_read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void c10_write(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

fs::path c10_scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("epuck2_c10_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// The CLI's exit status, its standard output in `out`.
int c10_run(const std::string& args, const fs::path& out) {
  const std::string cmd = std::string("'") + EPUCK2_FIT_EXE + "' " + args + " > '" + out.string() + "' 2>'" + out.string() + ".err'";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

json c10_fitted(const std::string& kind) {
  return json::parse(c10_read(fs::path(EPUCK2_SOURCE_DIR) / "data/fitted" / (kind + ".json")));
}

/// The reader's refusal of `j` as a `kind` file, "" when it reads every set.
std::string c10_refusal(const std::string& kind, const json& j) {
  try {
    (void)ec::model_from_json(kind, j, "edge.json");
    for (const std::string& r : ec::robot_ids(j)) (void)ec::model_from_json(kind, j, "edge.json", r);
    return "";
  } catch (const std::exception& e) {
    return e.what()[0] ? e.what() : "refused";
  }
}

// ----- every number a reader reads, on both edges of its documented range ------------------------

/// A documented range of one number of a coefficient file (docs/coefficient-files.md, "Validation:
/// one for every reader" and "Battery tables"). `exact`: the only value read (the image's size).
struct DocRange {
  double lo, hi;
  bool lo_open, hi_open;
  bool exact = false;
};

/// The number's place with array indices and robot names made generic: "parameters/gain/#",
/// "robots/*/noise/ground/per_sensor_sd/#".
std::string c10_generic(const std::string& pointer) {
  std::string out;
  std::stringstream s(pointer.substr(1));
  bool robot_next = false;
  for (std::string token; std::getline(s, token, '/');) {
    const bool index = !token.empty() && token.find_first_not_of("0123456789") == std::string::npos;
    out += (out.empty() ? "" : "/") + (robot_next ? std::string("*") : index ? std::string("#") : token);
    robot_next = token == "robots" && out == "robots";
  }
  return out;
}

/// The sections a reader reads (docs/coefficient-files.md, "Unknown keys", column "read"); the
/// informational keys beside them (`from`, `n`, `groups`, `per_sensor_n`, `argos_uniform_level`,
/// a per_sensor entry's `std_error`, ...) are not.
bool c10_is_read(const std::string& generic) {
  static const std::set<std::string> informational = {"from", "n", "groups", "per_sensor_n", "argos_uniform_level", "unit",
                                                      "std_error", "mse", "usable", "why", "rounded", "fit", "std_error_why"};
  std::vector<std::string> t;
  std::stringstream s(generic);
  for (std::string x; std::getline(s, x, '/');) t.push_back(x);
  std::size_t i = 0;
  if (t.size() > 2 && t[0] == "robots") i = 2;  // a robot's set: its parameters, noise, per_sensor
  if (i >= t.size()) return false;
  const std::string& section = t[i];
  if (section != "parameters" && section != "noise" && section != "per_sensor") return false;
  for (const std::string& x : t)
    if (informational.count(x)) return false;
  return true;
}

void c10_leaves(const json& j, const std::string& at, std::vector<std::string>& out) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) c10_leaves(it.value(), at + "/" + it.key(), out);
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) c10_leaves(j[i], at + "/" + std::to_string(i), out);
  } else if (j.is_number()) {
    out.push_back(at);
  }
}

/// The camera's aperture follows its field of view (docs: atan(tan(fov/2) 200/160)).
double c10_aperture_deg(double fov_deg) { return std::atan(std::tan(fov_deg / 2 * M_PI / 180) * 200.0 / 160.0) * 180 / M_PI; }

TEST(ClassesTenModelFile, EveryNumberAReaderReadsIsTriedOnBothEdgesOfItsDocumentedRange) {
  const double inf = HUGE_VAL;
  // docs/coefficient-files.md, word for word where it gives a range:
  //   proximity |a| <= 1e6 /m^2, |b| <= 1e5 /m, |c| <= 100, range_m in (0, 1] m (the curve of the
  //   means, mean_a/b/c, in the same ranges); light gamma in (0, 10] m (a per_sensor gamma too,
  //   its sensor 0 to 7); ground gain in (0, 4092] and offset in [-1023, 1023] counts; camera
  //   fov_deg in (0, 180), cx_px in [0, 160], cy_px in [0, 120], range_m in (0, 10] m, width_px
  //   and height_px the E-Puck2's 160 and 120; drive steps_per_m within +-20 % of 7763.656,
  //   tof_scale in [0.5, 2]; a noise sd in [0, its channel's full scale): 4095 counts for
  //   proximity and light, 1023 for ground, 160 px, 2000 mm, 65536 steps.
  // The light's range_m, a constant of the plug-in (0.5 m), is read in (0, 10] m (kind_facts.hpp;
  // the docs' list gains it with this test). The drive's tof_offset_mm and slip_time_constant_s
  // are effects whose home is `parameters`: their ranges are the registry's, tried on both edges
  // by SlipClassesBoundaries.EveryEffectParameterOnBothEdgesOfItsClosedRange; listed here so that
  // the walk below knows them.
  const std::map<std::string, std::map<std::string, DocRange>> ranges = {
      {"proximity",
       {{"parameters/a", {-1e6, 1e6, false, false}}, {"parameters/b", {-1e5, 1e5, false, false}},
        {"parameters/c", {-100, 100, false, false}}, {"parameters/mean_a", {-1e6, 1e6, false, false}},
        {"parameters/mean_b", {-1e5, 1e5, false, false}}, {"parameters/mean_c", {-100, 100, false, false}},
        {"parameters/range_m", {0, 1, true, false}}, {"noise/proximity/sd", {0, 4095, false, true}},
        {"noise/proximity/per_sensor_sd/#", {0, 4095, false, true}}}},
      {"light",
       {{"parameters/gamma", {0, 10, true, false}}, {"parameters/range_m", {0, 10, true, false}},
        {"per_sensor/#/gamma", {0, 10, true, false}}, {"per_sensor/#/sensor", {0, 7, false, false}},
        {"noise/light/sd", {0, 4095, false, true}}, {"noise/light/per_sensor_sd/#", {0, 4095, false, true}}}},
      {"ground",
       {{"parameters/gain/#", {0, 4092, true, false}}, {"parameters/offset/#", {-1023, 1023, false, false}},
        {"noise/ground/sd", {0, 1023, false, true}}, {"noise/ground/per_sensor_sd/#", {0, 1023, false, true}}}},
      {"camera",
       {{"parameters/fov_deg", {0, 180, true, true}}, {"parameters/cx_px", {0, 160, false, false}},
        {"parameters/cy_px", {0, 120, false, false}}, {"parameters/range_m", {0, 10, true, false}},
        {"parameters/width_px", {160, 160, false, false, true}}, {"parameters/height_px", {120, 120, false, false, true}},
        {"parameters/aperture_deg", {0, 0, false, false}},  // follows fov_deg: tried below
        {"noise/camera/sd", {0, 160, false, true}}}},
      {"drive",
       {{"parameters/steps_per_m", {0.8 * 7763.656, 1.2 * 7763.656, false, false}},
        {"parameters/tof_scale", {0.5, 2, false, false}},
        {"parameters/tof_offset_mm", {-inf, inf, false, false}},         // the registry's (above)
        {"parameters/slip_time_constant_s", {-inf, inf, false, false}},  // the registry's (above)
        {"noise/tof/sd", {0, 2000, false, true}}, {"noise/encoder/sd", {0, 65536, false, true}}}},
  };
  int tried = 0;
  for (const auto& [kind, table] : ranges) {
    const json file = c10_fitted(kind);
    ASSERT_EQ(c10_refusal(kind, file), "") << kind;
    ASSERT_FALSE(ec::robot_ids(file).empty()) << kind << ": the shipped file has no robot sets to try";
    std::vector<std::string> leaves;
    c10_leaves(file, "", leaves);
    std::set<std::string> seen;
    for (const std::string& pointer : leaves) {
      const std::string generic = c10_generic(pointer);
      if (!c10_is_read(generic)) continue;
      const std::string key = generic.rfind("robots/*/", 0) == 0 ? generic.substr(9) : generic;
      const auto r = table.find(key);
      ASSERT_NE(r, table.end()) << kind << " " << pointer << ": a number every reader reads, with no documented range in this test";
      seen.insert(key);
      const DocRange& d = r->second;
      if (!std::isfinite(d.lo) || key == "parameters/aperture_deg") continue;
      // Both edges and the next doubles beyond; an open edge is refused, the next double inside read.
      std::vector<std::pair<double, bool>> cases;
      if (d.exact) {
        cases = {{d.lo, true}, {d.lo + 1, false}, {d.lo - 1, false}};
      } else if (key == "parameters/steps_per_m") {
        cases = {{d.lo * (1 + 1e-9), true}, {d.hi * (1 - 1e-9), true}, {d.lo * (1 - 1e-6), false}, {d.hi * (1 + 1e-6), false}};
      } else {
        cases = {{d.lo_open ? std::nextafter(d.lo, inf) : d.lo, true}, {d.hi_open ? std::nextafter(d.hi, -inf) : d.hi, true},
                 {d.lo_open ? d.lo : std::nextafter(d.lo, -inf), false}, {d.hi_open ? d.hi : std::nextafter(d.hi, inf), false}};
        if (key == "per_sensor/#/sensor") cases.push_back({3.5, false});  // a sensor's number is whole
      }
      for (const auto& [value, read] : cases) {
        json j = file;
        j[json::json_pointer(pointer)] = value;
        if (key == "parameters/fov_deg")  // the aperture follows (docs), so that the fov alone is tried
          j[json::json_pointer(pointer.substr(0, pointer.rfind('/')) + "/aperture_deg")] = c10_aperture_deg(value);
        if (key == "per_sensor/#/sensor") {
          // One entry per sensor: an other entry naming the sensor tried takes this one's old number.
          const std::string entry = pointer.substr(0, pointer.rfind('/'));
          const std::string list = entry.substr(0, entry.rfind('/'));
          const std::size_t me = std::stoul(entry.substr(entry.rfind('/') + 1));
          const json old = file[json::json_pointer(pointer)];
          json& entries = j[json::json_pointer(list)];
          for (std::size_t i = 0; i < entries.size(); ++i)
            if (i != me && entries[i].contains("sensor") && entries[i]["sensor"].get<double>() == value) entries[i]["sensor"] = old;
        }
        const std::string why = c10_refusal(kind, j);
        EXPECT_EQ(why.empty(), read) << kind << " " << pointer << " = " << value << ": " << (why.empty() ? "read" : why);
        if (!read && !why.empty()) {
          EXPECT_NE(why.find(pointer), std::string::npos) << kind << " " << pointer << ": the refusal does not say where: " << why;
        }
        ++tried;
      }
    }
    // The camera's aperture: the one that follows fov_deg is read (the shipped file's), one 1e-3 deg
    // off it is refused; a field of view moved with its aperture is read.
    if (kind == "camera") {
      json j = file;
      const double fov = j["parameters"]["fov_deg"].get<double>();
      EXPECT_NEAR(j["parameters"]["aperture_deg"].get<double>(), c10_aperture_deg(fov), 1e-6);
      j["parameters"]["aperture_deg"] = c10_aperture_deg(fov) + 1e-3;
      EXPECT_NE(c10_refusal(kind, j).find("aperture_deg"), std::string::npos);
      j["parameters"]["fov_deg"] = 40.0;
      j["parameters"]["aperture_deg"] = c10_aperture_deg(40.0);
      EXPECT_EQ(c10_refusal(kind, j), "");
    }
    // Every number of the table is in the shipped file (else the table tries nothing).
    for (const auto& [key, d] : table) EXPECT_TRUE(seen.count(key)) << kind << " " << key << " is not in data/fitted/" << kind << ".json";
  }
  EXPECT_GE(tried, 200);
}


// ----- every base parameter of a file reaches the diagnosis's base as it reaches simulate --------

/// Each kind's shipped calibration with every base parameter moved well off its value (inside its
/// range), the robots' own sets left out (so that every reader takes the one set moved): a log
/// simulated from it without noise (`simulate --like`) is predicted by `diagnose --coefficients`
/// with the same file to within rounding -- its base MSE (`heldout_mse_plugin`, docs/diagnose.md:
/// "the given base model's") -- and by the plug-in's published model far worse. A parameter the
/// diagnosis took from elsewhere (another key, the plug-in's value, the image's other half-size)
/// leaves an error of the size it was moved by.
struct MovedFile {
  const char* kind;
  const char* log;  ///< under data/raw/
  std::function<void(json&)> move;
  double exact_below;  ///< a base MSE within rounding of the simulated log's printed readings
};

TEST(ClassesTenDiagnoseBase, EveryBaseParameterOfTheFileIsTheDiagnosissBase) {
  const std::vector<MovedFile> files = {
      {"proximity", "proximity/proximity_virtual-epuck2-1.csv",
       [](json& j) {
         json& p = j["parameters"];
         p["a"] = p["a"].get<double>() * 1.3;
         p["b"] = p["b"].get<double>() * 0.8;
         p["c"] = p["c"].get<double>() * 1.1;
         p["mean_a"] = p["a"];
         p["mean_b"] = p["b"];
         p["mean_c"] = p["c"];
       },
       1.0},
      {"light", "light/light_intensity_1.00.csv",
       [](json& j) {
         j["parameters"]["gamma"] = j["parameters"]["gamma"].get<double>() * 1.4;
         for (json& e : j["per_sensor"])
           if (e.contains("gamma")) e["gamma"] = e["gamma"].get<double>() * 1.2;
       },
       1.0},
      {"ground", "ground/ground_virtual-epuck2-1.csv",
       [](json& j) {
         json& p = j["parameters"];
         const double gain[3] = {1.1, 0.9, 1.05}, offset[3] = {10, -15, 20};
         for (int i = 0; i < 3; ++i) {
           p["gain"][i] = p["gain"][i].get<double>() * gain[i];
           p["offset"][i] = p["offset"][i].get<double>() + offset[i];
         }
       },
       1.0},
      {"camera", "camera/camera_virtual-epuck2-1.csv",
       [](json& j) {
         json& p = j["parameters"];
         p["fov_deg"] = 36.0;
         p["aperture_deg"] = c10_aperture_deg(36.0);
         p["cx_px"] = 74.0;
         p["cy_px"] = 66.0;
       },
       0.01},
      {"drive", "drive/drive_toward_10.0_cm_s.csv",
       [](json& j) {
         json& p = j["parameters"];
         p["steps_per_m"] = 7763.656 * 1.1;
         p["tof_scale"] = 1.04;
         p["tof_offset_mm"] = 15.0;
         p["slip_time_constant_s"] = 0.2;
       },
       1.0},
  };
  for (const MovedFile& f : files) {
    SCOPED_TRACE(f.kind);
    const fs::path d = c10_scratch(std::string("base_") + f.kind);
    json j = c10_fitted(f.kind);
    j.erase("robots");
    f.move(j);
    ASSERT_EQ(c10_refusal(f.kind, j), "");
    c10_write(d / "moved.json", j.dump(2));
    const std::string log = (fs::path(EPUCK2_SOURCE_DIR) / "data/raw" / f.log).string();
    ASSERT_EQ(c10_run(std::string("simulate ") + f.kind + " --like '" + log + "' --coefficients '" + (d / "moved.json").string() + "' -o '" +
                          (d / "sim.csv").string() + "'",
                      d / "sim.out"),
              0)
        << c10_read(d / "sim.out.err");
    ASSERT_EQ(c10_run("diagnose '" + (d / "sim.csv").string() + "' --coefficients '" + (d / "moved.json").string() + "' --json", d / "own.json"), 0)
        << c10_read(d / "own.json.err");
    ASSERT_EQ(c10_run("diagnose '" + (d / "sim.csv").string() + "' --json", d / "plugin.json"), 0) << c10_read(d / "plugin.json.err");
    const json own = json::parse(c10_read(d / "own.json")), plugin = json::parse(c10_read(d / "plugin.json"));
    const double mse_own = own.at("heldout_mse_plugin").get<double>(), mse_plugin = plugin.at("heldout_mse_plugin").get<double>();
    EXPECT_LT(mse_own, f.exact_below) << "the file's own base does not predict what simulate --like wrote from it";
    EXPECT_GT(mse_plugin, 20 * f.exact_below) << "the moved file is not far enough from the plug-in's to tell";
    fs::remove_all(d);
  }
}

// ----- magnitudes by sign -------------------------------------------------------------------------

/// docs/logs.md, battery: `speed_cm_s` is "commanded wheel speed; its magnitude is used". A run
/// logged with its speeds negated (the robot spinning the other way) gives the same calibration:
/// the battery fit, its diagnosis and `simulate battery --like` are those of the run as logged.
TEST(ClassesTenSigns, ABatteryRunLoggedBackwardsIsTheSameRun) {
  const fs::path d = c10_scratch("signs");
  std::vector<std::string> forward, backward;
  for (const char* name : {"robot-a_speed-00.csv", "robot-a_speed-05.csv", "robot-a_speed-10.csv"}) {
    const fs::path src = fs::path(EPUCK2_SOURCE_DIR) / "data/raw/battery" / name;
    std::istringstream in(c10_read(src));
    std::string out, line;
    int col = -1;
    while (std::getline(in, line)) {
      if (!line.empty() && line[0] == '#') {
        out += line + "\n";
        continue;
      }
      std::vector<std::string> cells;
      std::stringstream r(line);
      for (std::string c; std::getline(r, c, ',');) cells.push_back(c);
      if (col < 0) {
        for (std::size_t k = 0; k < cells.size(); ++k)
          if (cells[k] == "speed_cm_s") col = static_cast<int>(k);
        ASSERT_GE(col, 0) << name;
      } else {
        std::string& v = cells[static_cast<std::size_t>(col)];
        if (std::stod(v) != 0) v = v[0] == '-' ? v.substr(1) : "-" + v;
      }
      for (std::size_t k = 0; k < cells.size(); ++k) out += (k ? "," : "") + cells[k];
      out += "\n";
    }
    const fs::path back = d / (std::string("back_") + name);
    c10_write(back, out);
    forward.push_back(src.string());
    backward.push_back(back.string());
  }
  auto args = [](const std::vector<std::string>& files) {
    std::string a;
    for (const std::string& f : files) a += " '" + f + "'";
    return a;
  };
  // The fits: every coefficient the same (the sources' names aside).
  ASSERT_EQ(c10_run("battery" + args(forward) + " --json", d / "fwd.json"), 0) << c10_read(d / "fwd.json.err");
  ASSERT_EQ(c10_run("battery" + args(backward) + " --json", d / "bwd.json"), 0) << c10_read(d / "bwd.json.err");
  json fwd = json::parse(c10_read(d / "fwd.json")), bwd = json::parse(c10_read(d / "bwd.json"));
  ASSERT_TRUE(fwd.contains("speeds")) << fwd.dump().substr(0, 400);
  ASSERT_EQ(fwd["speeds"].size(), 3u);
  ASSERT_EQ(bwd["speeds"].size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(fwd["speeds"][i]["speed_cm_s"], bwd["speeds"][i]["speed_cm_s"]);
    EXPECT_EQ(fwd["speeds"][i]["lifetime_s"], bwd["speeds"][i]["lifetime_s"]);
    EXPECT_EQ(fwd["speeds"][i]["cubic"], bwd["speeds"][i]["cubic"]);
    EXPECT_EQ(fwd["speeds"][i]["linear_slope"], bwd["speeds"][i]["linear_slope"]);
  }
  EXPECT_EQ(fwd["simple"], bwd["simple"]);
  // The diagnosis: the same base error and the same findings.
  ASSERT_EQ(c10_run("diagnose" + args(forward) + " --json", d / "dfwd.json"), 0) << c10_read(d / "dfwd.json.err");
  ASSERT_EQ(c10_run("diagnose" + args(backward) + " --json", d / "dbwd.json"), 0) << c10_read(d / "dbwd.json.err");
  const json dfwd = json::parse(c10_read(d / "dfwd.json")), dbwd = json::parse(c10_read(d / "dbwd.json"));
  EXPECT_EQ(dfwd.at("heldout_mse_plugin"), dbwd.at("heldout_mse_plugin"));
  EXPECT_EQ(dfwd.at("findings").size(), dbwd.at("findings").size());
  // simulate --like: the same charges, row for row.
  ASSERT_EQ(c10_run("simulate battery --like '" + forward[1] + "' -o '" + (d / "sf.csv").string() + "'", d / "sf.out"), 0);
  ASSERT_EQ(c10_run("simulate battery --like '" + backward[1] + "' -o '" + (d / "sb.csv").string() + "'", d / "sb.out"), 0);
  std::istringstream sf(c10_read(d / "sf.csv")), sb(c10_read(d / "sb.csv"));
  int rows = 0;
  for (std::string a, b; std::getline(sf, a) && std::getline(sb, b);) {
    if (a.empty() || a[0] == '#' || a.rfind("time_s", 0) == 0) continue;
    // the charge is the last column; the speed column keeps the log's sign
    EXPECT_EQ(a.substr(a.rfind(',')), b.substr(b.rfind(','))) << a << " | " << b;
    ++rows;
  }
  EXPECT_GT(rows, 100);
  fs::remove_all(d);
}

}  // namespace
}  // namespace test_classes_ten_cpp
