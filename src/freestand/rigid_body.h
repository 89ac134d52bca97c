#ifndef FREESTAND_RIGID_BODY_H
#define FREESTAND_RIGID_BODY_H

// Rigid-body kernel of `fix rigid/convex`: mass properties, state and the
// time integrator, free of LIGGGHTS types. One LIGGGHTS atom carries one body,
// placed at the body's centre of mass.
//
// The integrator is the second-order, symplectic, time-reversible splitting
// of docs/rigid-body-integration.md, cut into the two phases of LIGGGHTS'
// velocity Verlet:
//
//   initial_integrate (before forces):  v += F dt/(2m);  L += tau dt/2;
//                                       x += v dt;  free-rotor rotation for dt
//   final_integrate   (after forces):   v += F dt/(2m);  L += tau dt/2
//
// The free rotor is split as H = |L|^2/(2 I2) + (1/I1 - 1/I2) L1^2/2 +
// (1/I3 - 1/I2) L3^2/2 (principal moments I1 <= I2 <= I3): an exact rotation
// about L at rate |L|/I2 composed with a Strang splitting of the two
// remaining principal-axis rotations. It is exact for axisymmetric bodies
// (I1 = I2 or I2 = I3) and conserves the world-frame angular momentum exactly.
//
// Units are SI: kg, m, s, N, N m, kg m^2.

#include <Eigen/Geometry>
#include <string_view>

namespace freestand {

// Mass and inertia as given by the user or computed from geometry. (Not
// named MassProperties: that is convex_shape.h's geometric result, which also
// carries volume and COM; pass {m.mass, m.inertia} from it, with the inertia
// taken about the COM.)
struct MassAndInertia {
  double mass = 0.0;                                  // kg
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // about the COM, body frame (kg m^2)
};

// MassAndInertia, validated and decomposed once per body type. Construction
// throws InputError unless: the mass is finite and > 0; the inertia tensor is
// finite, symmetric (to 1e-12 of its largest entry; it is then symmetrised),
// positive definite, and its principal moments satisfy the triangle
// inequality I1 + I2 >= I3 (to 1e-10 I3, round-off in a geometric
// computation of a lamina), which every real mass distribution does.
class PreparedMassProperties {
 public:
  // `name` prefixes error messages, e.g. "rigid body 'drum3'".
  explicit PreparedMassProperties(const MassAndInertia& given,
                                  std::string_view name = "rigid body");

  double mass() const { return mass_; }                                    // kg
  double inverse_mass() const { return inverse_mass_; }                    // 1/kg
  const Eigen::Matrix3d& inertia() const { return inertia_; }              // body frame
  const Eigen::Matrix3d& inverse_inertia() const { return inverse_inertia_; }  // body frame
  // I1 <= I2 <= I3 (kg m^2).
  const Eigen::Vector3d& principal_moments() const { return principal_moments_; }
  // Rotation from the principal frame (axis k along the eigenvector of I_k)
  // to the body frame; a proper rotation. Its matrix holds the principal
  // axes, in body coordinates, as columns.
  const Eigen::Quaterniond& principal_to_body() const { return principal_to_body_; }

  // Free-rotor constants: 1/I2, 1/I1 - 1/I2 (>= 0), 1/I3 - 1/I2 (<= 0).
  double inverse_i2() const { return inverse_i2_; }
  double c1() const { return c1_; }
  double c3() const { return c3_; }

 private:
  double mass_, inverse_mass_;
  Eigen::Matrix3d inertia_, inverse_inertia_;
  Eigen::Vector3d principal_moments_;
  Eigen::Quaterniond principal_to_body_;
  double inverse_i2_, c1_, c3_;
};

// State of one rigid body.
struct RigidBodyState {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // centre of mass, world (m)
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // of the centre of mass, world (m/s)
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // body frame -> world, unit
  Eigen::Vector3d angular_momentum = Eigen::Vector3d::Zero();  // about the COM, world (kg m^2/s)
};

// Angular velocity (rad/s), world frame: R I^-1 R^T L.
Eigen::Vector3d angular_velocity(const RigidBodyState& state, const PreparedMassProperties& props);

// Angular velocity (rad/s) in the body frame: I^-1 R^T L.
Eigen::Vector3d body_angular_velocity(const RigidBodyState& state,
                                      const PreparedMassProperties& props);

// World-frame angular momentum of a body with the given orientation spinning
// at omega (world, rad/s): R I R^T omega. For setting initial conditions.
Eigen::Vector3d angular_momentum(const Eigen::Quaterniond& orientation,
                                 const Eigen::Vector3d& omega,
                                 const PreparedMassProperties& props);

double translational_kinetic_energy(const RigidBodyState& state,
                                    const PreparedMassProperties& props);  // J
double rotational_kinetic_energy(const RigidBodyState& state,
                                 const PreparedMassProperties& props);  // J
double kinetic_energy(const RigidBodyState& state, const PreparedMassProperties& props);  // J

// Velocity (world) of the material point of the body that is at world
// position p: v + omega x (p - x). The contact code calls the first form with
// omega = angular_velocity(state, props) computed once per body.
inline Eigen::Vector3d point_velocity(const Eigen::Vector3d& com_position,
                                      const Eigen::Vector3d& com_velocity,
                                      const Eigen::Vector3d& omega, const Eigen::Vector3d& p) {
  return com_velocity + omega.cross(p - com_position);
}
Eigen::Vector3d point_velocity(const RigidBodyState& state, const PreparedMassProperties& props,
                               const Eigen::Vector3d& p);

// First phase of a step of length dt (force, torque: world frame, at the
// start of the step; torque about the COM): half kick, drift, free rotor.
// The orientation is left normalised. No allocation, no exceptions.
void initial_integrate(RigidBodyState& state, const PreparedMassProperties& props,
                       const Eigen::Vector3d& force, const Eigen::Vector3d& torque,
                       double dt) noexcept;

// Second phase (force, torque: at the end of the step): half kick.
void final_integrate(RigidBodyState& state, const PreparedMassProperties& props,
                     const Eigen::Vector3d& force, const Eigen::Vector3d& torque,
                     double dt) noexcept;

// Free-rotor sub-step alone: rotates `orientation` (body -> world) for dt
// with the world-frame angular momentum L held fixed. Symmetric: a step of
// -dt undoes a step of dt (to round-off). Normalises `orientation`.
void free_rotor_step(Eigen::Quaterniond& orientation, const Eigen::Vector3d& L,
                     const PreparedMassProperties& props, double dt) noexcept;

}  // namespace freestand

#endif
