/* freestand: compute rockslide. Rocking, sliding, twist and uplift of every
   rigid body; see docs/compute_rockslide.md. */

#ifdef COMPUTE_CLASS

ComputeStyle(rockslide,ComputeRockSlide)

#else

#ifndef LMP_COMPUTE_ROCKSLIDE_H
#define LMP_COMPUTE_ROCKSLIDE_H

#include <memory>
#include <string>
#include <vector>

#include "compute.h"
#include "freestand/body_channels.h"
#include "rigid_body_source.h"

namespace LAMMPS_NS {

class FixShakeTable;

class ComputeRockSlide : public Compute {
 public:
  ComputeRockSlide(class LAMMPS *lmp, int &iarg, int narg, char **arg);
  ~ComputeRockSlide() override;
  void init() override;
  // Global array: one row per body, columns rock_x rock_y twist slide_x slide_y uplift.
  void compute_array() override;

  const std::vector<freestand::ChannelBody> &bodies() const { return channels_->bodies(); }
  // The shake table the bodies stand on, or null for a fixed support.
  FixShakeTable *table() const { return table_; }
  // The channel kernel: own-frame poses of the last compute_array().
  const freestand::BodyChannels &channels() const { return *channels_; }

 private:
  void parse(int iarg, int narg, char **arg);
  void allocate_array();
  void describe_from_source();
  int parse_body(int iarg, int narg, char **arg, freestand::ChannelBody &body,
                 std::string &support);

  std::string source_id_;                       // ID of the rigid-body fix
  std::string table_id_;                        // ID of fix shaketable, empty: fixed support
  RigidBodySource *source_ = nullptr;           // resolved in init()
  std::unique_ptr<RigidBodySource> adapter_;    // owns the adapter for stock fixes
  FixShakeTable *table_ = nullptr;              // resolved in init()
  std::unique_ptr<freestand::BodyChannels> channels_;  // the channel kernel
};

}  // namespace LAMMPS_NS

#endif
#endif
