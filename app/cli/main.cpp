// trainsim: the headless command-line front end. A thin shell over the modules: it parses the
// command line, runs one command and maps exceptions to exit codes (0 ok, 1 runtime failure,
// 2 invalid input or usage).

#include <CLI/CLI.hpp>

#include <iostream>

#include "commands.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/core/version.hpp"
#include "trainsim/scenario/scenario.hpp"

int main(int argc, char** argv) {
  CLI::App app{"TrainSim: railway simulation workbench for labelled multi-sensor datasets",
               "trainsim"};
  app.set_version_flag("--version", std::string(trainsim::version()));
  trainsim::cli::addCommands(app);
  if (argc > 1 && argv[1][0] != '-') {
    bool known = false;
    std::string names;
    for (const CLI::App* sub : app.get_subcommands({})) {
      known = known || sub->get_name() == argv[1];
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    if (!known) {
      std::cerr << "trainsim: unknown command '" << trainsim::messageValue(argv[1])
                << "': expected one of " << names << " (trainsim --help)\n";
      return trainsim::kExitInvalidInput;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help, or the usage error
    return code == 0 ? trainsim::kExitOk : trainsim::kExitInvalidInput;
  } catch (const trainsim::scenario::InvalidScenario& e) {
    for (const auto& problem : e.problems())  // one line each, as validate prints them
      std::cerr << "trainsim: " << e.source() << ": " << problem.text() << "\n";
    return trainsim::kExitInvalidInput;
  } catch (const trainsim::Error& e) {
    std::cerr << "trainsim: " << e.what() << "\n";
    return trainsim::exitCodeFor(e);
  } catch (const std::exception& e) {
    std::cerr << "trainsim: internal error: " << e.what() << "\n";
    return trainsim::kExitRuntime;
  }
  return trainsim::cli::commandExitCode();
}
