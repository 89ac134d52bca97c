/* freestand: fix shaketable. A shake table driven by recorded or analytic
   ground motion; see docs/fix_shaketable.md. */

#ifdef FIX_CLASS

FixStyle(shaketable,FixShakeTable)

#else

#ifndef LMP_FIX_SHAKETABLE_H
#define LMP_FIX_SHAKETABLE_H

#include <memory>

#include "fix.h"
#include "freestand/shake_table.h"

namespace LAMMPS_NS {

class FixShakeTable : public Fix {
 public:
  FixShakeTable(class LAMMPS *lmp, int narg, char **arg);
  int setmask() override;
  void init() override;
  // Global vector: ax ay az vx vy vz dx dy dz at the current time step.
  double compute_vector(int i) override;
  void write_restart(FILE *fp) override;
  void restart(char *buf) override;

  // Table state at the current time step (what contact styles must use for
  // the table plane's position and velocity).
  freestand::TableState state() const;
  // Table state at simulation time t.
  freestand::TableState state_at(double t) const;
  // Height of the table top at rest (the `plane` keyword), m.
  double plane_height() const { return plane_z_; }

 private:
  double current_time() const;

  std::unique_ptr<freestand::ShakeTable> table_;  // the motion, in motion time
  double start_ = 0.0;                            // simulation time of motion time 0 (s)
  double plane_z_ = 0.0;                          // table top height at rest (m)
};

}  // namespace LAMMPS_NS

#endif
#endif
