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

 private:
  void allocate();
  void contact_pair(int i, int j);

  FixRigidConvex *bodies_ = nullptr;                  // resolved in init_style()
  freestand::BodyContactOptions options_;             // band, pass weight
  std::vector<freestand::NodeContact> contacts_;      // reused every pair
  std::vector<std::pair<std::uint64_t, freestand::ContactHistory>> updated_;  // reused
};

}  // namespace LAMMPS_NS

#endif
#endif
