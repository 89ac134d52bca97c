#include "rigid_body_source.h"

#include <mpi.h>

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
    // 8 numbers per body: present flag, xcm (3), quaternion w x y z (4).
    std::vector<double> local(8 * n, 0.0), global(8 * n, 0.0);
    Multisphere &bodies = fix_->data();
    for (int i = 0; i < bodies.n_body(); ++i) {
      const int tag = bodies.tag(i);
      if (tag < 1 || tag > n) continue;
      double *row = &local[8 * (tag - 1)];
      row[0] = 1.0;
      bodies.xcm(row + 1, i);
      bodies.quat(row + 4, i);
    }
    MPI_Allreduce(local.data(), global.data(), 8 * n, MPI_DOUBLE, MPI_SUM, world_);
    poses.assign(n, freestand::BodyPose{});
    present.assign(n, 0);
    for (int t = 0; t < n; ++t) {
      const double *row = &global[8 * t];
      present[t] = row[0] > 0.5;
      poses[t].com = Eigen::Vector3d(row[1], row[2], row[3]);
      poses[t].orientation = Eigen::Quaterniond(row[4], row[5], row[6], row[7]).normalized();
    }
  }

 private:
  FixMultisphere *fix_;  // the stock fix that owns the bodies
  MPI_Comm world_;       // the communicator of the LIGGGHTS instance
};

}  // namespace

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
