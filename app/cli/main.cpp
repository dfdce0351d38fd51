// trainsim: the headless command-line front end. A thin shell over the modules: it parses the
// command line, runs one command and maps exceptions to exit codes (0 ok, 1 runtime failure,
// 2 invalid input or usage).

#include <CLI/CLI.hpp>

#include <iostream>

#include "commands.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/core/version.hpp"

int main(int argc, char** argv) {
  CLI::App app{"TrainSim: railway simulation workbench for labelled multi-sensor datasets",
               "trainsim"};
  app.set_version_flag("--version", std::string(trainsim::version()));
  trainsim::cli::addCommands(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help, or the usage error
    return code == 0 ? trainsim::kExitOk : trainsim::kExitInvalidInput;
  } catch (const trainsim::Error& e) {
    std::cerr << "trainsim: " << e.what() << "\n";
    return trainsim::exitCodeFor(e);
  } catch (const std::exception& e) {
    std::cerr << "trainsim: internal error: " << e.what() << "\n";
    return trainsim::kExitRuntime;
  }
  return trainsim::cli::commandExitCode();
}
