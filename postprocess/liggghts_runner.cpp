#include "liggghts_runner.h"

#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>

extern char** environ;

namespace freestand {

namespace fs = std::filesystem;

namespace {

// mpirun for `processes` ranks. Open MPI variables inherited from a parent
// MPI job would make the child join that job: removed. Root needs
// --allow-run-as-root; --oversubscribe lets 2 ranks run on fewer slots.
std::string mpirun(int processes) {
  std::string command = "env";
  for (char** var = environ; *var; ++var)
    if (!std::strncmp(*var, "OMPI_", 5) || !std::strncmp(*var, "PMIX_", 5) || !std::strncmp(*var, "OPAL_", 5))
      command += " -u " + std::string(*var, std::strchr(*var, '=') - *var);
  command += " mpirun --oversubscribe";
  if (geteuid() == 0) command += " --allow-run-as-root";
  return command + fmt::format(" -np {}", processes);
}

// A single rank starts as an Open MPI singleton, which by default forks a PMIx server and
// probes every transport: 0.50 s of a 20 s tower run's 2 s, idle. Isolated and on the ob1
// transport it starts in 0.11 s (docs/benchmarks.md, "Single-rank start-up"); a diagnosis
// runs hundreds. A variable the user set is kept.
std::string singleton_environment() {
  std::string command;
  for (const char* var : {"OMPI_MCA_ess_singleton_isolated=1", "OMPI_MCA_pml=ob1"}) {
    const std::string name(var, std::strchr(var, '=') - var);
    if (!std::getenv(name.c_str())) command += std::string(command.empty() ? "env " : "") + var + " ";
  }
  return command;
}

// A thermo line starts with the step number.
bool thermo_step(const std::string& line, long* step) {
  std::istringstream in(line);
  std::string first;
  in >> first;
  if (first.empty() || first.find_first_not_of("0123456789") != std::string::npos) return false;
  *step = std::stol(first);
  return true;
}

}  // namespace

std::string shell_quote(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string default_liggghts_executable() {
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  if (!error) {
    const fs::path beside = self.parent_path() / "freestand-lmp";
    if (fs::exists(beside)) return beside.string();
  }
  return FREESTAND_LMP;
}

LiggghtsOutcome run_liggghts(const LiggghtsRun& run, const std::function<void(long, long)>& progress) {
  // stdbuf: LIGGGHTS writes its screen output through C stdio, block-buffered
  // into a pipe; line buffering lets progress arrive as it happens.
  const std::string launcher = (run.processes > 1 ? mpirun(run.processes) + " " : singleton_environment()) + "stdbuf -oL ";
  const std::string command = "cd " + shell_quote(run.directory) + " && " + launcher +
                              shell_quote(run.executable) + " -in " + shell_quote(run.script) + " -log " +
                              shell_quote(run.log) + " < /dev/null 2>&1";
  LiggghtsOutcome outcome;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) {
    outcome.status = -1;
    outcome.error = "cannot start " + run.executable;
    return outcome;
  }
  std::array<char, 8192> buffer;
  long total = 0, step = 0;
  while (std::fgets(buffer.data(), buffer.size(), pipe)) {
    const std::string line(buffer.data());
    if (line.rfind("freestand: steps ", 0) == 0) total = std::stol(line.substr(17));
    else if (line.rfind("ERROR", 0) == 0) outcome.error += line;
    else if (total > 0 && thermo_step(line, &step)) progress(step, total);
  }
  const int raw = pclose(pipe);
  // A process killed by a signal has no exit status: reported as a shell would (128 + signal).
  outcome.status = raw == -1 ? -1 : WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  if (outcome.status != 0 && outcome.error.empty())
    outcome.error = fmt::format("freestand-lmp exited with status {} (see {})", outcome.status,
                                (fs::path(run.directory) / run.log).string());
  return outcome;
}

}  // namespace freestand
