/* freestand: fix shaketable. A shake table driven by recorded or analytic
   ground motion; see docs/fix_shaketable.md. */

#ifdef FIX_CLASS

FixStyle(shaketable,FixShakeTable)

#else

#ifndef LMP_FIX_SHAKETABLE_H
#define LMP_FIX_SHAKETABLE_H

#include <memory>

#include "fix.h"
#include "lmptype.h"
#include "freestand/shake_table.h"

namespace LAMMPS_NS {

class FixShakeTable : public Fix {
 public:
  FixShakeTable(class LAMMPS *lmp, int narg, char **arg);
  int setmask() override;
  // Global vector at the current time step: ax ay az vx vy vz dx dy dz, roll
  // and pitch (rad), angular velocity wx wy wz (rad/s, world).
  double compute_vector(int i) override;
  void write_restart(FILE *fp) override;
  void restart(char *buf) override;
  void reset_dt() override;
  void reset_timestep(bigint newstep) override;

  // Table state at the current time step (what contact styles must use for
  // the table plane's position and velocity).
  freestand::TableState state() const;
  // Seconds since the motion's time 0 (negative before `start`).
  double motion_time() const;
  // Height of the table top at rest (the `plane` keyword), m: the table
  // rotates about the point (0, 0, plane_height) moved with it.
  double plane_height() const { return plane_z_; }
  bool rotates() const { return table_->rotates(); }

 private:
  std::unique_ptr<freestand::ShakeTable> table_;  // the motion, in motion time
  bigint anchor_step_ = 0;                        // a time step at which ...
  double anchor_time_ = 0.0;                      // ... the motion time was this (s)
  double dt_ = 0.0;                               // time step since the anchor (s)
  double plane_z_ = 0.0;                          // table top height at rest (m)
};

}  // namespace LAMMPS_NS

#endif
#endif
