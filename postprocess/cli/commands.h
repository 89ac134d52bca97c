#ifndef FREESTAND_CLI_COMMANDS_H
#define FREESTAND_CLI_COMMANDS_H

// The subcommands of `freestand`, one file each (postprocess/cli/NAME_command.cpp):
// each adds itself to the application with its options and its callback.

#include <CLI/CLI.hpp>

#include "recording.h"

namespace freestand::cli {

void add_run_command(CLI::App& app);
void add_post_command(CLI::App& app);
void add_calibrate_command(CLI::App& app);
void add_tosses_command(CLI::App& app);
void add_report_command(CLI::App& app);
void add_compare_command(CLI::App& app);
void add_diagnose_command(CLI::App& app);
void add_generate_command(CLI::App& app);

// Runs a subcommand's `body` (which returns its exit status), turning
// InputError and other exceptions into one message on stderr and status 1;
// a non-zero status ends the program with it.
void guarded(const std::function<int()>& body);

// A recording's warnings (unknown fields and columns, table channels derived through a cut),
// one line each on stderr.
void print_warnings(const Recording& recording);

}  // namespace freestand::cli

#endif
