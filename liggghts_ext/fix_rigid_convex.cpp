// fix rigid/convex: LIGGGHTS adapter over freestand's rigid-body, shape and
// contact-law kernels. One atom per body (at its centre of mass, radius =
// bounding sphere), so LIGGGHTS' neighbour lists and domain decomposition
// apply; the orientation, angular momentum and contact histories live here.

#include "fix_rigid_convex.h"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <unordered_map>

#include "atom.h"
#include "atom_vec.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "style_args.h"
#include "fix_gravity.h"
#include "fix_shaketable.h"
#include "force.h"
#include "freestand/body_contact.h"
#include "freestand/contact_time_step.h"
#include "freestand/input_error.h"
#include "freestand/scene_time_step.h"
#include "modify.h"
#include "pair.h"
#include "pair_convex.h"
#include "update.h"

using namespace LAMMPS_NS;
using Eigen::Quaterniond;
using Eigen::Vector3d;

namespace {

// Writes a message to screen and log on rank 0.
void note(LAMMPS *lmp, const std::string &text) {
  if (lmp->comm->me != 0) return;
  if (lmp->screen) fprintf(lmp->screen, "fix rigid/convex: %s\n", text.c_str());
  if (lmp->logfile) fprintf(lmp->logfile, "fix rigid/convex: %s\n", text.c_str());
}

}  // namespace

// fix ID group rigid/convex scene FILE [table SHAKE-ID] [plane Z] [type T]
//     [stiffness KA] [restitution E] [mu MU] [spacing H] [layout surface|boundary|vertices]
//     [tangential_damping ZT|normal]
FixRigidConvex::FixRigidConvex(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg) {
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    error->all(FLERR, "fix rigid/convex needs atom_style sphere (radius, rmass, omega, torque)");
  vector_flag = 1;
  size_vector = kLedgerSize;
  global_freq = 1;
  extvector = 1;
  time_integrate = 1;
  restart_global = 1;
  restart_peratom = 1;
  comm_forward = 5;  // body index and orientation of ghosts

  std::string scene_file;
  freestand::SceneDefaults defaults;
  parse(narg, arg, scene_file, defaults);
  try {
    scene_ = freestand::read_scene_file(scene_file, defaults);
    // Tangential dashpot (docs/fix_rigid_convex.md, "Housner's limit"): zeta_t = zeta unless
    // the tangential_damping keyword says otherwise (SceneContactLaws).
    laws_ = std::make_unique<freestand::SceneContactLaws>(scene_, defaults);
    build_templates();
  } catch (const freestand::InputError &e) {
    error->all(FLERR, (std::string("fix rigid/convex: ") + e.what()).c_str());
  }
  for (const auto &body : scene_.bodies)
    for (const auto &text : body.notes) note(lmp, text);
  for (const auto &interface : scene_.interfaces)
    for (const auto &text : interface.notes) note(lmp, text);

  grow_arrays(atom->nmax);
  // Atom::add_callback() registers the fix whose slot in Modify is still
  // empty, i.e. the one under construction: it must be called from here.
  atom->add_callback(0);
  atom->add_callback(1);
}

// Bodies are created once the fix is complete (restart data, if any, has
// then been applied: a restarted run keeps its bodies).
void FixRigidConvex::post_create() {
  if (modify->have_restart_data(this))
    note(lmp, "bodies continue from the restart file (tags from " + std::to_string(first_tag_) + ")");
  else
    create_bodies();
}

FixRigidConvex::~FixRigidConvex() {
  atom->delete_callback(id, 0);
  atom->delete_callback(id, 1);
}

void FixRigidConvex::parse(int narg, char **arg, std::string &scene_file,
                           freestand::SceneDefaults &defaults) {
  for (int i = 3; i < narg; i += 2) {
    const std::string key = arg[i];
    if (i + 1 >= narg) error->all(FLERR, ("fix rigid/convex: '" + key + "' needs a value").c_str());
    const char *value = arg[i + 1];
    if (key == "scene") scene_file = value;
    else if (key == "table") table_id_ = value;
    else if (key == "plane") plane_z_ = freestand::parse_number(error, "fix rigid/convex", "plane", value);
    else if (key == "type") atom_type_ = static_cast<int>(freestand::parse_number(error, "fix rigid/convex", "type", value));
    else if (key == "timestep") {
      if (std::strcmp(value, "auto") != 0) error->all(FLERR, "fix rigid/convex: timestep takes 'auto'");
      auto_time_step_ = true;
    } else {
      bool known = false;  // stiffness, restitution, mu, law, spacing, layout, tangential_damping
      try {
        known = freestand::set_scene_default(defaults, key, value);
      } catch (const freestand::InputError &e) {
        error->all(FLERR, (std::string("fix rigid/convex: ") + e.what()).c_str());
      }
      if (!known) error->all(FLERR, ("fix rigid/convex: unknown keyword '" + key + "'").c_str());
    }
  }
  if (scene_file.empty()) error->all(FLERR, "fix rigid/convex: 'scene FILE' is required");
  for (int i = 3; i < narg; i += 2)
    if (!std::strcmp(arg[i], "plane") && !table_id_.empty())
      error->all(FLERR, "fix rigid/convex: with 'table', the plane height is fix shaketable's 'plane'");
  if (atom_type_ < 1 || atom_type_ > atom->ntypes)
    error->all(FLERR, "fix rigid/convex: 'type' must be an existing atom type");
}

void FixRigidConvex::build_templates() {
  for (std::size_t b = 0; b < scene_.bodies.size(); ++b) {
    const freestand::BodySpec &spec = scene_.bodies[b];
    BodyTemplate t{spec.name, freestand::PreparedMassProperties({spec.mass, spec.inertia}, spec.name)};
    // Against the table a body can land on any face (a toppled statue).
    t.table_nodes = freestand::make_plane_contact_nodes(spec.geometry, spec.com, spec.mass, spec.nodes);
    for (std::size_t k = 0; k < t.table_nodes.points(); ++k)
      acting_.resize(std::max<std::size_t>(acting_.size(),
                                           t.table_nodes.first_share[k + 1] - t.table_nodes.first_share[k]));
    t.bounding_radius = spec.geometry.bounding_radius(spec.com);
    // Against other bodies every exposed face can touch.
    t.contact_model = std::make_shared<freestand::BodyContactModel>(
        spec.geometry, spec.com, freestand::make_contact_nodes(spec.geometry, spec.nodes));
    t.bounding_radius = std::max(t.bounding_radius, t.contact_model->bounding_radius());
    templates_.push_back(std::move(t));
  }
}

// Each body becomes one atom at its centre of mass, on the rank that owns
// that point; tags follow the scene's order after any existing atoms.
void FixRigidConvex::create_bodies() {
  tagint local_max = 0;
  for (int i = 0; i < atom->nlocal; ++i) local_max = std::max(local_max, atom->tag[i]);
  tagint max_tag = 0;
  MPI_Allreduce(&local_max, &max_tag, 1, MPI_LMP_TAGINT, MPI_MAX, world);
  first_tag_ = max_tag + 1;

  for (std::size_t b = 0; b < scene_.bodies.size(); ++b) {
    const freestand::BodySpec &spec = scene_.bodies[b];
    const Vector3d com = spec.position + spec.orientation * spec.com;
    double x[3] = {com.x(), com.y(), com.z()};
    const bool mine = x[0] >= domain->sublo[0] && x[0] < domain->subhi[0] &&
                      x[1] >= domain->sublo[1] && x[1] < domain->subhi[1] &&
                      x[2] >= domain->sublo[2] && x[2] < domain->subhi[2];
    if (!mine) continue;
    atom->avec->create_atom(atom_type_, x);
    const int i = atom->nlocal - 1;
    atom->tag[i] = first_tag_ + static_cast<tagint>(b);
    atom->mask[i] = 1 | groupbit;
    atom->radius[i] = templates_[b].bounding_radius;
    atom->rmass[i] = spec.mass;
    for (int k = 0; k < 3; ++k) {
      atom->v[i][k] = spec.velocity[k];
      atom->omega[i][k] = spec.omega[k];
    }
    BodyState &s = state_[i];
    s.body = static_cast<int>(b);
    s.orientation = spec.orientation;
    s.angular_momentum = freestand::angular_momentum(spec.orientation, spec.omega, templates_[b].mass);
    s.table_history.assign(templates_[b].table_nodes.shares(), freestand::ContactHistory{});
  }
  atom->natoms += static_cast<bigint>(scene_.bodies.size());
  if (atom->map_style) {
    atom->nghost = 0;
    atom->map_init();
    atom->map_set();
  }
  note(lmp, std::to_string(scene_.bodies.size()) + " bodies created, tags " +
                std::to_string(first_tag_) + " to " +
                std::to_string(first_tag_ + static_cast<tagint>(scene_.bodies.size()) - 1));
}

int FixRigidConvex::setmask() {
  return FixConst::INITIAL_INTEGRATE | FixConst::PRE_FORCE | FixConst::POST_FORCE |
         FixConst::FINAL_INTEGRATE;
}

void FixRigidConvex::init() {
  table_ = nullptr;
  if (!table_id_.empty()) {
    const int ifix = modify->find_fix(table_id_.c_str());
    if (ifix >= 0) table_ = dynamic_cast<FixShakeTable *>(modify->fix[ifix]);
    if (!table_)
      error->all(FLERR, ("fix rigid/convex: '" + table_id_ + "' is not a fix shaketable").c_str());
    plane_z_ = table_->plane_height();  // one place states where the table is
  }
  check_time_step();
}

// The run's dt against the stability limit of each body resting on its base,
// and the accuracy fraction of it (docs/contact-law.md).
void FixRigidConvex::check_time_step() {
  try {
    const freestand::SceneTimeStep step = freestand::resting_time_step(scene_, *laws_);
    if (!step.law) return;
    // timestep auto: half the critical step (set before anything integrates
    // with it). With corner nodes and e = 0.05 free rocking is within 0.4 %
    // of Housner even at the critical step (docs/benchmarks.md, time to
    // accuracy); the factor 2 is margin for stacks and impacts the resting
    // eigenproblem does not see.
    if (auto_time_step_) update->dt = kAutoTimeStepFraction * step.critical;
    char text[256];
    snprintf(text, sizeof(text), "critical time step %.3g s; accurate restitution needs %.3g s or "
             "less; timestep is %.3g s%s", step.critical, step.recommended, update->dt,
             auto_time_step_ ? " (timestep auto)" : "");
    note(lmp, text);
    freestand::check_time_step(*step.law, update->dt, step.critical, "fix rigid/convex");
  } catch (const freestand::InputError &e) {
    error->all(FLERR, e.what());
  }
}

void FixRigidConvex::setup(int vflag) {
  in_setup_ = true;  // the ledger counts no dissipation or work for setup's force evaluation
  post_force(vflag);
  in_setup_ = false;
}

// Ghost bodies need their body index and orientation before pair convex
// computes contacts; positions and velocities come with LIGGGHTS' own comm.
// Only pair convex needs ghost orientations.
void FixRigidConvex::setup_pre_force(int) {
  if (force->pair_match("convex", 1)) comm->forward_comm_fix(this);
}

void FixRigidConvex::pre_force(int) {
  if (force->pair_match("convex", 1)) comm->forward_comm_fix(this);
}

int FixRigidConvex::pack_comm(int n, int *list, double *buf, int, int *) {
  int m = 0;
  for (int k = 0; k < n; ++k) {
    const BodyState &s = state_[list[k]];
    buf[m++] = s.body;
    buf[m++] = s.orientation.w();
    buf[m++] = s.orientation.x();
    buf[m++] = s.orientation.y();
    buf[m++] = s.orientation.z();
  }
  // LIGGGHTS 3.8 (like LAMMPS of its time) expects the number of values per
  // atom here and multiplies it by the atom counts of both sides itself.
  return comm_forward;
}

void FixRigidConvex::unpack_comm(int n, int first, double *buf) {
  int m = 0;
  for (int i = first; i < first + n; ++i) {
    BodyState &s = state_[i];
    s.body = static_cast<int>(buf[m]);
    s.orientation = Quaterniond(buf[m + 1], buf[m + 2], buf[m + 3], buf[m + 4]);
    m += 5;
  }
}

double FixRigidConvex::largest_radius() const {
  double largest = 0.0;
  for (const BodyTemplate &t : templates_) largest = std::max(largest, t.bounding_radius);
  return largest;
}

FixRigidConvex::PairHistory &FixRigidConvex::pair_history(int i, tagint partner) {
  for (PairHistory &h : state_[i].pairs)
    if (h.partner == partner) return h;
  state_[i].pairs.push_back(PairHistory{partner, {}});
  return state_[i].pairs.back();
}

void FixRigidConvex::initial_integrate(int) {
  const double dt = update->dt;
  double **x = atom->x, **v = atom->v, **f = atom->f, **omega = atom->omega, **torque = atom->torque;
  for (int i = 0; i < atom->nlocal; ++i) {
    BodyState &s = state_[i];
    if (s.body < 0) continue;
    const freestand::PreparedMassProperties &props = templates_[s.body].mass;
    freestand::RigidBodyState body{Vector3d(x[i]), Vector3d(v[i]), s.orientation, s.angular_momentum};
    freestand::initial_integrate(body, props, Vector3d(f[i]), Vector3d(torque[i]), dt);
    const Vector3d w = freestand::angular_velocity(body, props);
    for (int k = 0; k < 3; ++k) {
      x[i][k] = body.position[k];
      v[i][k] = body.velocity[k];
      omega[i][k] = w[k];
    }
    s.orientation = body.orientation;
    s.angular_momentum = body.angular_momentum;
  }
}

void FixRigidConvex::post_force(int) {
  table_contacts_ = 0;
  table_elastic_ = 0.0;
  for (int i = 0; i < atom->nlocal; ++i) {
    state_[i].table_force = state_[i].table_torque = Vector3d::Zero();
    if (state_[i].body >= 0) table_contact(i);
  }
}

FixRigidConvex::TablePlane FixRigidConvex::table_plane() const {
  TablePlane plane{Vector3d(0.0, 0.0, plane_z_), Vector3d::UnitZ(), Vector3d::Zero(), Vector3d::Zero()};
  if (!table_) return plane;
  const freestand::TableState table = table_->state();
  plane.point += table.displacement;
  plane.normal = table.orientation.toRotationMatrix().col(2);
  plane.velocity = table.velocity;
  plane.omega = table.angular_velocity;
  return plane;
}

// Contact nodes of body i against the table plane (through the table's
// reference point, normal R_table e_z), whose material point at x moves with
// v_table + omega_table x (x - reference point). With a table that does not
// rotate, the normal is exactly e_z and the terms in omega exactly zero.
void FixRigidConvex::table_contact(int i) {
  BodyState &s = state_[i];
  const BodyTemplate &t = templates_[s.body];
  const Vector3d com(atom->x[i]), v(atom->v[i]), w(atom->omega[i]);
  const TablePlane table = table_plane();
  const double plane = table.normal.dot(table.point);  // heights along the table normal
  const double height = table.normal.dot(com);
  // Lowest possible node: skip bodies far above the plane.
  if (height - atom->radius[i] > plane) {
    for (auto &h : s.table_history) h = freestand::ContactHistory{};
    return;
  }
  const Eigen::Matrix3d rotation = s.orientation.toRotationMatrix();
  const Vector3d up = rotation.transpose() * table.normal;  // table normal in the body frame
  const freestand::PlaneContactNodes &nodes = t.table_nodes;
  Vector3d force = Vector3d::Zero(), torque = Vector3d::Zero();
  const double dt = update->dt;
  for (std::size_t k = 0; k < nodes.points(); ++k) {
    const double overlap = plane - (height + up.dot(nodes.point[k]));
    const int first = nodes.first_share[k], end = nodes.first_share[k + 1];
    if (overlap <= 0.0) {
      for (int share = first; share < end; ++share) s.table_history[share] = freestand::ContactHistory{};
      continue;
    }
    const Vector3d r = rotation * nodes.point[k];
    const Vector3d table_velocity = table.velocity + table.omega.cross(com + r - table.point);
    const int acting = nodes.acting_shares(k, up, acting_.data());
    // A face that stops acting (the body rolled onto another face) forgets
    // its tangential spring.
    for (int share = first, a = 0; share < end; ++share)
      if (a < acting && acting_[a] == share) ++a;
      else s.table_history[share] = freestand::ContactHistory{};
    for (int a = 0; a < acting; ++a) {
      const int share = acting_[a];
      freestand::ContactPoint contact{table.normal, overlap, v + w.cross(r) - table_velocity,
                                      nodes.area[share], nodes.dashpot_mass[share]};
      const freestand::ContactForce result = laws_->table(s.body).compute(contact, dt, s.table_history[share]);
      force += result.force;
      torque += r.cross(result.force);
      ++table_contacts_;
      // Energy ledger: stored energy now; dissipation and the table's work
      // F . v_table dt with the velocities the law used (not during setup).
      table_elastic_ += result.elastic_energy();
      if (!in_setup_) {
        table_normal_dissipated_ += result.normal_dissipation;
        table_friction_dissipated_ += result.friction_dissipation;
        table_work_ += result.force.dot(table_velocity) * dt;
      }
    }
  }
  s.table_force = force;
  s.table_torque = torque;
  for (int k = 0; k < 3; ++k) {
    atom->f[i][k] += force[k];
    atom->torque[i][k] += torque[k];
  }
}

void FixRigidConvex::clear_pair_resultants() {
  for (int i = 0; i < atom->nlocal; ++i) state_[i].pair_force = state_[i].pair_torque = Vector3d::Zero();
}

void FixRigidConvex::add_pair_resultant(int i, const Vector3d &force, const Vector3d &torque) {
  state_[i].pair_force += force;
  state_[i].pair_torque += torque;
}

namespace {

// A point on the line of action of a force F with torque T about `com`:
// com + F x T / |F|^2 is the point of the line nearest the COM; with a
// plane (a point on it and its normal) the point where the line meets it.
Vector3d line_of_action(const Vector3d &com, const Vector3d &force, const Vector3d &torque,
                        const Vector3d *plane_point, const Vector3d &plane_normal) {
  const double f2 = force.squaredNorm();
  if (f2 == 0.0) return com;
  Vector3d point = com + force.cross(torque) / f2;
  const double along = plane_normal.dot(force);
  if (plane_point && along != 0.0) point += force * (plane_normal.dot(*plane_point - point) / along);
  return point;
}

}  // namespace

std::vector<FixRigidConvex::ContactResultant> FixRigidConvex::gather_contact_resultants() {
  const std::size_t n = templates_.size();
  constexpr int kRow = 12;  // table force, table point, pair force, pair point
  std::vector<double> local(kRow * n, 0.0), global(kRow * n, 0.0);
  const TablePlane table = table_plane();
  for (int i = 0; i < atom->nlocal; ++i) {
    const BodyState &s = state_[i];
    if (s.body < 0) continue;
    const Vector3d com(atom->x[i]);
    const Vector3d rows[4] = {s.table_force, line_of_action(com, s.table_force, s.table_torque, &table.point, table.normal),
                              s.pair_force, line_of_action(com, s.pair_force, s.pair_torque, nullptr, table.normal)};
    for (int r = 0; r < 4; ++r)
      for (int k = 0; k < 3; ++k) local[kRow * s.body + 3 * r + k] = rows[r][k];
  }
  MPI_Allreduce(local.data(), global.data(), static_cast<int>(global.size()), MPI_DOUBLE, MPI_SUM, world);
  std::vector<ContactResultant> out(n);
  for (std::size_t b = 0; b < n; ++b) {
    const double *row = &global[kRow * b];
    out[b] = {Vector3d(row), Vector3d(row + 3), Vector3d(row + 6), Vector3d(row + 9)};
  }
  return out;
}

void FixRigidConvex::final_integrate() {
  const double dt = update->dt;
  double **v = atom->v, **f = atom->f, **omega = atom->omega, **torque = atom->torque;
  for (int i = 0; i < atom->nlocal; ++i) {
    BodyState &s = state_[i];
    if (s.body < 0) continue;
    const freestand::PreparedMassProperties &props = templates_[s.body].mass;
    freestand::RigidBodyState body{Vector3d(atom->x[i]), Vector3d(v[i]), s.orientation,
                                   s.angular_momentum};
    freestand::final_integrate(body, props, Vector3d(f[i]), Vector3d(torque[i]), dt);
    const Vector3d w = freestand::angular_velocity(body, props);
    for (int k = 0; k < 3; ++k) {
      v[i][k] = body.velocity[k];
      omega[i][k] = w[k];
    }
    s.angular_momentum = body.angular_momentum;
  }
}

double FixRigidConvex::compute_vector(int index) {
  double local[kLedgerSize], total[kLedgerSize];
  ledger_local(local);
  MPI_Allreduce(local, total, kLedgerSize, MPI_DOUBLE, MPI_SUM, world);
  if (index == kLedgerSize - 1)
    return total[0] + total[2] + total[3] + total[4] + total[5] - total[6];
  return total[index];
}

// This rank's share of the global vector (its last entry is left 0).
// Gravity: the acceleration of the first fix gravity, else the scene's
// gravity along -z; the potential is -m g . x_com (zero at the origin).
void FixRigidConvex::ledger_local(double out[kLedgerSize]) {
  std::fill(out, out + kLedgerSize, 0.0);
  Vector3d g(0.0, 0.0, -scene_.gravity);
  for (int k = 0; k < modify->nfix; ++k)
    if (auto *gravity = dynamic_cast<FixGravity *>(modify->fix[k])) {
      double acceleration[3];
      gravity->get_gravity(acceleration);
      g = Vector3d(acceleration[0], acceleration[1], acceleration[2]);
      break;
    }
  for (int i = 0; i < atom->nlocal; ++i) {
    const BodyState &s = state_[i];
    if (s.body < 0) continue;
    freestand::RigidBodyState body{Vector3d(atom->x[i]), Vector3d(atom->v[i]), s.orientation,
                                   s.angular_momentum};
    out[0] += freestand::kinetic_energy(body, templates_[s.body].mass);
    out[2] -= templates_[s.body].mass.mass() * g.dot(Vector3d(atom->x[i]));
  }
  out[1] = table_contacts_;
  out[3] = table_elastic_;
  out[4] = table_normal_dissipated_;
  out[5] = table_friction_dissipated_;
  out[6] = table_work_;
  if (auto *pair = dynamic_cast<PairConvex *>(force->pair)) {
    const PairConvex::EnergyLedger &ledger = pair->ledger();
    out[3] += ledger.elastic;
    out[4] += ledger.normal_dissipated;
    out[5] += ledger.friction_dissipated;
  }
}

// ---- per-atom storage that follows atoms between ranks ----------------------

void FixRigidConvex::grow_arrays(int nmax) { state_.resize(nmax); }

void FixRigidConvex::copy_arrays(int i, int j, int) { state_[j] = state_[i]; }


// Layout: body, quaternion (4), angular momentum (3), node count, histories.
int FixRigidConvex::pack_exchange(int i, double *buf) {
  const BodyState &s = state_[i];
  int m = 0;
  buf[m++] = s.body;
  for (double q : {s.orientation.w(), s.orientation.x(), s.orientation.y(), s.orientation.z()})
    buf[m++] = q;
  for (int k = 0; k < 3; ++k) buf[m++] = s.angular_momentum[k];
  buf[m++] = static_cast<double>(s.table_history.size());
  for (const auto &h : s.table_history) {
    std::copy(h.xi, h.xi + 3, buf + m);
    buf[m + 3] = h.sliding;
    m += freestand::kContactHistorySize;
  }
  buf[m++] = static_cast<double>(s.pairs.size());
  for (const PairHistory &pair : s.pairs) {
    buf[m++] = static_cast<double>(pair.partner);
    buf[m++] = static_cast<double>(pair.entries.size());
    for (const auto &entry : pair.entries) {
      buf[m++] = static_cast<double>(entry.first);
      std::copy(entry.second.xi, entry.second.xi + 3, buf + m);
      buf[m + 3] = entry.second.sliding;
      m += freestand::kContactHistorySize;
    }
  }
  return m;
}

int FixRigidConvex::unpack_exchange(int nlocal, double *buf) {
  BodyState &s = state_[nlocal];
  int m = 0;
  s.body = static_cast<int>(buf[m++]);
  s.orientation = Quaterniond(buf[m], buf[m + 1], buf[m + 2], buf[m + 3]);
  m += 4;
  s.angular_momentum = Vector3d(buf[m], buf[m + 1], buf[m + 2]);
  m += 3;
  s.table_history.resize(static_cast<std::size_t>(buf[m++]));
  for (auto &h : s.table_history) {
    std::copy(buf + m, buf + m + 3, h.xi);
    h.sliding = buf[m + 3];
    m += freestand::kContactHistorySize;
  }
  s.pairs.resize(static_cast<std::size_t>(buf[m++]));
  for (PairHistory &pair : s.pairs) {
    pair.partner = static_cast<tagint>(buf[m++]);
    pair.entries.resize(static_cast<std::size_t>(buf[m++]));
    for (auto &entry : pair.entries) {
      entry.first = static_cast<std::uint64_t>(buf[m++]);
      std::copy(buf + m, buf + m + 3, entry.second.xi);
      entry.second.sliding = buf[m + 3];
      m += freestand::kContactHistorySize;
    }
  }
  return m;
}

// ---- restart files: the same layout as exchange, behind a length ---------------

int FixRigidConvex::pack_restart(int i, double *buf) {
  const int m = pack_exchange(i, buf + 1) + 1;
  buf[0] = m;
  return m;
}

void FixRigidConvex::unpack_restart(int nlocal, int nth) {
  double *extra = atom->extra[nlocal];
  int m = 0;
  for (int k = 0; k < nth; ++k) m += static_cast<int>(extra[m]);
  unpack_exchange(nlocal, extra + m + 1);
}

int FixRigidConvex::size_restart(int nlocal) {
  // length, body, quaternion (4), angular momentum (3), node count, histories,
  // pair count, per pair: partner, entry count, per entry: key and history
  const BodyState &s = state_[nlocal];
  int size = 1 + 9 + freestand::kContactHistorySize * static_cast<int>(s.table_history.size()) + 1;
  for (const PairHistory &pair : s.pairs)
    size += 2 + (1 + freestand::kContactHistorySize) * static_cast<int>(pair.entries.size());
  return size;
}

int FixRigidConvex::maxsize_restart() {
  int most = 0;
  for (int i = 0; i < atom->nlocal; ++i) most = std::max(most, size_restart(i));
  return most;
}

void FixRigidConvex::write_restart(FILE *fp) {
  if (comm->me != 0) return;
  const double list[1] = {static_cast<double>(first_tag_)};
  const int size = sizeof(list);
  fwrite(&size, sizeof(int), 1, fp);
  fwrite(list, sizeof(double), 1, fp);
}

void FixRigidConvex::restart(char *buf) {
  first_tag_ = static_cast<tagint>(reinterpret_cast<double *>(buf)[0]);
}

// ---- RigidBodySource ---------------------------------------------------------

int FixRigidConvex::max_tag() { return static_cast<int>(scene_.bodies.size()); }

void FixRigidConvex::gather_poses(std::vector<freestand::BodyPose> &poses,
                                  std::vector<char> &present) {
  PoseGatherer gatherer(max_tag());
  for (int i = 0; i < atom->nlocal; ++i) {
    const BodyState &s = state_[i];
    if (s.body < 0) continue;
    const double quaternion[4] = {s.orientation.w(), s.orientation.x(), s.orientation.y(),
                                  s.orientation.z()};
    gatherer.add(s.body, atom->x[i], quaternion, atom->v[i], atom->omega[i]);
  }
  gatherer.gather(world, poses, present);
}

std::vector<freestand::ChannelBody> FixRigidConvex::describe_bodies() {
  std::vector<freestand::ChannelBody> bodies;
  for (std::size_t b = 0; b < scene_.bodies.size(); ++b) {
    const freestand::BodySpec &spec = scene_.bodies[b];
    freestand::ChannelBody body;
    body.name = spec.name;
    body.index = static_cast<int>(b);
    body.geometry = {spec.com, spec.height};
    body.support = -1;
    for (std::size_t k = 0; k < scene_.bodies.size(); ++k)
      if (scene_.bodies[k].name == spec.supported_by) body.support = static_cast<int>(k);
    body.source_frame_is_own = true;  // orientations here are the body's own frame
    bodies.push_back(body);
  }
  return bodies;
}
