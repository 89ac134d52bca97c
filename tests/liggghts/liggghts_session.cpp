#include "liggghts_session.h"

#include <mpi.h>

#include <sstream>
#include <vector>

#include "input.h"
#include "lammps.h"
#include "library.h"
#include "modify.h"
#include "compute.h"
#include "style_registry.h"
#include "update.h"

namespace freestand::testing {

LiggghtsSession::LiggghtsSession(const std::string& log) {
  // Screen to stderr, not "none": some LIGGGHTS 3.8 styles print to screen
  // unchecked, and a LIGGGHTS error exits the process, so its message must
  // reach the test output (ctest shows it only for failing tests).
  std::vector<std::string> args{"freestand-lmp", "-screen", "/dev/stderr", "-log", log, "-nocite"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  lmp_ = new LAMMPS_NS::LAMMPS(static_cast<int>(argv.size()), argv.data(), MPI_COMM_WORLD);
  register_freestand_styles(lmp_);
}

LiggghtsSession::~LiggghtsSession() { delete lmp_; }

void LiggghtsSession::commands(const std::string& script) {
  std::istringstream in(script);
  std::string line, pending;
  while (std::getline(in, line)) {
    const auto last = line.find_last_not_of(" \t\r");
    if (last != std::string::npos && line[last] == '&') {
      pending += line.substr(0, last) + " ";
      continue;
    }
    pending += line;
    lmp_->input->one(pending.c_str());
    pending.clear();
  }
}

double LiggghtsSession::equal(const std::string& expression) {
  commands("variable freestand_test_probe equal " + expression);
  char name[] = "freestand_test_probe";
  void* value = lammps_extract_variable(lmp_, name, nullptr);
  const double result = *static_cast<double*>(value);
  lammps_free(value);
  return result;
}

double LiggghtsSession::compute_array(const std::string& id, int row, int column) {
  const int index = lmp_->modify->find_compute(id.c_str());
  LAMMPS_NS::Compute* compute = lmp_->modify->compute[index];
  if (compute->invoked_array != lmp_->update->ntimestep) compute->compute_array();
  return compute->array[row - 1][column - 1];
}

}  // namespace freestand::testing
