#ifndef FREESTAND_TESTS_LIGGGHTS_SESSION_H
#define FREESTAND_TESTS_LIGGGHTS_SESSION_H

// A LIGGGHTS instance with freestand's styles, driven command by command from
// a test, as freestand-lmp would run an input script.

#include <string>

namespace LAMMPS_NS { class LAMMPS; }

namespace freestand::testing {

class LiggghtsSession {
 public:
  // Screen output off; log to `log` ("none" for no log).
  explicit LiggghtsSession(const std::string& log = "none");
  ~LiggghtsSession();
  LiggghtsSession(const LiggghtsSession&) = delete;
  LiggghtsSession& operator=(const LiggghtsSession&) = delete;

  // Executes input-script text: one or more lines, with & continuations.
  void commands(const std::string& script);
  // Value of an equal-style variable (evaluated now).
  double equal(const std::string& expression);
  // Element (row, column), 1-based as in input scripts, of a compute's global array.
  double compute_array(const std::string& id, int row, int column);

  LAMMPS_NS::LAMMPS* lmp() { return lmp_; }

 private:
  LAMMPS_NS::LAMMPS* lmp_;  // owned
};

}  // namespace freestand::testing

#endif
