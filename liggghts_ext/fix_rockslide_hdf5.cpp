// fix rockslide/hdf5: samples compute rockslide every N steps into HDF5.
// Only rank 0 writes; the compute already gathers every body to all ranks.

#include "fix_rockslide_hdf5.h"

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include <fmt/format.h>

#include "comm.h"
#include "compute_rockslide.h"
#include "error.h"
#include "fix_rigid_convex.h"
#include "fix_shaketable.h"
#include "freestand/body_channels.h"
#include "freestand/input_error.h"
#include "modify.h"
#include "universe.h"
#include "update.h"

using namespace LAMMPS_NS;

namespace {

const char *const kStateNames[] = {"x", "y", "z", "qw", "qx", "qy", "qz", "vx", "vy", "vz", "wx", "wy", "wz"};
const char *const kStateUnits[] = {"m", "m", "m", "1", "1", "1", "1", "m/s", "m/s", "m/s", "rad/s", "rad/s", "rad/s"};
// Contact resultants of fix rigid/convex (force, and a point on its line of action).
const char *const kContactNames[] = {"table_f", "table_p", "bodies_f", "bodies_p"};
// The energy ledger of fix rigid/convex (docs/fix_rigid_convex.md): global
// vector entry (1-based) and dataset name; entry 2 is a contact count.
const std::pair<int, const char *> kLedger[] = {
    {1, "kinetic"}, {3, "potential"}, {4, "elastic"}, {5, "normal_dissipation"},
    {6, "friction_dissipation"}, {7, "table_work"}, {8, "balance"}};
const char *const kTableNames[] = {"ax", "ay", "az", "vx", "vy", "vz", "dx", "dy", "dz"};
const char *const kTableUnits[] = {"m/s^2", "m/s^2", "m/s^2", "m/s", "m/s", "m/s", "m", "m", "m"};

}  // namespace

// fix ID group rockslide/hdf5 COMPUTE-ID N FILE [energy FIX-ID] [contacts FIX-ID] [scenario FILE]
FixRockSlideHDF5::FixRockSlideHDF5(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg) {
  if (narg < 6 || narg % 2 != 0)
    error->all(FLERR, "Illegal fix rockslide/hdf5 command: fix ID group rockslide/hdf5 COMPUTE-ID N FILE "
                      "[energy FIX-ID] [contacts FIX-ID] [scenario FILE]");
  compute_id_ = arg[3];
  char *end = nullptr;
  nevery = static_cast<int>(std::strtol(arg[4], &end, 10));
  if (*end != '\0' || nevery <= 0)
    error->all(FLERR, "fix rockslide/hdf5: N (sample every N steps) must be a positive integer");
  path_ = arg[5];
  for (int i = 6; i < narg; i += 2) {
    if (!std::strcmp(arg[i], "energy")) {
      energy_id_ = arg[i + 1];
    } else if (!std::strcmp(arg[i], "contacts")) {
      contacts_id_ = arg[i + 1];
    } else if (!std::strcmp(arg[i], "scenario")) {
      std::ifstream in(arg[i + 1]);
      if (!in) error->all(FLERR, (std::string("fix rockslide/hdf5: cannot read scenario file ") + arg[i + 1]).c_str());
      std::ostringstream text;
      text << in.rdbuf();
      scenario_text_ = text.str();
    } else {
      error->all(FLERR, (std::string("fix rockslide/hdf5: unknown keyword '") + arg[i] +
                         "' (expected energy, contacts or scenario)").c_str());
    }
  }
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
  energy_ = energy_id_.empty() ? nullptr : rigid_convex(energy_id_, "energy");
  contacts_ = contacts_id_.empty() ? nullptr : rigid_convex(contacts_id_, "contacts");
}

FixRigidConvex *FixRockSlideHDF5::rigid_convex(const std::string &id, const char *keyword) {
  const int ifix = modify->find_fix(id.c_str());
  auto *fix = ifix < 0 ? nullptr : dynamic_cast<FixRigidConvex *>(modify->fix[ifix]);
  if (!fix)
    error->all(FLERR, (std::string("fix rockslide/hdf5: ") + keyword + " '" + id + "' is not a fix rigid/convex").c_str());
  return fix;
}

void FixRockSlideHDF5::open_file() {
  file_ = std::make_unique<freestand::SeriesFile>(path_);
  file_->set_attribute("/", "creator", "freestand fix rockslide/hdf5");
  file_->set_attribute("/", "channel_definitions", "see recording-format.md: rock_x, rock_y, twist, "
                       "slide_x, slide_y, uplift; pose = centre of mass and body-to-world quaternion");
  file_->set_attribute("/", "freestand_version", FREESTAND_VERSION);
  file_->set_attribute("/", "liggghts_version", universe->version);
  file_->set_attribute("/", "time_step", fmt::format("{:.17g} s", update->dt));
  if (!scenario_text_.empty()) file_->set_attribute("/", "scenario", scenario_text_);
  file_->add_series("/time", "s");
  if (compute_->table())
    for (int k = 0; k < 9; ++k) file_->add_series(std::string("/table/") + kTableNames[k], kTableUnits[k]);
  const auto &names = freestand::channel_names();
  for (const auto &body : compute_->bodies()) {
    const std::string group = "/bodies/" + body.name + "/";
    for (const auto &channel : names)
      file_->add_series(group + channel, channel.rfind("rock", 0) == 0 || channel == "twist" ? "rad" : "m");
    for (int k = 0; k < 13; ++k) file_->add_series(group + kStateNames[k], kStateUnits[k]);
    if (contacts_)
      for (const char *what : kContactNames)
        for (const char *axis : {"x", "y", "z"})
          file_->add_series(group + what + axis, what[std::strlen(what) - 2] == 'f' ? "N" : "m");
  }
  if (energy_)
    for (const auto &[entry, name] : kLedger) file_->add_series(std::string("/energy/") + name, "J");
}

void FixRockSlideHDF5::setup(int) { end_of_step(); }

void FixRockSlideHDF5::end_of_step() {
  if (update->ntimestep == last_written_) return;
  last_written_ = update->ntimestep;
  if (compute_->invoked_array != update->ntimestep) compute_->compute_array();
  // Collective: every rank takes part; rank 0 writes.
  std::vector<double> collective;
  std::vector<FixRigidConvex::ContactResultant> resultants;
  if (contacts_) resultants = contacts_->gather_contact_resultants();
  for (const auto &r : resultants)
    for (const Eigen::Vector3d *v : {&r.table_force, &r.table_point, &r.pair_force, &r.pair_point})
      collective.insert(collective.end(), v->data(), v->data() + 3);
  if (energy_)
    for (const auto &[entry, name] : kLedger) collective.push_back(energy_->compute_vector(entry - 1));
  if (comm->me == 0) write_sample(collective);
}

void FixRockSlideHDF5::write_sample(const std::vector<double> &collective) {
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
    const freestand::BodyPose &p = poses[i];
    const Eigen::Quaterniond &q = p.orientation;
    row.insert(row.end(), {p.com.x(), p.com.y(), p.com.z(), q.w(), q.x(), q.y(), q.z(), p.velocity.x(),
                           p.velocity.y(), p.velocity.z(), p.omega.x(), p.omega.y(), p.omega.z()});
    // Contact resultants come in scene order, as the compute's bodies do
    // when it takes them from the same fix rigid/convex.
    if (contacts_) row.insert(row.end(), collective.begin() + 12 * i, collective.begin() + 12 * (i + 1));
  }
  row.insert(row.end(), collective.begin() + (contacts_ ? 12 * poses.size() : 0), collective.end());
  try {
    file_->append(row);
  } catch (const freestand::InputError &e) {
    error->one(FLERR, e.what());
  }
}
