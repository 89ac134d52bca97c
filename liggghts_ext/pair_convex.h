/* freestand: pair_style convex. Penalty contact between the convex bodies of
   fix rigid/convex; see docs/pair_convex.md. */

#ifdef PAIR_CLASS

PairStyle(convex,PairConvex)

#else

#ifndef LMP_PAIR_CONVEX_H
#define LMP_PAIR_CONVEX_H

#include <vector>

#include "freestand/body_contact.h"
#include "pair.h"

namespace LAMMPS_NS {

class FixRigidConvex;

class PairConvex : public Pair {
 public:
  explicit PairConvex(class LAMMPS *lmp);
  ~PairConvex() override;
  void compute(int eflag, int vflag) override;
  void settings(int narg, char **arg) override;
  void coeff(int narg, char **arg) override;
  void init_style() override;
  double init_one(int i, int j) override;

  // Energy ledger of the body-on-body contacts on this rank (J), for fix
  // rigid/convex's global vector: a pair computed by two ranks (newton off,
  // one body each) counts half on each. The dissipation is cumulative over
  // the run's steps (setup's force evaluation not counted).
  struct EnergyLedger {
    double elastic = 0.0;              // stored in the contacts now
    double normal_dissipated = 0.0;    // by the normal dashpots, cumulative
    double friction_dissipated = 0.0;  // by friction and tangential dashpots, cumulative
  };
  const EnergyLedger &ledger() const { return ledger_; }

 private:
  // A pair's force and torque on one local body, applied after all pairs.
  struct PairForce {
    int atom;                 // local index of the body
    tagint partner;           // tag of the other body
    Eigen::Vector3d force;    // N
    Eigen::Vector3d torque;   // N m, about the body's COM
  };

  void allocate();
  void contact_pair(int i, int j);
  void apply_pair_forces();

  FixRigidConvex *bodies_ = nullptr;                  // resolved in init_style()
  freestand::BodyContactOptions options_;             // band, pass weight
  std::vector<freestand::NodeContact> contacts_;      // reused every pair
  std::vector<std::pair<std::uint64_t, freestand::ContactHistory>> updated_;  // reused
  std::vector<PairForce> pair_forces_;                // this step's, reused
  EnergyLedger ledger_;
};

}  // namespace LAMMPS_NS

#endif
#endif
