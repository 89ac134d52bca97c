// pair_style convex: body-on-body penalty contact between the bodies of
// fix rigid/convex, a thin adapter over freestand::find_body_contacts and
// freestand::ContactLaw. Needs `newton off`: a pair whose bodies live on two
// ranks is computed by both, each applying the forces to its own body and
// updating its own copy of the pair's contact histories identically (the
// pair is always evaluated with the lower tag first).

#include "pair_convex.h"

#include <algorithm>
#include <cstring>

#include "atom.h"
#include "error.h"
#include "fix_rigid_convex.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "style_args.h"
#include "update.h"

using namespace LAMMPS_NS;
using Eigen::Vector3d;

PairConvex::PairConvex(LAMMPS *lmp) : Pair(lmp) { single_enable = 0; }

PairConvex::~PairConvex() {
  if (!allocated) return;
  memory->destroy(setflag);
  memory->destroy(cutsq);
}

void PairConvex::allocate() {
  allocated = 1;
  const int n = atom->ntypes;
  memory->create(setflag, n + 1, n + 1, "pair:setflag");
  memory->create(cutsq, n + 1, n + 1, "pair:cutsq");
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) setflag[i][j] = 0;
}

// pair_style convex [pass_weight W]
void PairConvex::settings(int narg, char **arg) {
  for (int i = 0; i < narg; i += 2) {
    if (std::strcmp(arg[i], "pass_weight") || i + 1 >= narg)
      error->all(FLERR, "Illegal pair_style convex command: pair_style convex [pass_weight W]");
    options_.pass_weight = freestand::parse_number(error, "pair_style convex", "pass_weight", arg[i + 1]);
    if (options_.pass_weight <= 0.0 || options_.pass_weight > 1.0)
      error->all(FLERR, "pair_style convex: pass_weight must be in (0, 1]");
  }
}

// pair_coeff * *: the contact parameters are the interfaces of the scene.
void PairConvex::coeff(int narg, char **arg) {
  if (narg != 2) error->all(FLERR, "pair_coeff for pair_style convex takes no parameters: pair_coeff * *");
  if (!allocated) allocate();
  int ilo, ihi, jlo, jhi;
  force->bounds(arg[0], atom->ntypes, ilo, ihi);
  force->bounds(arg[1], atom->ntypes, jlo, jhi);
  for (int i = ilo; i <= ihi; ++i)
    for (int j = std::max(jlo, i); j <= jhi; ++j) setflag[i][j] = 1;
}

void PairConvex::init_style() {
  if (force->newton_pair)
    error->all(FLERR, "pair_style convex needs 'newton off' (each rank updates its own bodies' histories)");
  bodies_ = nullptr;
  for (int i = 0; i < modify->nfix && !bodies_; ++i)
    bodies_ = dynamic_cast<FixRigidConvex *>(modify->fix[i]);
  if (!bodies_) error->all(FLERR, "pair_style convex needs a fix rigid/convex defined before the run");
  neighbor->request(this);
}

// Bodies interact when their bounding spheres can touch.
double PairConvex::init_one(int, int) { return 2.0 * bodies_->largest_radius(); }

void PairConvex::compute(int eflag, int vflag) {
  if (eflag || vflag) ev_setup(eflag, vflag);
  else evflag = vflag_fdotr = 0;
  ledger_.elastic = 0.0;
  pair_forces_.clear();
  bodies_->clear_pair_resultants();
  for (int ii = 0; ii < list->inum; ++ii) {
    const int i = list->ilist[ii];
    if (bodies_->body_of(i) < 0) continue;
    const int *neighbours = list->firstneigh[i];
    for (int jj = 0; jj < list->numneigh[i]; ++jj) {
      const int j = neighbours[jj] & NEIGHMASK;
      if (bodies_->body_of(j) >= 0) contact_pair(i, j);
    }
  }
  apply_pair_forces();
}

// Each body's pair forces summed in the order of the partners' tags: the
// floating-point sum is then independent of how atoms are ordered on a rank
// (neighbour lists, migration, restart), so runs on any number of ranks and
// restarted runs match the serial, uninterrupted one bit for bit.
void PairConvex::apply_pair_forces() {
  std::sort(pair_forces_.begin(), pair_forces_.end(), [](const PairForce &x, const PairForce &y) {
    return x.atom != y.atom ? x.atom < y.atom : x.partner < y.partner;
  });
  for (const PairForce &p : pair_forces_) {
    for (int k = 0; k < 3; ++k) {
      atom->f[p.atom][k] += p.force[k];
      atom->torque[p.atom][k] += p.torque[k];
    }
    bodies_->add_pair_resultant(p.atom, p.force, p.torque);
  }
}

namespace {

freestand::BodyMotion motion_of(const FixRigidConvex &bodies, const Atom &atom, int i) {
  return {Vector3d(atom.x[i]), bodies.orientation_of(i), Vector3d(atom.v[i]), Vector3d(atom.omega[i])};
}

}  // namespace

// Contacts of one pair, A being the body with the lower tag.
void PairConvex::contact_pair(int i, int j) {
  const int a = atom->tag[i] < atom->tag[j] ? i : j, b = a == i ? j : i;
  const int body_a = bodies_->body_of(a), body_b = bodies_->body_of(b);
  const freestand::BodyContactModel &model_a = bodies_->contact_model(body_a);
  const freestand::BodyContactModel &model_b = bodies_->contact_model(body_b);
  freestand::find_body_contacts(model_a, motion_of(*bodies_, *atom, a), model_b,
                                motion_of(*bodies_, *atom, b), options_, contacts_);
  const int nlocal = atom->nlocal;
  FixRigidConvex::PairHistory *copy_a = a < nlocal ? &bodies_->pair_history(a, atom->tag[b]) : nullptr;
  FixRigidConvex::PairHistory *copy_b = b < nlocal ? &bodies_->pair_history(b, atom->tag[a]) : nullptr;
  const auto &previous = (copy_a ? copy_a : copy_b)->entries;
  if (contacts_.empty() && previous.empty()) return;

  const freestand::ContactLaw &law = bodies_->law_between(body_a, body_b);
  const double m_a = bodies_->mass_of(body_a), m_b = bodies_->mass_of(body_b);
  const double reduced_mass = m_a * m_b / (m_a + m_b);
  Vector3d force_a = Vector3d::Zero(), torque_a = Vector3d::Zero();
  Vector3d force_b = Vector3d::Zero(), torque_b = Vector3d::Zero();
  updated_.clear();
  // Ledger share: 1 when this rank owns both bodies, 1/2 when it owns one
  // (the other rank computes the same pair).
  const double share = 0.5 * ((a < nlocal ? 1 : 0) + (b < nlocal ? 1 : 0));
  const bool count_dissipation = !update->setupflag;
  for (const freestand::NodeContact &c : contacts_) {
    auto found = std::lower_bound(previous.begin(), previous.end(), c.key,
                                  [](const auto &entry, std::uint64_t key) { return entry.first < key; });
    freestand::ContactHistory history =
        found != previous.end() && found->first == c.key ? found->second : freestand::ContactHistory{};
    const freestand::ContactForce result =
        law.compute(freestand::to_contact_point(c, reduced_mass), update->dt, history);
    freestand::apply_node_force(c, result.force, force_a, torque_a, force_b, torque_b);
    updated_.emplace_back(c.key, history);
    ledger_.elastic += share * result.elastic_energy();
    if (count_dissipation) {
      ledger_.normal_dissipated += share * result.normal_dissipation;
      ledger_.friction_dissipated += share * result.friction_dissipation;
    }
  }
  std::sort(updated_.begin(), updated_.end(),
            [](const auto &x, const auto &y) { return x.first < y.first; });
  if (copy_a) copy_a->entries = updated_;
  if (copy_b) copy_b->entries = updated_;
  if (a < nlocal) pair_forces_.push_back({a, atom->tag[b], force_a, torque_a});
  if (b < nlocal) pair_forces_.push_back({b, atom->tag[a], force_b, torque_b});
}
