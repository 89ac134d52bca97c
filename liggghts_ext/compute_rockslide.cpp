// compute rockslide: thin LIGGGHTS adapter over freestand::BodyChannels.

#include "compute_rockslide.h"

#include <cmath>
#include <cstdlib>
#include <cstring>

#include "error.h"
#include "style_args.h"
#include "fix_shaketable.h"
#include "freestand/input_error.h"
#include "memory.h"
#include "modify.h"
#include "update.h"

using namespace LAMMPS_NS;

ComputeRockSlide::ComputeRockSlide(LAMMPS *lmp, int &iarg, int narg, char **arg)
    : Compute(lmp, iarg, narg, arg) {
  array_flag = 1;
  size_array_cols = static_cast<int>(freestand::channel_names().size());
  extarray = 0;
  parse(iarg, narg, arg);
  if (!channels_) describe_from_source();
  allocate_array();
}

// No `body` keywords: the body fix (defined before this compute) names them.
void ComputeRockSlide::describe_from_source() {
  const int ifix = modify->find_fix(source_id_.c_str());
  std::unique_ptr<RigidBodySource> adapter;
  RigidBodySource *source = ifix < 0 ? nullptr : find_rigid_body_source(modify->fix[ifix], world, adapter);
  std::vector<freestand::ChannelBody> bodies;
  if (source) bodies = source->describe_bodies();
  if (bodies.empty())
    error->all(FLERR, ("compute rockslide: fix '" + source_id_ +
                       "' does not describe its bodies: give 'body NAME TAG com X Y Z height H'").c_str());
  channels_ = std::make_unique<freestand::BodyChannels>(std::move(bodies));
}

void ComputeRockSlide::allocate_array() {
  size_array_rows = static_cast<int>(channels_->bodies().size());
  memory->create(array, size_array_rows, size_array_cols, "rockslide:array");
  for (int i = 0; i < size_array_rows; ++i)
    for (int j = 0; j < size_array_cols; ++j) array[i][j] = 0.0;
}

ComputeRockSlide::~ComputeRockSlide() { memory->destroy(array); }

void ComputeRockSlide::parse(int iarg, int narg, char **arg) {
  if (iarg >= narg) error->all(FLERR, "compute rockslide: needs the ID of a rigid-body fix");
  source_id_ = arg[iarg++];
  std::vector<freestand::ChannelBody> bodies;
  std::vector<std::string> supports;  // support name per body
  while (iarg < narg) {
    if (!std::strcmp(arg[iarg], "table")) {
      if (iarg + 1 >= narg) error->all(FLERR, "compute rockslide: 'table' needs a fix ID");
      table_id_ = arg[iarg + 1];
      iarg += 2;
    } else if (!std::strcmp(arg[iarg], "body")) {
      bodies.emplace_back();
      supports.emplace_back("table");
      iarg = parse_body(iarg + 1, narg, arg, bodies.back(), supports.back());
    } else {
      error->all(FLERR, (std::string("compute rockslide: unknown keyword '") + arg[iarg] +
                         "' (expected 'table' or 'body')").c_str());
    }
  }
  if (bodies.empty()) return;  // taken from the body fix in init()
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (supports[i] == "table") continue;
    bodies[i].support = -2;  // unknown until found
    for (std::size_t j = 0; j < bodies.size(); ++j)
      if (bodies[j].name == supports[i]) bodies[i].support = static_cast<int>(j);
    if (bodies[i].support < 0)
      error->all(FLERR, ("compute rockslide: body '" + bodies[i].name + "' is supported by '" +
                         supports[i] + "', which is neither 'table' nor a body").c_str());
  }
  try {
    channels_ = std::make_unique<freestand::BodyChannels>(std::move(bodies));
  } catch (const freestand::InputError &e) {
    error->all(FLERR, (std::string("compute rockslide: ") + e.what()).c_str());
  }
}

// body NAME TAG com X Y Z height H [support table|NAME] [rotate AX AY AZ ANGLE]
int ComputeRockSlide::parse_body(int iarg, int narg, char **arg, freestand::ChannelBody &body,
                                 std::string &support) {
  if (iarg + 2 > narg) error->all(FLERR, "compute rockslide: 'body' needs NAME TAG");
  body.name = arg[iarg];
  const double tag = freestand::parse_number(error, "compute rockslide", "body TAG", arg[iarg + 1]);
  if (tag < 1 || tag != std::floor(tag))
    error->all(FLERR, ("compute rockslide: body '" + body.name + "' TAG must be a positive integer").c_str());
  body.index = static_cast<int>(tag) - 1;
  iarg += 2;
  bool have_com = false, have_height = false;
  while (iarg < narg && std::strcmp(arg[iarg], "body") && std::strcmp(arg[iarg], "table")) {
    const std::string key = arg[iarg];
    if (key == "com" && iarg + 3 < narg) {
      for (int k = 0; k < 3; ++k) body.geometry.com[k] = freestand::parse_number(error, "compute rockslide", "com", arg[iarg + 1 + k]);
      have_com = true;
      iarg += 4;
    } else if (key == "height" && iarg + 1 < narg) {
      body.geometry.height = freestand::parse_number(error, "compute rockslide", "height", arg[iarg + 1]);
      if (body.geometry.height <= 0)
        error->all(FLERR, ("compute rockslide: body '" + body.name + "' height must be > 0").c_str());
      have_height = true;
      iarg += 2;
    } else if (key == "support" && iarg + 1 < narg) {
      support = arg[iarg + 1];
      iarg += 2;
    } else if (key == "rotate" && iarg + 4 < narg) {
      Eigen::Vector3d axis;
      for (int k = 0; k < 3; ++k) axis[k] = freestand::parse_number(error, "compute rockslide", "rotate axis", arg[iarg + 1 + k]);
      const double angle = freestand::parse_number(error, "compute rockslide", "rotate angle", arg[iarg + 4]);
      if (axis.norm() == 0) error->all(FLERR, "compute rockslide: 'rotate' axis must be nonzero");
      body.initial_frame = Eigen::AngleAxisd(angle, axis.normalized());
      iarg += 5;
    } else {
      error->all(FLERR, ("compute rockslide: body '" + body.name + "': unknown or incomplete keyword '" +
                         key + "'").c_str());
    }
  }
  if (!have_com || !have_height)
    error->all(FLERR, ("compute rockslide: body '" + body.name +
                       "' needs 'com X Y Z' and 'height H' (body frame: origin at the base centre)").c_str());
  return iarg;
}

void ComputeRockSlide::init() {
  const int ifix = modify->find_fix(source_id_.c_str());
  if (ifix < 0)
    error->all(FLERR, ("compute rockslide: no fix with ID '" + source_id_ + "'").c_str());
  source_ = find_rigid_body_source(modify->fix[ifix], world, adapter_);
  if (!source_)
    error->all(FLERR, ("compute rockslide: fix '" + source_id_ +
                       "' integrates no rigid bodies (use fix multisphere or a freestand body fix)").c_str());
  table_ = nullptr;
  if (!table_id_.empty()) {
    const int itable = modify->find_fix(table_id_.c_str());
    if (itable >= 0) table_ = dynamic_cast<FixShakeTable *>(modify->fix[itable]);
    if (!table_)
      error->all(FLERR, ("compute rockslide: '" + table_id_ + "' is not a fix shaketable").c_str());
  }
}

void ComputeRockSlide::compute_array() {
  invoked_array = update->ntimestep;
  std::vector<freestand::BodyPose> poses;
  std::vector<char> present;
  source_->gather_poses(poses, present);
  freestand::TablePose table;
  if (table_) {
    const freestand::TableState state = table_->state();
    table = {state.displacement, state.orientation, Eigen::Vector3d(0.0, 0.0, table_->plane_height())};
  }
  const std::vector<freestand::ModeChannels> values = channels_->update(poses, present, table);
  for (std::size_t i = 0; i < values.size(); ++i) {
    const std::vector<double> row = freestand::channel_values(values[i]);
    for (std::size_t j = 0; j < row.size(); ++j) array[i][j] = row[j];
  }
}
