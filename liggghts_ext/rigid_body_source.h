#ifndef FREESTAND_RIGID_BODY_SOURCE_H
#define FREESTAND_RIGID_BODY_SOURCE_H

// What compute rockslide needs from a fix that integrates rigid bodies: the
// pose and velocities of every body, gathered on all ranks. Stock fix multisphere is adapted
// by MultisphereBodySource; freestand's own rigid-body fixes implement this
// interface directly.

#include <mpi.h>

#include <memory>
#include <vector>

#include "freestand/body_channels.h"
#include "freestand/rocking_angles.h"

namespace LAMMPS_NS {

class Fix;

class RigidBodySource {
 public:
  virtual ~RigidBodySource() = default;
  // Largest body tag; poses are indexed by tag - 1.
  virtual int max_tag() = 0;
  // Poses of all bodies on all ranks, by tag - 1; `present[i]` is false for
  // tags that do not exist (yet). Collective: every rank must call it.
  virtual void gather_poses(std::vector<freestand::BodyPose> &poses,
                            std::vector<char> &present) = 0;
  // Names, geometry and supports of the bodies, when the source knows them
  // (freestand's body fixes do; stock multisphere does not: empty).
  virtual std::vector<freestand::ChannelBody> describe_bodies() { return {}; }
};

// Poses of bodies spread over ranks, gathered on every rank: each rank adds
// the bodies it owns, then gather() sums over ranks (each body is owned by
// exactly one rank).
class PoseGatherer {
 public:
  explicit PoseGatherer(int bodies) : rows_(kRow * bodies, 0.0) {}
  void add(int index, const double com[3], const double quaternion_wxyz[4], const double velocity[3],
           const double omega[3]);
  void gather(MPI_Comm world, std::vector<freestand::BodyPose> &poses, std::vector<char> &present);

 private:
  static constexpr int kRow = 14;  // present flag, com (3), quaternion w x y z (4), velocity (3), omega (3)
  std::vector<double> rows_;      // kRow numbers per body, zero where absent
};

// The body source behind a fix: the fix itself when it implements
// RigidBodySource, an adapter kept in `adapter` for stock fix multisphere,
// or null when the fix integrates no rigid bodies.
RigidBodySource *find_rigid_body_source(Fix *fix, MPI_Comm world,
                                        std::unique_ptr<RigidBodySource> &adapter);

}  // namespace LAMMPS_NS

#endif
