// epuck2-fit codegen COEFFICIENT_FILES... -o HEADER: the C++ header of fitted coefficients that
// the runtime model library compiles in (data/fitted/include/epuck2/fitted/coefficients.hpp).
// Its first lines name every source file and its FNV-1a 64-bit hash; a test regenerates it and
// fails when the committed copy differs.
#include <iostream>

#include "app_support.hpp"
#include "commands.hpp"
#include "epuck2/coefficients/codegen.hpp"
#include "epuck2/logs/output.hpp"

namespace epuck2::app {

namespace {

struct CodegenOptions {
  std::vector<std::string> inputs;
  std::string output;
};

int run_codegen(const CodegenOptions& o) {
  // The header is made, and every file validated, by the coefficient file's owner
  // (lib/coefficients codegen.hpp); here only the options and the write.
  std::vector<std::string> warnings;
  const std::string header = coefficients::header_cpp(o.inputs, o.output, &warnings);
  logs::write_file_atomically(o.output, header);
  for (const auto& w : warnings) std::cerr << "codegen: warning: " << w << '\n';
  std::cerr << "codegen: wrote " << o.output << '\n';
  return 0;
}
}  // namespace

void setup_codegen(CLI::App& app, Action& action) {
  auto o = std::make_shared<CodegenOptions>();
  CLI::App* sub = app.add_subcommand("codegen", "Write the C++ header of fitted coefficients compiled into lib/models");
  sub->add_option("files", o->inputs, "Coefficient files (JSON) written by the fitting subcommands")->required()->check(CLI::ExistingFile);
  sub->add_option("-o,--output", o->output, "The header to write (atomically; -: to standard output)")->type_name("FILE")->required()->check(output_file());
  sub->callback([o, &action] { action = [o] { return run_codegen(*o); }; });
}

}  // namespace epuck2::app
