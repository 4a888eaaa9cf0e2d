// epuck2-fit: the command line. Exit status: 0 success; 1 data read but no usable fit; 2 bad
// usage or bad input (the message names file, line and column).
//
// Before CLI11 parses the arguments, prepare_arguments() handles what CLI11 cannot say well:
// `help [SUBCOMMAND]`, a misspelt subcommand or simulated kind (did you mean, and the list), and
// diagnose's old spelling `--json FILE` (taken as the file only when FILE is `-` or ends in .json,
// so that a log is never taken for the output).
#include <algorithm>
#include <iostream>

#include "app_support.hpp"
#include "commands.hpp"
#include "heap.hpp"
#include "epuck2/fit/solver_log.hpp"
#include "epuck2/logs/log.hpp"

#ifndef EPUCK2_VERSION
#define EPUCK2_VERSION "unknown"
#endif

namespace {

using namespace epuck2::app;

std::vector<std::string> names_of(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) names.push_back(sub->get_name());
  return names;
}

bool ends_with_json(const std::string& s) {
  if (s.size() < 5) return false;
  std::string tail = s.substr(s.size() - 5);
  std::transform(tail.begin(), tail.end(), tail.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return tail == ".json";
}

/// The subcommand named `word`, or a usage error naming the closest and listing them all.
CLI::App* subcommand(CLI::App& app, const std::string& word) {
  for (CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    if (sub->get_name() == word) return sub;
  const std::string near = closest(word, names_of(app));
  throw UsageError("unknown subcommand '" + epuck2::logs::escape_control(word) + "'" +
                   (near.empty() ? std::string() : "; did you mean '" + near + "'?") + "\nsubcommands: " + join(names_of(app)) +
                   "\n(`epuck2-fit help SUBCOMMAND` describes one)");
}

/// `simulate WORD`: WORD must name a runtime model that can be simulated.
void check_simulated_kind(CLI::App& simulate, const std::string& typed) {
  const std::string word = epuck2::logs::escape_control(typed);
  const std::vector<std::string> models = names_of(simulate);
  if (std::find(models.begin(), models.end(), word) != models.end()) return;
  const std::vector<std::string> kinds = kind_names();
  const std::string list = "; kinds that can be simulated: " + join(models);
  if (std::find(kinds.begin(), kinds.end(), word) != kinds.end())
    throw UsageError("simulate: the " + word + " model cannot be simulated yet" + list);
  std::string near = closest(word, models);
  if (!near.empty()) throw UsageError("simulate: unknown kind '" + word + "'; did you mean '" + near + "'?" + list.substr(1));
  near = closest(word, kinds);
  if (!near.empty())
    throw UsageError("simulate: unknown kind '" + word + "' (did you mean '" + near + "'? it cannot be simulated yet)" + list);
  throw UsageError("simulate: unknown kind '" + word + "'" + list);
}

/// diagnose's --json: a flag, or the spelling published first, `--json FILE` (FILE "-" or *.json).
void rewrite_diagnose_json(std::vector<std::string>& args, std::size_t from) {
  std::vector<std::string> out(args.begin(), args.begin() + static_cast<std::ptrdiff_t>(from));
  for (std::size_t i = from; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--") {  // the rest are logs
      out.insert(out.end(), args.begin() + static_cast<std::ptrdiff_t>(i), args.end());
      break;
    }
    if (a == "--json") {
      const bool has_next = i + 1 < args.size();
      const std::string next = has_next ? args[i + 1] : std::string();
      out.push_back("--json");
      if (has_next && next == "-") {
        ++i;  // `--json -`: standard output, which the flag means
      } else if (has_next && next.rfind('-', 0) != 0 && ends_with_json(next)) {
        out.back() = "--json-file=" + next;  // `--json FILE.json`: the report to FILE
        ++i;
      }
      continue;
    }
    if (a.rfind("--json=", 0) == 0) {
      const std::string value = a.substr(7);
      if (value == "-") out.push_back("--json");
      else if (ends_with_json(value)) out.push_back("--json-file=" + value);
      else
        throw UsageError("--json=" + epuck2::logs::escape_control(value) + ": the report's file must end in .json (or be - for standard output); "
                         "-o FILE writes it under any name");
      continue;
    }
    out.push_back(a);
  }
  args = std::move(out);
}

/// The arguments as CLI11 should see them (see the file's comment). Throws UsageError.
std::vector<std::string> prepare_arguments(CLI::App& app, std::vector<std::string> args) {
  if (args.empty())
    throw UsageError("a subcommand is required\nsubcommands: " + join(names_of(app)) + "\n(`epuck2-fit help` describes them)");
  if (args[0] == "help") {
    std::vector<std::string> rest(args.begin() + 1, args.end());
    if (rest.empty() || rest[0] == "help") return {"--help"};
    CLI::App* sub = subcommand(app, rest[0]);
    if (rest.size() > 1 && !sub->get_subcommands([](const CLI::App*) { return true; }).empty()) {
      check_simulated_kind(*sub, rest[1]);
      return {rest[0], rest[1], "--help"};
    }
    return {rest[0], "--help"};
  }
  if (args[0].rfind('-', 0) == 0) return args;  // --help, --version or an unknown option: CLI11's
  CLI::App* sub = subcommand(app, args[0]);
  if (sub->get_name() == "simulate") {
    const auto word = std::find_if(args.begin() + 1, args.end(), [](const std::string& a) { return a.rfind('-', 0) != 0; });
    const bool help = std::find(args.begin() + 1, args.end(), "--help") != args.end() ||
                      std::find(args.begin() + 1, args.end(), "-h") != args.end();
    if (word != args.end()) check_simulated_kind(*sub, *word);
    else if (!help)
      throw UsageError("simulate: name the kind of model to run; kinds that can be simulated: " + join(names_of(*sub)) +
                       "\n(`epuck2-fit help simulate battery` describes it)");
  }
  if (sub->get_name() == "diagnose") rewrite_diagnose_json(args, 1);
  return args;
}

/// CLI11's errors in the project's form: "error: ...", then where the options are described.
std::string failure_message(const CLI::App* app, const CLI::Error& e) {
  std::string where = "epuck2-fit";
  const CLI::App* a = app;
  for (;;) {
    const auto subs = a->get_subcommands();
    if (subs.empty()) break;
    a = subs.front();
    where += " " + a->get_name();
  }
  return "error: " + epuck2::logs::escape_control(e.what()) + "\n`" + where + " --help` lists the options.\n";
}

}  // namespace

namespace {
int run(int argc, char** argv);
}

int main(int argc, char** argv) {
  // Nothing lost in silence: whatever the command printed must have reached standard output
  // (a full disk, /dev/full, an I/O error), else exit 2 with the reason.
  epuck2::app::capture_standard_output();
  const int code = run(argc, argv);
  const std::string lost = epuck2::app::standard_output_error();
  if (lost.empty()) return code;
  std::cerr << "error: " << lost << '\n';
  return 2;
}

namespace {

int run(int argc, char** argv) {
  using namespace epuck2::app;
  // The solver's log is not for our users (fits report their own status).
  epuck2::fit::silence_solver_log(argv[0]);
  // Battery and diagnosis runs fit hundreds of times: freed memory waits for the next fit.
  epuck2::app::keep_freed_heap();
  CLI::App app{"epuck2-fit: calibrate and diagnose E-Puck2 simulation models from raw robot logs"};
  app.name("epuck2-fit");
  app.set_version_flag("--version", std::string("epuck2-fit ") + EPUCK2_VERSION);
  app.failure_message(failure_message);  // before the subcommands, which copy it
  app.require_subcommand(1);
  Action action;
  setup_battery(app, action);
  setup_table5(app, action);
  setup_codegen(app, action);
  setup_simulate(app, action);
  setup_generate(app, action);
  setup_proximity(app, action);
  setup_light(app, action);
  setup_ground(app, action);
  setup_camera(app, action);
  setup_drive(app, action);
  setup_nist(app, action);
  setup_diagnose(app, action);
  // Listed in --help; prepare_arguments() turns `help [SUBCOMMAND]` into `[SUBCOMMAND] --help`.
  app.add_subcommand("help", "Print this help, or a subcommand's: epuck2-fit help SUBCOMMAND");
  app.footer("Exit status: 0 success, 1 no usable fit, 2 bad usage or bad input. The reference: docs/cli.md.");
  std::vector<std::string> args;
  try {
    args = prepare_arguments(app, std::vector<std::string>(argv + 1, argv + argc));
  } catch (const UsageError& e) {
    std::cerr << "error: " << e.what() << '\n';  // what users typed in it is escaped
    return 2;
  }
  try {
    std::reverse(args.begin(), args.end());  // CLI11 takes them last first
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help/version or the parse error
    return code == 0 ? 0 : 2;
  }
  if (!action) return 0;
  try {
    return action();
  } catch (const epuck2::logs::InputError& e) {
    std::cerr << "error: " << e.what() << '\n';
    return 2;
  } catch (const UsageError& e) {
    // Messages may quote input (robot names, JSON keys): control characters are escaped.
    std::cerr << "error: " << epuck2::logs::escape_control(e.what()) << '\n';
    return 2;
  } catch (const NoUsableFit& e) {
    std::cerr << "error: no usable fit: " << epuck2::logs::escape_control(e.what()) << '\n';
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "error: " << epuck2::logs::escape_control(e.what()) << '\n';
    return 2;
  }
}

}  // namespace
