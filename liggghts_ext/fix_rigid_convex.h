/* freestand: fix rigid/convex. Convex rigid bodies (one LIGGGHTS atom each)
   with penalty contact against the shake-table plane; see
   docs/fix_rigid_convex.md. */

#ifdef FIX_CLASS

FixStyle(rigid/convex,FixRigidConvex)

#else

#ifndef LMP_FIX_RIGID_CONVEX_H
#define LMP_FIX_RIGID_CONVEX_H

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "fix.h"
#include "freestand/contact_law.h"
#include "freestand/plane_contact_nodes.h"
#include "freestand/rigid_body.h"
#include "freestand/scene.h"
#include "freestand/scene_contact_laws.h"
#include "rigid_body_source.h"

namespace freestand { class BodyContactModel; }

namespace LAMMPS_NS {

class FixShakeTable;

class FixRigidConvex : public Fix, public RigidBodySource {
 public:
  FixRigidConvex(class LAMMPS *lmp, int narg, char **arg);
  ~FixRigidConvex() override;
  void post_create() override;
  int setmask() override;
  void init() override;
  void setup(int vflag) override;
  void setup_pre_force(int vflag) override;
  void pre_force(int vflag) override;
  int pack_comm(int n, int *list, double *buf, int pbc_flag, int *pbc) override;
  void unpack_comm(int n, int first, double *buf) override;
  void initial_integrate(int vflag) override;
  void post_force(int vflag) override;
  void final_integrate() override;
  // Global vector: [1] kinetic energy (J), [2] number of node contacts with
  // the table, then the energy ledger (docs/fix_rigid_convex.md, "Energy
  // ledger"): [3] gravitational potential energy, [4] elastic energy stored in
  // the contacts (table and pair convex), [5] cumulative normal-dashpot
  // dissipation, [6] cumulative friction (and tangential dashpot)
  // dissipation, [7] cumulative work of the table on the bodies, [8]
  // [1] + [3] + [4] + [5] + [6] - [7] (constant if the ledger closes). J.
  double compute_vector(int i) override;
  static constexpr int kLedgerSize = 8;

  void grow_arrays(int nmax) override;
  void copy_arrays(int i, int j, int delflag) override;
  int pack_exchange(int i, double *buf) override;
  int unpack_exchange(int nlocal, double *buf) override;
  int pack_restart(int i, double *buf) override;
  void unpack_restart(int nlocal, int nth) override;
  int size_restart(int nlocal) override;
  int maxsize_restart() override;
  void write_restart(FILE *fp) override;
  void restart(char *buf) override;

  // RigidBodySource: bodies by body number (file order).
  int max_tag() override;
  void gather_poses(std::vector<freestand::BodyPose> &poses, std::vector<char> &present) override;
  std::vector<freestand::ChannelBody> describe_bodies() override;

 public:
  // Contact histories of one body with one partner body (pair convex),
  // keyed by NodeContact::key and sorted by it. Both bodies keep a copy,
  // updated identically, so the pair's ranks agree after migration.
  struct PairHistory {
    tagint partner;                                                   // tag of the other body
    std::vector<std::pair<std::uint64_t, freestand::ContactHistory>> entries;  // by key
  };
  // For pair convex: body index of atom i (local or ghost; -1: not a body).
  int body_of(int i) const { return state_[i].body; }
  const Eigen::Quaterniond &orientation_of(int i) const { return state_[i].orientation; }
  const freestand::BodyContactModel &contact_model(int body) const { return *templates_[body].contact_model; }
  double mass_of(int body) const { return templates_[body].mass.mass(); }
  double largest_radius() const;
  // The law between two bodies: their interface, or the fix's defaults.
  const freestand::ContactLaw &law_between(int body_a, int body_b) const { return laws_->between(body_a, body_b); }
  // Histories of local atom i with `partner`, created empty when new.
  PairHistory &pair_history(int i, tagint partner);
  // pair convex reports each body's body-on-body resultant of the step.
  void clear_pair_resultants();
  void add_pair_resultant(int i, const Eigen::Vector3d &force, const Eigen::Vector3d &torque);

  // Resultant contact forces of every body (by scene index), with a point on
  // their line of action: the table's in the table plane, the other bodies'
  // nearest the COM. Collective.
  struct ContactResultant {
    Eigen::Vector3d table_force, table_point;  // N, m (world); the point is in the table plane
    Eigen::Vector3d pair_force, pair_point;    // N, m (world)
  };
  std::vector<ContactResultant> gather_contact_resultants();

 private:
  // Everything about one body of the scene that does not change (cold data).
  struct BodyTemplate {
    std::string name;                              // from the scene
    freestand::PreparedMassProperties mass;        // mass and inertia about the COM
    freestand::PlaneContactNodes table_nodes;      // every face's nodes against the table plane
    double bounding_radius;                        // atom radius: farthest point from the COM (m)
    std::shared_ptr<freestand::BodyContactModel> contact_model;  // all faces' nodes, for pair convex
  };
  // Per local atom: the body it is and its rotational state (hot data).
  struct BodyState {
    int body = -1;                                       // index into templates_, -1: not ours
    Eigen::Quaterniond orientation;                      // body frame -> world
    Eigen::Vector3d angular_momentum;                    // world (kg m^2/s)
    std::vector<freestand::ContactHistory> table_history;  // per share of table_nodes
    std::vector<PairHistory> pairs;                      // with bodies in contact (pair convex)
    Eigen::Vector3d table_force = Eigen::Vector3d::Zero();   // this step's table contact force (N)
    Eigen::Vector3d table_torque = Eigen::Vector3d::Zero();  // ... its torque about the COM (N m)
    Eigen::Vector3d pair_force = Eigen::Vector3d::Zero();    // this step's body-on-body force (N)
    Eigen::Vector3d pair_torque = Eigen::Vector3d::Zero();   // ... its torque about the COM (N m)
  };

  void parse(int narg, char **arg, std::string &scene_file, freestand::SceneDefaults &defaults);
  void build_templates();
  void create_bodies();
  void check_time_step();
  void table_contact(int i);
  // The table plane now: through `point` (the table's reference point) with
  // upward unit normal `normal`; `point` moves at `velocity`, the table
  // turns at `omega` (world frame).
  struct TablePlane {
    Eigen::Vector3d point, normal, velocity, omega;
  };
  TablePlane table_plane() const;

  freestand::Scene scene_;                          // as read, with defaults applied
  std::unique_ptr<freestand::SceneContactLaws> laws_;  // every contact's law: interfaces, defaults
  std::vector<BodyTemplate> templates_;             // one per scene body
  std::vector<BodyState> state_;                    // per local atom (size nmax)
  std::vector<int> acting_;                         // scratch: acting shares of one table node
  std::string table_id_;                            // fix shaketable moving the plane, or empty
  FixShakeTable *table_ = nullptr;                  // resolved in init()
  double plane_z_ = 0.0;                            // table top at rest (m)
  bool auto_time_step_ = false;                     // keyword timestep auto: set dt in init()
  static constexpr double kAutoTimeStepFraction = 0.5;  // timestep auto: dt / critical step
  int atom_type_ = 1;                               // LIGGGHTS atom type of the bodies
  tagint first_tag_ = 0;                            // tag of body 0; body k has first_tag_ + k
  int table_contacts_ = 0;                          // node contacts with the table, this rank

  // Energy ledger of the table contacts on this rank (J); pair convex keeps
  // its own. The cumulative terms do not count the force evaluation of setup
  // and start from zero in every new fix (also after read_restart).
  void ledger_local(double out[kLedgerSize]);
  bool in_setup_ = false;          // post_force() called from setup()
  double table_elastic_ = 0.0;     // elastic energy of the table contacts now
  double table_normal_dissipated_ = 0.0;
  double table_friction_dissipated_ = 0.0;
  double table_work_ = 0.0;        // sum F . v_table dt
};

}  // namespace LAMMPS_NS

#endif
#endif
