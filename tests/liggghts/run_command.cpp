#include "run_command.h"

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>

extern char** environ;

namespace freestand::testing {

int run_command(const std::string& command) {
  const int raw = std::system(command.c_str());
  return raw == -1 ? -1 : WEXITSTATUS(raw);
}

std::string capture_command(const std::string& command, int* status) {
  std::string out;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return out;
  std::array<char, 4096> buffer;
  while (std::fgets(buffer.data(), buffer.size(), pipe)) out += buffer.data();
  const int raw = pclose(pipe);
  if (status) *status = raw == -1 ? -1 : WEXITSTATUS(raw);
  return out;
}

std::string mpirun(int processes) {
  // The test process is itself an MPI singleton; Open MPI's variables it
  // inherited would make the child mpirun join that job instead of starting
  // its own, so they are removed from the child's environment.
  std::string unset = "env";
  for (char** var = environ; *var; ++var) {
    if (std::strncmp(*var, "OMPI_", 5) && std::strncmp(*var, "PMIX_", 5) &&
        std::strncmp(*var, "OPAL_", 5))
      continue;
    unset += " -u " + std::string(*var, std::strchr(*var, '=') - *var);
  }
  // --oversubscribe: CI has 2 cores and may count fewer slots.
  return unset + " mpirun --allow-run-as-root --oversubscribe -np " + std::to_string(processes);
}

}  // namespace freestand::testing
