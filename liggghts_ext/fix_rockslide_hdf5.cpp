// fix rockslide/hdf5: samples compute rockslide every N steps into HDF5.
// Only rank 0 writes; the compute already gathers every body to all ranks.

#include "fix_rockslide_hdf5.h"

#include <cstdlib>
#include <vector>

#include "comm.h"
#include "compute_rockslide.h"
#include "error.h"
#include "fix_shaketable.h"
#include "freestand/body_channels.h"
#include "freestand/input_error.h"
#include "modify.h"
#include "update.h"

using namespace LAMMPS_NS;

namespace {

const char *const kPoseNames[] = {"x", "y", "z", "qw", "qx", "qy", "qz"};
const char *const kPoseUnits[] = {"m", "m", "m", "1", "1", "1", "1"};
const char *const kTableNames[] = {"ax", "ay", "az", "vx", "vy", "vz", "dx", "dy", "dz"};
const char *const kTableUnits[] = {"m/s^2", "m/s^2", "m/s^2", "m/s", "m/s", "m/s", "m", "m", "m"};

}  // namespace

// fix ID group rockslide/hdf5 COMPUTE-ID N FILE
FixRockSlideHDF5::FixRockSlideHDF5(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg) {
  if (narg != 6)
    error->all(FLERR, "Illegal fix rockslide/hdf5 command: fix ID group rockslide/hdf5 COMPUTE-ID N FILE");
  compute_id_ = arg[3];
  char *end = nullptr;
  nevery = static_cast<int>(std::strtol(arg[4], &end, 10));
  if (*end != '\0' || nevery <= 0)
    error->all(FLERR, "fix rockslide/hdf5: N (sample every N steps) must be a positive integer");
  path_ = arg[5];
}

FixRockSlideHDF5::~FixRockSlideHDF5() {
  if (!file_) return;
  try {
    file_->commit();
  } catch (const freestand::InputError &e) {
    if (screen) fprintf(screen, "WARNING: fix rockslide/hdf5: %s\n", e.what());
  }
}

int FixRockSlideHDF5::setmask() { return FixConst::END_OF_STEP; }

void FixRockSlideHDF5::init() {
  const int icompute = modify->find_compute(compute_id_.c_str());
  compute_ = icompute < 0 ? nullptr : dynamic_cast<ComputeRockSlide *>(modify->compute[icompute]);
  if (!compute_)
    error->all(FLERR, ("fix rockslide/hdf5: '" + compute_id_ + "' is not a compute rockslide").c_str());
}

void FixRockSlideHDF5::open_file() {
  file_ = std::make_unique<freestand::SeriesFile>(path_);
  file_->set_attribute("/", "creator", "freestand fix rockslide/hdf5");
  file_->set_attribute("/", "channel_definitions", "see recording-format.md: rock_x, rock_y, twist, "
                       "slide_x, slide_y, uplift; pose = centre of mass and body-to-world quaternion");
  file_->add_series("/time", "s");
  if (compute_->table())
    for (int k = 0; k < 9; ++k) file_->add_series(std::string("/table/") + kTableNames[k], kTableUnits[k]);
  const auto &names = freestand::channel_names();
  for (const auto &body : compute_->bodies()) {
    const std::string group = "/bodies/" + body.name + "/";
    for (const auto &channel : names)
      file_->add_series(group + channel, channel.rfind("rock", 0) == 0 || channel == "twist" ? "rad" : "m");
    for (int k = 0; k < 7; ++k) file_->add_series(group + kPoseNames[k], kPoseUnits[k]);
  }
}

void FixRockSlideHDF5::setup(int) { end_of_step(); }

void FixRockSlideHDF5::end_of_step() {
  if (update->ntimestep == last_written_) return;
  last_written_ = update->ntimestep;
  if (compute_->invoked_array != update->ntimestep) compute_->compute_array();
  if (comm->me == 0) write_sample();
}

void FixRockSlideHDF5::write_sample() {
  // Opened at the first sample, once the compute has resolved its table.
  if (!file_) {
    try {
      open_file();
    } catch (const freestand::InputError &e) {
      error->one(FLERR, e.what());
    }
  }
  std::vector<double> row;
  row.push_back(update->atime + (update->ntimestep - update->atimestep) * update->dt);
  if (FixShakeTable *table = compute_->table()) {
    const freestand::TableState s = table->state();
    for (const Eigen::Vector3d *v : {&s.acceleration, &s.velocity, &s.displacement})
      row.insert(row.end(), v->data(), v->data() + 3);
  }
  const auto &poses = compute_->channels().own_poses();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    for (int j = 0; j < compute_->size_array_cols; ++j) row.push_back(compute_->array[i][j]);
    const Eigen::Quaterniond &q = poses[i].orientation;
    row.insert(row.end(), {poses[i].com.x(), poses[i].com.y(), poses[i].com.z(), q.w(), q.x(), q.y(), q.z()});
  }
  try {
    file_->append(row);
  } catch (const freestand::InputError &e) {
    error->one(FLERR, e.what());
  }
}
