// fix shaketable: thin LIGGGHTS adapter over freestand::ShakeTable.

#include "fix_shaketable.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "comm.h"
#include "error.h"
#include "style_args.h"
#include "freestand/input_error.h"
#include "update.h"

using namespace LAMMPS_NS;

namespace {

// Splits off the `plane Z` keyword, which belongs to the LIGGGHTS side (the
// table plane seen by contact styles), from the motion arguments.
std::vector<std::string> motion_args(int narg, char **arg, double &plane_z, Error *error) {
  std::vector<std::string> args;
  for (int i = 3; i < narg; ++i) {
    if (!std::strcmp(arg[i], "plane")) {
      if (i + 1 >= narg) error->all(FLERR, "fix shaketable: 'plane' needs a height in m");
      plane_z = freestand::parse_number(error, "fix shaketable", "plane", arg[++i]);
    } else {
      args.emplace_back(arg[i]);
    }
  }
  return args;
}

}  // namespace

FixShakeTable::FixShakeTable(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg) {
  vector_flag = 1;
  size_vector = 14;
  global_freq = 1;
  extvector = 0;
  restart_global = 1;
  time_depend = 1;

  try {
    const freestand::ShakeTableSpec spec =
        freestand::parse_shake_table_args(motion_args(narg, arg, plane_z_, error));
    table_ = std::make_unique<freestand::ShakeTable>(spec);
    anchor_step_ = update->ntimestep;
    anchor_time_ = -spec.start;
    dt_ = update->dt;
  } catch (const freestand::InputError &e) {
    error->all(FLERR, e.what());
  }
  if (comm->me == 0) {
    for (const std::string &line : table_->describe()) {
      if (screen) fprintf(screen, "fix shaketable %s: %s\n", id, line.c_str());
      if (logfile) fprintf(logfile, "fix shaketable %s: %s\n", id, line.c_str());
    }
  }
}

// No per-step work: the table state is evaluated when asked for.
int FixShakeTable::setmask() { return 0; }


// Motion time is counted in steps from an anchor, not read from LIGGGHTS'
// simulation time, which 3.8 does not carry through restart files.
double FixShakeTable::motion_time() const {
  return anchor_time_ + (update->ntimestep - anchor_step_) * dt_;
}

// The `timestep` command and fix dt/reset call this after changing dt; the
// steps since the anchor were taken with the old dt, kept in dt_.
void FixShakeTable::reset_dt() {
  anchor_time_ = motion_time();
  anchor_step_ = update->ntimestep;
  dt_ = update->dt;
}

// `reset_timestep` renumbers steps without moving time.
void FixShakeTable::reset_timestep(bigint newstep) {
  anchor_step_ += newstep - update->ntimestep;
}

freestand::TableState FixShakeTable::state() const { return table_->at(motion_time()); }

double FixShakeTable::compute_vector(int i) {
  const freestand::TableState s = state();
  if (i < 3) return s.acceleration[i];
  if (i < 6) return s.velocity[i - 3];
  if (i < 9) return s.displacement[i - 6];
  if (i == 9) return s.roll;
  if (i == 10) return s.pitch;
  return s.angular_velocity[i - 11];
}

void FixShakeTable::write_restart(FILE *fp) {
  if (comm->me != 0) return;
  // The anchor and the steps since it, not the simulation time: LIGGGHTS 3.8
  // does not keep that in restart files (it restarts from 0), and the
  // restarted run then computes the motion time with the same arithmetic as
  // the uninterrupted one (bit for bit, not just to round-off).
  const double list[2] = {anchor_time_, static_cast<double>(update->ntimestep - anchor_step_)};
  const int size = sizeof(list);
  fwrite(&size, sizeof(int), 1, fp);
  fwrite(list, sizeof(double), 2, fp);
}

void FixShakeTable::restart(char *buf) {
  // A restarted run keeps playing the record where the saved run was.
  const double *list = reinterpret_cast<double *>(buf);
  anchor_time_ = list[0];
  anchor_step_ = update->ntimestep - static_cast<bigint>(list[1]);
  dt_ = update->dt;
}
