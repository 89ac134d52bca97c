#ifndef FREESTAND_TESTS_RUN_COMMAND_H
#define FREESTAND_TESTS_RUN_COMMAND_H

// Running freestand-lmp, liggghts and mpirun as a user would, from tests.

#include <string>

namespace freestand::testing {

// Runs a shell command; returns its exit status (-1 if it could not run).
int run_command(const std::string& command);

// Runs a shell command and returns what it printed (stdout and stderr).
std::string capture_command(const std::string& command, int* status = nullptr);

// "mpirun ... -np N" with the flags this machine needs (root, 2 cores).
std::string mpirun(int processes);

}  // namespace freestand::testing

#endif
