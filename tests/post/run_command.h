#ifndef FREESTAND_TESTS_POST_RUN_COMMAND_H
#define FREESTAND_TESTS_POST_RUN_COMMAND_H

// Runs a shell command as a user would (the `freestand` tool): its exit
// status, and what it printed on stdout and stderr appended to *output.

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace freestand::test {

inline int run(const std::string& command, std::string* output) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  std::array<char, 4096> buffer;
  while (std::fgets(buffer.data(), buffer.size(), pipe)) *output += buffer.data();
  const int status = pclose(pipe);
  return WEXITSTATUS(status);
}

}  // namespace freestand::test

#endif
