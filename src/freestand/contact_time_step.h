#ifndef FREESTAND_CONTACT_TIME_STEP_H
#define FREESTAND_CONTACT_TIME_STEP_H

// Critical (largest stable) time step of the penalty contact law of
// contact_law.h under LIGGGHTS' velocity Verlet, so that a fix can print it
// and refuse a time step that is too large. docs/contact-law.md explains the
// choices; in short:
//
//  * A linear oscillator (stiffness k, mass m, damping ratio zeta) integrated
//    by velocity Verlet with the force evaluated from the half-step velocity
//    (LIGGGHTS' order) is stable iff dt <= 2/omega (sqrt(1 + zeta^2) - zeta),
//    omega = sqrt(k/m).
//  * Because stiffness is per unit area, the node count does not enter: a
//    face's stiffness matrix is the sum over its nodes, which converges to
//    the integral over the face. The stiffest configuration of a body is a
//    whole face in contact (adding springs only raises frequencies, so a
//    single-node or edge impact is never stiffer than the face it belongs
//    to), and its highest mode is often NOT the vertical bounce: for a block
//    it is a rocking-sliding mode, 1.78 times faster for a 0.4 x 0.6 x 1 m box.
//    resting_critical_time_step() solves that eigenproblem exactly (6 or 12
//    degrees of freedom); face_critical_time_step() is the bounce-mode formula.

#include <Eigen/Core>
#include <string_view>
#include <vector>

#include "freestand/contact_law.h"

namespace freestand {

// Stable step of velocity Verlet / central differences for a linear
// oscillator: 2/omega (sqrt(1 + zeta^2) - zeta), omega = sqrt(k/m). k, m > 0,
// zeta >= 0, else InputError.
double oscillator_critical_time_step(double stiffness, double mass, double damping_ratio);

// Bounce-mode limit of mass m on a face of area A_face at overlap delta (the
// Hertz stiffness grows with delta: pass the largest overlap expected, e.g.
// max(overlap_under_load, impact_overlap)): the smaller of the normal mode
// (k_n, linearised zeta) and the tangential mode (kappa k_n, zeta_t). Exact
// for a point mass; for a rigid body it ignores rotation (see
// resting_critical_time_step).
double face_critical_time_step(const ContactLaw& law, double face_area, double mass,
                               double overlap);

// Mass and inertia of one rigid body, world frame.
struct ContactBody {
  double mass = 0.0;                                  // kg > 0
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // about the COM, world frame (kg m^2), SPD
  Eigen::Vector3d com = Eigen::Vector3d::Zero();      // centre of mass, world (m)
};

// Smallest effective mass of the point r (relative to the COM, world frame)
// over all directions: 1 / lambda_max(I/m + [r]x I^-1 [r]x^T) (kg).
double smallest_point_mass(const ContactBody& body, const Eigen::Vector3d& r);

// The linearised modes of body `a` held by contact nodes (world positions,
// tributary areas) against a fixed surface (b == nullptr: the table) or
// against body b, all nodes at overlap delta with unit normal n (from the
// other surface toward a), and every node's dashpot built with the recommended
// m_eff = m_red A_i / sum(A) (contact_law.h).
struct ContactModes {
  double omega_max = 0.0;      // highest natural frequency (rad/s)
  double time_step = 0.0;      // min over modes of 2/omega_j (sqrt(1 + zeta_j^2) - zeta_j) (s)
  double damping_ratio = 0.0;  // zeta_j of the mode giving time_step
  double omega = 0.0;          // omega_j of that mode (rad/s)
};
ContactModes resting_critical_time_step(const ContactLaw& law,
                                        const std::vector<Eigen::Vector3d>& points,
                                        const std::vector<double>& areas,
                                        const Eigen::Vector3d& normal, double overlap,
                                        const ContactBody& a, const ContactBody* b = nullptr);

// Fraction of the critical step a run should use so that the restitution of
// a flat impact is within 1 % of its target (measured, docs/contact-law.md):
// 0.02 for the linear law, 0.1 for Hertz. LIGGGHTS' velocity Verlet feeds
// the dashpot the half-step velocity, which biases e upward at first order in
// dt: +3 % at 0.1 of the critical step for the linear law, whose dashpot acts
// at full strength from the first instant of contact; the Hertz dashpot
// vanishes with the overlap and the bias is 5 times smaller.
inline constexpr double kLinearTimeStepFraction = 0.02;
inline constexpr double kHertzTimeStepFraction = 0.1;
double recommended_time_step_fraction(const ContactLaw& law);

// Throws InputError when dt > dt_critical (the run would blow up), saying
// what to use, e.g. "pair convex: timestep 3e-05 s is above the critical
// time step 2e-05 s of the contact law and the run would blow up; use
// timestep 4e-07 or less (...)". dt must be > 0.
void check_time_step(const ContactLaw& law, double dt, double dt_critical, std::string_view what);

}  // namespace freestand

#endif
