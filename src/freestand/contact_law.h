#ifndef FREESTAND_CONTACT_LAW_H
#define FREESTAND_CONTACT_LAW_H

// Penalty contact law of one contact NODE: a vertex or face-grid point of one
// body, with tributary area A, pressed into a face of another body or into the
// shake-table plane. Used by `pair_style convex` and by the body-vs-table
// contact. docs/contact-law.md is the precise statement: every equation, the
// units, the defaults, the stick/slip state machine, the restitution mapping
// and the critical time step.
//
// Stiffness and damping are PER UNIT CONTACT AREA, so a face's total
// stiffness is the sum over its nodes and does not depend on how finely the
// face is sampled:
//
//   linear:  F_el = k_a A delta                          (k_a in N/m^3)
//   Hertz:   F_el = k_a A delta^{3/2} / sqrt(delta_ref)  (Winkler bed of Hertz springs)
//   dashpot: linear 2 zeta sqrt(k_a A m_eff) ddelta/dt,
//            Hertz  sqrt(5) zeta sqrt(k_h A m_eff) delta^{1/4} ddelta/dt
//   F_n = max(0, F_el + F_d)      (never attractive)
//
// Tangential: an elastic spring on the accumulated tangential displacement
// xi (history, kept in the current tangent plane), k_t = kappa * (normal
// tangent stiffness), optional dashpot, capped by Coulomb friction with static
// mu_s and velocity-dependent kinetic mu(v) = mu_k + (mu_s - mu_k) exp(-d_c |v_t|).
//
// SI units throughout.

#include <Eigen/Core>
#include <limits>
#include <optional>
#include <type_traits>

namespace freestand {

enum class NormalLaw {
  kLinear,  // p = k_a delta
  kHertz,   // p = k_a delta_ref (delta / delta_ref)^{3/2}
};

// Mindlin's ratio 2(1 - nu)/(2 - nu) of tangential to normal (tangent)
// stiffness for nu = 0.25 (stone, concrete, metals are 0.2 to 0.3): 6/7.
inline constexpr double kDefaultTangentialStiffnessRatio = 6.0 / 7.0;

// What the user states about one interface (one pair of materials or bodies).
// ContactLaw's constructor validates it and throws InputError naming the field.
struct ContactParams {
  NormalLaw law = NormalLaw::kLinear;
  // k_a > 0, N/m^3: pressure per unit overlap. From the recording format's
  // `contact_stiffness` K (N/m, whole face in contact): k_a = K / A_face. For
  // Hertz, K is then the secant stiffness of the face at delta = delta_ref.
  double stiffness_per_area = 0.0;
  // delta_ref > 0, m (Hertz only): overlap at which the Hertz pressure equals
  // the linear law's k_a delta. Required for Hertz, ignored for linear.
  double hertz_reference_overlap = 0.0;
  // Normal damping: exactly one of the two. damping_ratio >= 0 (zeta;
  // > 1 is allowed, overdamped); restitution in (0, 1] (e of a flat face-on
  // impact, converted to zeta by damping_ratio_from_restitution()).
  std::optional<double> damping_ratio;
  std::optional<double> restitution;
  // kappa > 0: k_t / (normal tangent stiffness). Default 6/7 (nu = 0.25).
  double tangential_stiffness_ratio = kDefaultTangentialStiffnessRatio;
  // zeta_t >= 0: tangential dashpot c_t = 2 zeta_t sqrt(k_t m_eff), acting while stuck.
  double tangential_damping_ratio = 0.0;
  // Coulomb friction, 0 <= mu_k <= mu_s. Both must be set (a single `mu`
  // means mu_s = mu_k = mu).
  double mu_s = std::numeric_limits<double>::quiet_NaN();
  double mu_k = std::numeric_limits<double>::quiet_NaN();
  // d_c >= 0, s/m: decay of friction with sliding speed,
  // mu(v) = mu_k + (mu_s - mu_k) exp(-d_c |v_t|) (LS-DYNA FS, FD, DC).
  // d_c = 0 means a plain static/kinetic switch: mu_k while sliding.
  double friction_decay = 0.0;
};

// Per-contact history: 4 doubles, trivially copyable, so LIGGGHTS can keep it
// in its per-contact double array (copy with std::memcpy). A new contact
// starts from the value-initialised history (all zero).
struct ContactHistory {
  double xi[3] = {0.0, 0.0, 0.0};  // accumulated tangential displacement (m), world frame
  double sliding = 0.0;            // 1 while sliding, 0 while stuck

  bool is_sliding() const { return sliding != 0.0; }
  Eigen::Vector3d displacement() const { return Eigen::Vector3d(xi[0], xi[1], xi[2]); }
};
inline constexpr int kContactHistorySize = 4;  // doubles
static_assert(std::is_trivially_copyable_v<ContactHistory>);
static_assert(sizeof(ContactHistory) == kContactHistorySize * sizeof(double));

// One node in contact, as the caller (pair style, table contact) sees it.
struct ContactPoint {
  Eigen::Vector3d normal;    // unit normal from the other surface toward this node's body
  double overlap = 0.0;      // delta >= 0 (m); <= 0 means no contact
  Eigen::Vector3d velocity;  // velocity of the node minus that of the other surface there (m/s), world
  double area = 0.0;         // tributary area A of the node (m^2)
  // m_eff (kg), used by the dashpots only. Recommended: m_red A / A_face, with
  // m_red the reduced mass of the two bodies (the body mass against the
  // table) and A_face the area of the face being pressed (sum of its nodes'
  // A): then the dashpots are per unit area too and a flat face-on impact of
  // the whole face has exactly the target restitution.
  double effective_mass = 0.0;
};

// What the law returns: the force on the node's body (the other body gets
// -force, applied at the same point).
struct ContactForce {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();       // total (N), world
  Eigen::Vector3d tangential = Eigen::Vector3d::Zero();  // friction part of it (N), world
  double normal = 0.0;                                   // F_n >= 0 (N): force = F_n n + tangential
  bool sliding = false;                                  // state after this step
  // Energy ledger of this step (docs/fix_rigid_convex.md, "Energy ledger").
  // Cheap (a few flops); callers that do not keep a ledger ignore them.
  double normal_energy = 0.0;      // elastic energy of the normal spring after the step (J):
                                   // linear k_a A delta^2 / 2, Hertz (2/5) k_h A delta^{5/2}
  double tangential_energy = 0.0;  // elastic energy of the tangential spring after it (J): k_t |xi|^2 / 2
  double normal_dissipation = 0.0;    // by the normal dashpot in this step (J), >= 0:
                                      // -(F_n - F_el) v_n dt (the clamp included)
  double friction_dissipation = 0.0;  // by friction and the tangential dashpot in this step (J):
                                      // stick c_t |v_t|^2 dt; slip -F_t . v_t dt + (E_t,old - E_t,new)
  double elastic_energy() const { return normal_energy + tangential_energy; }
};

// Coefficient of restitution of a single-dof impact of the law with damping
// ratio zeta >= 0, with the tensile force clamped (contact ends when F_n
// reaches 0, Schwager & Poeschel 2007). Same for linear and Hertz.
//   zeta < 1:  e = exp(-x (pi - 2 atan x)),   x = zeta / sqrt(1 - zeta^2)
//   zeta = 1:  e = exp(-2)
//   zeta > 1:  e = exp(-2 atanh(y) / y),      y = sqrt(1 - 1/zeta^2)
double restitution_from_damping_ratio(double zeta);
// Its inverse, for e in (0, 1] (InputError otherwise); relative accuracy 1e-14.
double damping_ratio_from_restitution(double e);
// Reference only: the textbook restitution exp(-pi zeta / sqrt(1 - zeta^2))
// of a spring-dashpot WITHOUT the clamp (0 for zeta >= 1).
double unclamped_restitution(double zeta);

// Rotates a history displacement into the tangent plane of the unit normal
// n: removes the normal component and rescales to the old magnitude (as
// LIGGGHTS/LAMMPS do). A displacement (nearly) parallel to n becomes zero.
Eigen::Vector3d rotate_into_tangent_plane(const Eigen::Vector3d& xi, const Eigen::Vector3d& n);

// Linearised stiffness and damping of one node (or of a whole face, with
// A = A_face and m_eff = m_red) at overlap delta, for time-step estimates.
struct ContactLinearization {
  double normal_stiffness = 0.0;      // dF_el/ddelta (N/m)
  double tangential_stiffness = 0.0;  // k_t (N/m)
  double normal_damping = 0.0;        // dF_d/d(ddelta/dt) (N s/m)
  double tangential_damping = 0.0;    // c_t (N s/m)
};

// A validated ContactParams with its derived constants. Immutable; compute()
// is const, allocation-free and thread-safe.
class ContactLaw {
 public:
  explicit ContactLaw(const ContactParams& params);  // throws InputError

  // Force on the node's body for one step of length dt > 0; updates history.
  // overlap <= 0 returns zero force and resets the history. area and
  // effective_mass must be > 0 (not checked here: hot path).
  ContactForce compute(const ContactPoint& point, double dt, ContactHistory& history) const;

  // mu(v) while sliding: mu_k + (mu_s - mu_k) exp(-d_c |v|); mu_k when d_c = 0.
  double kinetic_friction(double sliding_speed) const;

  // Elastic normal force of a node of area A at overlap delta (N).
  double elastic_force(double area, double overlap) const;
  // Elastic energy of the normal spring of a node of area A at overlap delta
  // (J): linear k_a A delta^2 / 2, Hertz (2/5) k_h A delta^{5/2}; 0 for delta <= 0.
  double elastic_energy(double area, double overlap) const;
  ContactLinearization linearize(double area, double effective_mass, double overlap) const;

  // Overlap of a face of area A_face pressed by a steady load W (N): the
  // static overlap, linear W / (k_a A), Hertz delta_ref (W / (k_a A delta_ref))^{2/3}.
  double overlap_under_load(double face_area, double load) const;
  // Largest overlap of an undamped flat face-on impact of mass m at speed v
  // (an upper bound for the damped one): linear v sqrt(m / (k_a A)),
  // Hertz (5 m v^2 / (4 k_h A))^{2/5}.
  double impact_overlap(double face_area, double mass, double speed) const;

  const ContactParams& params() const { return params_; }
  double damping_ratio() const { return zeta_; }  // zeta (given, or from restitution)
  // Restitution of a flat face-on impact (exactly what was asked, if given).
  double restitution() const { return restitution_from_damping_ratio(zeta_); }
  // Damping ratio of small oscillations about any overlap: zeta for linear,
  // zeta sqrt(5/6) for Hertz (its dashpot and the square root of its tangent
  // stiffness both scale as delta^{1/4}, so the ratio is the same at every overlap).
  double linearized_damping_ratio() const;
  double hertz_stiffness() const { return k_h_; }  // k_a / sqrt(delta_ref) (N/m^{7/2}); 0 for linear

 private:
  ContactParams params_;
  double zeta_ = 0.0;     // normal damping ratio
  double k_h_ = 0.0;      // Hertz: k_a / sqrt(delta_ref)
  double c_norm_ = 0.0;   // linear: 2 zeta; Hertz: sqrt(5) zeta (alpha)
  double c_tang_ = 0.0;   // 2 zeta_t
};

}  // namespace freestand

#endif
