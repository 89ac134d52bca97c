#include "liggghts_runner.h"

#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <sstream>

extern char** environ;

namespace freestand {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kLastLines = 8;  // output lines kept for the message of a run that failed without an ERROR

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
// probes every transport: 0.46 s of a profile point's 1.55 s, idle. Isolated and on the ob1
// transport it starts in 0.09 s (docs/benchmarks.md, "Single-rank start-up"); a diagnosis
// runs hundreds. Isolated singletons all take job family 0, so side by side they race to make
// and remove the same session directory under /tmp (3 of 900 quick starts failed, 10 at a
// time): each gets its own, in its run's directory. A variable the user set is kept.
std::string singleton_environment(const std::string& directory) {
  std::error_code error;
  const fs::path absolute = fs::absolute(directory, error);
  const std::string session = error ? directory : absolute.string();
  std::string command;
  for (const auto& [name, value] : {std::pair<std::string, std::string>{"OMPI_MCA_ess_singleton_isolated", "1"},
                                    {"OMPI_MCA_pml", "ob1"},
                                    {"OMPI_MCA_orte_tmpdir_base", session}})
    if (!std::getenv(name.c_str())) command += (command.empty() ? "env " : "") + name + "=" + shell_quote(value) + " ";
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
  const std::string launcher =
      (run.processes > 1 ? mpirun(run.processes) + " " : singleton_environment(run.directory)) + "stdbuf -oL ";
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
  std::deque<std::string> last;  // the output's last lines: what a start-up failure (MPI) printed
  while (std::fgets(buffer.data(), buffer.size(), pipe)) {
    const std::string line(buffer.data());
    if (line.rfind("freestand: steps ", 0) == 0) total = std::stol(line.substr(17));
    else if (line.rfind("ERROR", 0) == 0) outcome.error += line;
    else if (total > 0 && thermo_step(line, &step)) progress(step, total);
    last.push_back(line);
    if (last.size() > kLastLines) last.pop_front();
  }
  const int raw = pclose(pipe);
  // A process killed by a signal has no exit status: reported as a shell would (128 + signal).
  outcome.status = raw == -1 ? -1 : WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  if (outcome.status != 0 && outcome.error.empty())
    outcome.error = fmt::format("freestand-lmp exited with status {} (see {}); its last output:\n{}", outcome.status,
                                (fs::path(run.directory) / run.log).string(), fmt::join(last, ""));
  return outcome;
}

}  // namespace freestand
