#include "rigid_body_source.h"

#include <mpi.h>

#include <algorithm>
#include <cstring>

#include "fix_multisphere.h"
#include "multisphere.h"

namespace LAMMPS_NS {
namespace {

// Stock fix multisphere: bodies live on the rank that owns them.
class MultisphereBodySource : public RigidBodySource {
 public:
  MultisphereBodySource(FixMultisphere *fix, MPI_Comm world) : fix_(fix), world_(world) {}

  int max_tag() override {
    int local = fix_->data().tag_max_body(), global = 0;
    MPI_Allreduce(&local, &global, 1, MPI_INT, MPI_MAX, world_);
    return global;
  }

  void gather_poses(std::vector<freestand::BodyPose> &poses, std::vector<char> &present) override {
    const int n = max_tag();
    PoseGatherer gatherer(n);
    Multisphere &bodies = fix_->data();
    for (int i = 0; i < bodies.n_body(); ++i) {
      const int tag = bodies.tag(i);
      if (tag < 1 || tag > n) continue;
      double com[3], quaternion[4], velocity[3], omega[3];
      bodies.xcm(com, i);
      bodies.quat(quaternion, i);
      bodies.vcm(velocity, i);
      bodies.omega(omega, i);
      gatherer.add(tag - 1, com, quaternion, velocity, omega);
    }
    gatherer.gather(world_, poses, present);
  }

 private:
  FixMultisphere *fix_;  // the stock fix that owns the bodies
  MPI_Comm world_;       // the communicator of the LIGGGHTS instance
};

}  // namespace

void PoseGatherer::add(int index, const double com[3], const double quaternion_wxyz[4],
                       const double velocity[3], const double omega[3]) {
  double *row = &rows_[kRow * index];
  row[0] = 1.0;
  std::copy(com, com + 3, row + 1);
  std::copy(quaternion_wxyz, quaternion_wxyz + 4, row + 4);
  std::copy(velocity, velocity + 3, row + 8);
  std::copy(omega, omega + 3, row + 11);
}

void PoseGatherer::gather(MPI_Comm world, std::vector<freestand::BodyPose> &poses,
                          std::vector<char> &present) {
  std::vector<double> global(rows_.size(), 0.0);
  MPI_Allreduce(rows_.data(), global.data(), static_cast<int>(rows_.size()), MPI_DOUBLE, MPI_SUM,
                world);
  const std::size_t n = rows_.size() / kRow;
  poses.assign(n, freestand::BodyPose{});
  present.assign(n, 0);
  for (std::size_t b = 0; b < n; ++b) {
    const double *row = &global[kRow * b];
    present[b] = row[0] > 0.5;
    poses[b].com = Eigen::Vector3d(row[1], row[2], row[3]);
    poses[b].orientation = Eigen::Quaterniond(row[4], row[5], row[6], row[7]).normalized();
    poses[b].velocity = Eigen::Vector3d(row[8], row[9], row[10]);
    poses[b].omega = Eigen::Vector3d(row[11], row[12], row[13]);
  }
}

RigidBodySource *find_rigid_body_source(Fix *fix, MPI_Comm world,
                                        std::unique_ptr<RigidBodySource> &adapter) {
  if (auto *own = dynamic_cast<RigidBodySource *>(fix)) return own;
  if (std::strncmp(fix->style, "multisphere", 11) == 0) {
    adapter = std::make_unique<MultisphereBodySource>(static_cast<FixMultisphere *>(fix), world);
    return adapter.get();
  }
  return nullptr;
}

}  // namespace LAMMPS_NS
