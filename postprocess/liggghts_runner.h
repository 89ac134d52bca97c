#ifndef FREESTAND_POST_LIGGGHTS_RUNNER_H
#define FREESTAND_POST_LIGGGHTS_RUNNER_H

// Runs freestand-lmp on an input script as a child process, the way a user
// would from a shell, and reports its progress from the thermo output.

#include <functional>
#include <string>

namespace freestand {

struct LiggghtsRun {
  std::string executable;      // freestand-lmp
  std::string directory;       // working directory of the run
  std::string script;          // input script, relative to `directory`
  std::string log = "log.liggghts";  // LIGGGHTS log, relative to `directory`
  int processes = 1;           // > 1: under mpirun
};

struct LiggghtsOutcome {
  int status = 0;              // exit status; 0 = finished
  std::string error;           // LIGGGHTS' ERROR line(s) when it failed
};

// `progress(step, total)` is called for every thermo line once the script has
// printed "freestand: steps N" (total = N).
LiggghtsOutcome run_liggghts(const LiggghtsRun& run, const std::function<void(long, long)>& progress);

// The freestand-lmp next to the running executable, else the one this tool
// was built with.
std::string default_liggghts_executable();

// Shell-quoted argument.
std::string shell_quote(const std::string& text);

}  // namespace freestand

#endif
