#pragma once

#include <CLI/CLI.hpp>

namespace trainsim::cli {

/// Adds the subcommands (generate, plan, validate, defaults, schema) to `app`. Each
/// subcommand's callback does the work and throws trainsim::Error on failure; main() maps
/// exceptions to exit codes.
void addCommands(CLI::App& app);

/// Exit code the command that ran asked for (validate returns 2 for an invalid scenario
/// without throwing, so that every problem is printed).
int commandExitCode();

}  // namespace trainsim::cli
