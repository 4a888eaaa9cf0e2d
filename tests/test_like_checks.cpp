// The second of two like checks (bench/fresh-slips.md, round 14's survivor classes): every fit
// a sensor calibration checks for lack of fit refuses its own misfit by its own name, and only
// that fit is named. Round 14 found `proximity` checking its maxima fit twice; the drive's ToF
// and the ground's per-sensor fits were already covered (test_cli_corners, test_round_fourteen).
// Here: the light fit, the camera fit and the drive's encoder fit. Every log is made by hand from
// the paper's equations with whole-count jitter; the expected words are docs/fitting.md's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "hand_logs.hpp"

namespace test_like_checks_cpp {

namespace fs = std::filesystem;
using epuck2::testing::CliTest;
using epuck2::testing::slurp;

class LikeChecks : public CliTest {
 protected:
  std::string out(const std::string& name) const { return "\"" + (dir_ / name).string() + "\""; }
};

/// A light log by hand (paper Eq. 2): gamma 0.1 m, intensity 0.5, distances 0.10, 0.15, ...,
/// 0.50 m, 8 sensors, 6 readings each: round(4095 (1 - (0.05/d)^2)) + a jitter in {-2..2}
/// (replicate sd about 1.5 counts). At d = 0.2 m every reading is 600 counts lower when `bent`
/// (a misfit of hundreds of replicate sd); `shuffled` deals the readings across the distances.
std::string light_log(bool bent, bool shuffled) {
  const int jitter[6] = {-2, 1, 0, 2, -1, 0};
  std::vector<double> d;
  for (int i = 0; i <= 8; ++i) d.push_back(0.10 + 0.05 * i);
  std::vector<int> all;
  for (double di : d)
    for (int s = 0; s < 8; ++s)
      for (int k = 0; k < 6; ++k) all.push_back(static_cast<int>(std::lround(4095.0 * (1.0 - std::pow(0.05 / di, 2)))) + jitter[k]);
  std::ostringstream o;
  o << "# robot: hand-made\ndistance_m,intensity,sensor,value\n";
  std::size_t next = 0;
  for (std::size_t i = 0; i < d.size(); ++i)
    for (int s = 0; s < 8; ++s)
      for (int k = 0; k < 6; ++k) {
        int v = all[next];
        if (shuffled) v = all[(next * 97) % all.size()];  // 97 is prime, 432 = 2^4 3^3: a permutation
        if (bent && i == 2) v -= 600;
        ++next;
        o << d[i] << ",0.5," << s << ',' << v << '\n';
      }
  return o.str();
}

// One light fit: a reading set that misses Eq. 2 by far more than 10 replicate sd is refused
// (exit 1, nothing written) naming the light fit; --accept-misfit writes it with a warning that
// names it. The miss at d = 0.2 m is downwards: "the readings below it".
TEST_F(LikeChecks, TheLightFitRefusesItsOwnMisfit) {
  const std::string log = write("light_bent.csv", light_log(true, false));
  const auto r = run("light \"" + log + "\" -o " + out("l.json"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("light fit: the curve misses its data"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("the readings below it"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "l.json"));
  const auto a = run("light \"" + log + "\" --accept-misfit -o " + out("l.json"));
  EXPECT_EQ(a.exit_code, 0) << a.err;
  EXPECT_NE(a.err.find("light fit (accepted by --accept-misfit): the curve misses its data"), std::string::npos) << a.err;
  EXPECT_TRUE(fs::exists(dir_ / "l.json"));
}

// Readings dealt across the distances follow no distance: Eq. 2's curve, which must pass 1 at
// an infinite distance, does worse than a flat line (R^2 < 0), refused naming the light fit.
TEST_F(LikeChecks, TheLightFitRefusesAnRSquaredBelowZero) {
  const std::string log = write("light_shuffled.csv", light_log(false, true));
  const auto r = run("light \"" + log + "\" -o " + out("l.json"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  const std::size_t at = r.err.find("light fit: R^2 = ");
  ASSERT_NE(at, std::string::npos) << r.err;
  EXPECT_LT(std::stod(r.err.substr(at + 17)), 0.0) << r.err;
  EXPECT_NE(r.err.find("worse than a flat line"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "l.json"));
}

/// The hand-made camera log (hand_logs.hpp, unbent) with one wild reading: at forward 0.4 m,
/// lateral 0, vertical 0 the fourth frame (data row 3 + 45 + 15 + 5 = 68, file line 71) reads
/// 30 px more in `column` ("px" or "py").
std::string camera_log_with_wild(const std::string& column);

/// The hand-made camera log (hand_logs.hpp).
std::string camera_log(bool bent) { return epuck2::testing::hand_camera_log(bent); }

// The camera fit checks its own lack of fit: the hand log as made fits (exit 0, no word on the
// fit); bent, it misses the bent readings by about 20 px (their replicates' sd 0.84 px), "above"
// them (a larger px), and is refused naming the camera fit; written with --accept-misfit.
TEST_F(LikeChecks, TheCameraFitRefusesItsOwnMisfit) {
  const auto ok = run("camera \"" + write("camera.csv", camera_log(false)) + "\" -o " + out("c0.json"));
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_EQ(ok.err.find("camera fit"), std::string::npos) << ok.err;
  const std::string log = write("camera_bent.csv", camera_log(true));
  const auto r = run("camera \"" + log + "\" -o " + out("c.json"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("camera fit: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("the readings above it. Nothing was written"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "c.json"));
  const auto a = run("camera \"" + log + "\" --accept-misfit -o " + out("c.json"));
  EXPECT_EQ(a.exit_code, 0) << a.err;
  EXPECT_NE(a.err.find("camera fit (accepted by --accept-misfit)"), std::string::npos) << a.err;
  EXPECT_TRUE(fs::exists(dir_ / "c.json"));
}

std::string camera_log_with_wild(const std::string& column) {
  std::istringstream in(camera_log(false));
  std::ostringstream o;
  int line = 0;
  for (std::string l; std::getline(in, l);) {
    if (++line == 71) {
      const std::size_t c = l.rfind(',');
      const long px = std::stol(l.substr(l.rfind(',', c - 1) + 1)), py = std::stol(l.substr(c + 1));
      l = l.substr(0, l.rfind(',', c - 1) + 1) + std::to_string(px + (column == "px" ? 30 : 0)) + ',' +
          std::to_string(py + (column == "py" ? 30 : 0));
    }
    o << l << '\n';
  }
  return o.str();
}

// The camera's two readings are each screened: a wild px and a wild py are each left out of the
// calibration (its outliers name file line 71) and named by the diagnosis with their column.
// By hand: px at (0.4, 0, 0) is 80 + jitter {-1, 0, 1, 0, 1}, the fourth 80 + 30 = 110; the
// frames 79, 80, 81, 110, 81 centre on 81 with a median absolute deviation of 1 (robust sd
// 1.4826). py's jitter is shifted by two frames: 61, 60, 61, 59 + 30 = 89, 60, centre 61, MAD 1.
TEST_F(LikeChecks, AWildCameraReadingIsFoundInEitherColumn) {
  const std::pair<std::string, std::string> cases[] = {{"px", "px 110 where the readings under the same conditions centre on 81 (robust sd 1.4826)"},
                                                       {"py", "py 89 where the readings under the same conditions centre on 61 (robust sd 1.4826)"}};
  for (const auto& [column, words] : cases) {
    const std::string log = write("camera_wild_" + column + ".csv", camera_log_with_wild(column));
    const auto c = run("camera \"" + log + "\" -o " + out("c_" + column + ".json"));
    ASSERT_EQ(c.exit_code, 0) << column << "\n" << c.err;
    const nlohmann::json j = nlohmann::json::parse(slurp(dir_ / ("c_" + column + ".json")));
    EXPECT_EQ(j["outliers"]["rows"], nlohmann::json::array({log + ":71"})) << column << "\n" << j["outliers"].dump();
    const auto d = run("diagnose \"" + log + "\" -o " + out("d_" + column + ".json"));
    ASSERT_EQ(d.exit_code, 0) << column << "\n" << d.err;
    const nlohmann::json dj = nlohmann::json::parse(slurp(dir_ / ("d_" + column + ".json")));
    ASSERT_EQ(dj["outliers"]["count"], 1) << column << "\n" << dj["outliers"].dump();
    EXPECT_EQ(dj["outliers"]["rows"][0], log + ":71: " + words) << column;
  }
}

// The drive's encoder fit checks its own lack of fit (its ToF fit is test_cli_corners'): the
// shipped drive logs with both encoder registers replaced by a sawtooth 0, 300, ..., 1800 steps
// that does not follow the travelled distance. The encoders' line through the origin does worse
// than a flat line (R^2 < 0): refused naming the encoder fit, before the ToF fit (whose travel
// comes from the same encoders) is judged; with --accept-misfit, written with a warning naming it.
TEST_F(LikeChecks, TheDrivesEncoderFitRefusesItsOwnMisfit) {
  const std::vector<fs::path> shipped = epuck2::testing::shipped_logs("drive");
  ASSERT_GE(shipped.size(), 10u);
  fs::create_directories(dir_ / "saw");
  std::string args;
  for (const fs::path& p : shipped) {
    std::istringstream in(slurp(p));
    std::ofstream o(dir_ / "saw" / p.filename());
    bool header = false;
    int n = 0;
    for (std::string line; std::getline(in, line);) {
      if (line.empty() || line[0] == '#' || !header) {
        header = header || (!line.empty() && line[0] != '#');
        o << line << '\n';
        continue;
      }
      // time_s,left_speed_cm_s,right_speed_cm_s,left_steps,right_steps,tof_mm
      std::vector<std::string> c;
      std::istringstream cells(line);
      for (std::string x; std::getline(cells, x, ',');) c.push_back(x);
      ASSERT_EQ(c.size(), 6u) << p << ": " << line;
      const int saw = (++n % 7) * 300;
      o << c[0] << ',' << c[1] << ',' << c[2] << ',' << saw << ',' << saw << ',' << c[5] << '\n';
    }
    args += " \"" + (dir_ / "saw" / p.filename()).string() + "\"";
  }
  const auto r = run("drive" + args + " -o " + out("d.json"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  const std::size_t at = r.err.find("encoder fit: R^2 = ");
  ASSERT_NE(at, std::string::npos) << r.err;
  EXPECT_LT(std::stod(r.err.substr(at + 19)), 0.0) << r.err;
  EXPECT_NE(r.err.find("the curve does worse than a flat line through the readings' mean. Nothing was written"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "d.json"));
  const auto a = run("drive" + args + " --accept-misfit -o " + out("d.json"));
  EXPECT_EQ(a.exit_code, 0) << a.err;
  EXPECT_NE(a.err.find("encoder fit (accepted by --accept-misfit): R^2 = "), std::string::npos) << a.err;
  EXPECT_TRUE(fs::exists(dir_ / "d.json"));
}

/// The 1-based line and column of the `nth` (from 1) occurrence of `what` in `text`, plus `shift`
/// characters: an independent locator for the expected error positions.
std::string line_col(const std::string& text, const std::string& what, int nth, std::size_t shift) {
  std::size_t at = std::string::npos;
  for (int k = 0; k < nth; ++k) at = text.find(what, at == std::string::npos ? 0 : at + 1);
  if (at == std::string::npos) return "(not found)";
  at += shift;
  const std::size_t line = 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
  const std::size_t start = text.rfind('\n', at == 0 ? 0 : at - 1);
  return std::to_string(line) + ":" + std::to_string(start == std::string::npos ? at + 1 : at - start);
}

// Each of a battery file's speed tables is checked for its shape, not only the first (docs/
// coefficient-files.md: `cubic` is [d, c, b, a], finite numbers): the shipped battery file with
// speeds[3]'s cubic cut to three numbers, or its third number a string, or `speeds` an object, is
// refused by codegen (exit 2) at the place: the array's '[', the element, the object's '{'.
TEST_F(LikeChecks, EveryBatterySpeedTablesShapeIsCheckedAtItsPlace) {
  const nlohmann::json shipped = nlohmann::json::parse(slurp(fs::path(EPUCK2_SOURCE_DIR) / "data" / "fitted" / "battery.json"));
  ASSERT_GE(shipped.at("speeds").size(), 4u);
  struct Case {
    std::string name;
    nlohmann::json file;
    std::string anchor;  // where the error must point: the 4th (or 1st) occurrence of this text
    int nth;
    std::size_t shift;
    std::string words;
  };
  std::vector<Case> cases;
  nlohmann::json three = shipped;
  three["speeds"][3]["cubic"].erase(3);
  cases.push_back({"three", three, "\"cubic\": [", 4, 9, "speeds[3]: expected 'cubic' as [d, c, b, a] (at JSON path /speeds/3/cubic)"});
  nlohmann::json text = shipped;
  text["speeds"][3]["cubic"][2] = "x";
  cases.push_back({"text", text, "\"x\"", 1, 0, "speeds[3]: 'cubic' must hold finite numbers (at JSON path /speeds/3/cubic/2)"});
  nlohmann::json object = shipped;
  object["speeds"] = {{"a", 1}};
  cases.push_back({"object", object, "\"speeds\": {", 1, 10,
                   "not a battery coefficient file: expected an object with a 'speeds' array (at JSON path /speeds)"});
  for (const Case& c : cases) {
    const std::string body = c.file.dump(1);
    const std::string path = write("battery_" + c.name + ".json", body);
    const auto r = run("codegen \"" + path + "\" -o " + out("b.hpp"));
    EXPECT_EQ(r.exit_code, 2) << c.name << "\n" << r.err;
    const std::string want = path + ":" + line_col(body, c.anchor, c.nth, c.shift) + ": " + c.words;
    EXPECT_NE(r.err.find(want), std::string::npos) << c.name << ": expected \"" << want << "\" in\n" << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "b.hpp")) << c.name;
  }
}

/// docs/coefficient-files.md's `units` row of the kind's section ("### KIND (`epuck2-fit KIND -o`)"):
/// name -> unit, as the docs write it ("1" for none; a remark in parentheses after the unit left
/// out). The battery's `cubic`: [charge, charge/s, charge/s², charge/s³] become d, c, b, a.
std::map<std::string, std::string> documented_units(const std::string& kind) {
  const std::string doc = slurp(fs::path(EPUCK2_SOURCE_DIR) / "docs" / "coefficient-files.md");
  const std::size_t section = doc.find("### " + kind + " (`epuck2-fit " + kind + " -o`)");
  if (section == std::string::npos) return {};
  const std::size_t row = doc.find("| `units` | ", section);
  std::string text = doc.substr(row + 12, doc.find('\n', row) - row - 12);
  std::map<std::string, std::string> units;
  const std::size_t cubic = text.find("`cubic`: [");
  if (cubic != std::string::npos) {
    std::istringstream list(text.substr(cubic + 10, text.find(']', cubic) - cubic - 10));
    const char* names[4] = {"d", "c", "b", "a"};
    int k = 0;
    for (std::string u; k < 4 && std::getline(list, u, ',');) units[names[k++]] = u.substr(u.find_first_not_of(' '));
    return units;
  }
  std::istringstream entries(text);
  for (std::string entry; std::getline(entries, entry, ';');) {
    const std::size_t colon = entry.rfind("`: ");
    if (colon == std::string::npos) continue;
    std::string unit = entry.substr(colon + 3);
    unit = unit.substr(0, unit.find(" ("));
    unit = unit.substr(0, unit.find(" |"));
    for (std::size_t at = entry.find('`'); at < colon; at = entry.find('`', entry.find('`', at + 1) + 1)) {
      const std::size_t end = entry.find('`', at + 1);
      units[entry.substr(at + 1, end - at - 1)] = unit;
    }
  }
  return units;
}

// Text no test read against the facts was round 15's class of survivor (the battery report's unit
// of b). Every parameter line of every calibration's text report ("NAME = VALUE ± SE UNIT ...")
// carries the unit docs/coefficient-files.md gives NAME in that kind's file (a unit of 1: none
// printed); every documented parameter the report prints is checked, and at least two per kind.
TEST_F(LikeChecks, EveryReportedParameterCarriesItsDocumentedUnit) {
  const std::regex line(R"(^\s*([a-z_]+) = (\S+) ± (\S+)(.*)$)");
  for (const std::string kind : {"proximity", "light", "ground", "camera", "drive", "battery"}) {
    const std::map<std::string, std::string> units = documented_units(kind);
    ASSERT_GE(units.size(), 3u) << kind << ": no units row read from docs/coefficient-files.md";
    const auto r = run(kind + epuck2::testing::shipped_args(kind));
    ASSERT_EQ(r.exit_code, 0) << kind << "\n" << r.err;
    std::istringstream report(r.out);
    int checked = 0;
    for (std::string l; std::getline(report, l);) {
      std::smatch m;
      if (!std::regex_match(l, m, line)) continue;
      const auto documented = units.find(m[1].str());
      if (documented == units.end()) continue;
      std::string rest = m[4].str();
      std::string unit = rest.size() > 1 && rest[0] == ' ' && rest[1] != '[' && rest[1] != '(' ? rest.substr(1) : "";
      unit = unit.substr(0, unit.find(" ["));
      unit = unit.substr(0, unit.find(" ("));
      EXPECT_EQ(unit, documented->second == "1" ? "" : documented->second) << kind << ": \"" << l << "\"";
      ++checked;
    }
    EXPECT_GE(checked, 2) << kind << "'s report:\n" << r.out;
  }
}

// Round 15's codegen survivor: an input check whose absence only a missing or folder input shows,
// and the reader's own refusal stood in for it. Every file a command reads is checked alike before
// any reading (docs/cli.md: a usage error, exit 2, naming the option or argument): a missing file
// and a folder, for each subcommand's logs, codegen's files, simulate's --profile, --like and
// --coefficients, and --charge-map; nist's folder. The message is CLI11's: "NAME: File does not
// exist: PATH", "NAME: File is actually a directory: PATH".
TEST_F(LikeChecks, EveryFileACommandReadsIsCheckedBeforeAnyReading) {
  const std::string missing = (dir_ / "missing.csv").string();
  fs::create_directories(dir_ / "folder");
  const std::string folder = (dir_ / "folder").string();
  const std::string prox = epuck2::testing::shipped_logs("proximity").front().string();
  const std::string batt = epuck2::testing::shipped_logs("battery").front().string();
  // (command with PATH where the input goes, the name CLI11 gives the input)
  const std::vector<std::pair<std::string, std::string>> inputs{
      {"proximity PATH", "logs"},
      {"light PATH", "logs"},
      {"ground PATH", "logs"},
      {"camera PATH", "logs"},
      {"drive PATH", "logs"},
      {"battery PATH", "logs"},
      {"table5 PATH", "logs"},
      {"diagnose PATH", "logs"},
      {"codegen PATH -o OUT", "files"},
      {"simulate battery --profile PATH", "--profile"},
      {"simulate battery --like PATH", "--like"},
      {"simulate proximity --like PATH", "--like"},
      {"simulate drive --like \"" + prox + "\" --coefficients PATH", "--coefficients"},
      {"battery --charge-map PATH \"" + batt + "\"", "--charge-map"},
      {"table5 --charge-map PATH \"" + batt + "\"", "--charge-map"}};
  for (const auto& [command, name] : inputs)
    for (const auto& [path, words] : std::vector<std::pair<std::string, std::string>>{
             {missing, "File does not exist: "}, {folder, "File is actually a directory: "}}) {
      std::string cmd = command;
      cmd.replace(cmd.find("PATH"), 4, "\"" + path + "\"");
      if (cmd.find("OUT") != std::string::npos) cmd.replace(cmd.find("OUT"), 3, out("o.hpp"));
      const auto r = run(cmd);
      EXPECT_EQ(r.exit_code, 2) << cmd << "\n" << r.err;
      EXPECT_NE(r.err.find("error: " + name + ": " + words + path), std::string::npos) << cmd << "\n" << r.err;
    }
  const auto nist = run("nist " + out("no_such_folder"));
  EXPECT_EQ(nist.exit_code, 2) << nist.err;
  EXPECT_NE(nist.err.find("error: dir: Directory does not exist: "), std::string::npos) << nist.err;
  EXPECT_FALSE(fs::exists(dir_ / "o.hpp"));
}

}  // namespace test_like_checks_cpp
