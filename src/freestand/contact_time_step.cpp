#include "freestand/contact_time_step.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "freestand/input_error.h"

namespace freestand {

namespace {

Eigen::Matrix3d cross_matrix(const Eigen::Vector3d& r) {
  Eigen::Matrix3d m;
  m << 0.0, -r.z(), r.y(), r.z(), 0.0, -r.x(), -r.y(), r.x(), 0.0;
  return m;  // m * v = r x v
}

void require_body(const ContactBody& body, const char* which) {
  if (!(std::isfinite(body.mass) && body.mass > 0.0))
    throw InputError(fmt::format("contact time step: mass of body {} must be > 0, got {}",
                                 which, body.mass));
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(body.inertia);
  if (!body.inertia.allFinite() || eig.info() != Eigen::Success || !(eig.eigenvalues()(0) > 0.0))
    throw InputError(fmt::format(
        "contact time step: inertia of body {} must be symmetric positive definite", which));
}

}  // namespace

double oscillator_critical_time_step(double stiffness, double mass, double damping_ratio) {
  if (!(std::isfinite(stiffness) && stiffness > 0.0))
    throw InputError(fmt::format("critical time step: stiffness must be > 0, got {}", stiffness));
  if (!(std::isfinite(mass) && mass > 0.0))
    throw InputError(fmt::format("critical time step: mass must be > 0, got {}", mass));
  if (!(std::isfinite(damping_ratio) && damping_ratio >= 0.0))
    throw InputError(
        fmt::format("critical time step: damping ratio must be >= 0, got {}", damping_ratio));
  const double omega = std::sqrt(stiffness / mass);
  // sqrt(1 + z^2) - z = 1 / (sqrt(1 + z^2) + z), without cancellation.
  return 2.0 / (omega * (std::sqrt(1.0 + damping_ratio * damping_ratio) + damping_ratio));
}

double face_critical_time_step(const ContactLaw& law, double face_area, double mass,
                               double overlap) {
  if (!(std::isfinite(face_area) && face_area > 0.0))
    throw InputError(fmt::format("critical time step: face area must be > 0, got {}", face_area));
  if (law.params().law == NormalLaw::kHertz && !(std::isfinite(overlap) && overlap > 0.0))
    throw InputError(fmt::format(
        "critical time step: the Hertz law needs the largest expected overlap (> 0), got {}",
        overlap));
  const ContactLinearization lin = law.linearize(face_area, mass, overlap);
  const double normal =
      oscillator_critical_time_step(lin.normal_stiffness, mass, law.linearized_damping_ratio());
  const double tangential = oscillator_critical_time_step(
      lin.tangential_stiffness, mass, law.params().tangential_damping_ratio);
  return std::min(normal, tangential);
}

double smallest_point_mass(const ContactBody& body, const Eigen::Vector3d& r) {
  require_body(body, "a");
  const Eigen::Matrix3d rx = cross_matrix(r);
  const Eigen::Matrix3d mobility = Eigen::Matrix3d::Identity() / body.mass +
                                   rx * body.inertia.inverse() * rx.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(mobility, Eigen::EigenvaluesOnly);
  return 1.0 / eig.eigenvalues()(2);
}

ContactModes resting_critical_time_step(const ContactLaw& law,
                                        const std::vector<Eigen::Vector3d>& points,
                                        const std::vector<double>& areas,
                                        const Eigen::Vector3d& normal, double overlap,
                                        const ContactBody& a, const ContactBody* b) {
  if (points.empty() || points.size() != areas.size())
    throw InputError(fmt::format(
        "contact time step: need as many areas as points (> 0), got {} points and {} areas",
        points.size(), areas.size()));
  if (!(std::abs(normal.norm() - 1.0) < 1e-9))
    throw InputError("contact time step: the normal must be a unit vector");
  if (law.params().law == NormalLaw::kHertz && !(std::isfinite(overlap) && overlap > 0.0))
    throw InputError(fmt::format(
        "contact time step: the Hertz law needs the largest expected overlap (> 0), got {}",
        overlap));
  require_body(a, "a");
  if (b) require_body(*b, "b");

  double total_area = 0.0;
  for (double area : areas) {
    if (!(std::isfinite(area) && area > 0.0))
      throw InputError(fmt::format("contact time step: node areas must be > 0, got {}", area));
    total_area += area;
  }
  const double m_red = b ? a.mass * b->mass / (a.mass + b->mass) : a.mass;

  const int dof = b ? 12 : 6;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(dof, dof);
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(dof, dof);
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(dof, dof);
  M.block<3, 3>(0, 0) = a.mass * Eigen::Matrix3d::Identity();
  M.block<3, 3>(3, 3) = 0.5 * (a.inertia + a.inertia.transpose());
  if (b) {
    M.block<3, 3>(6, 6) = b->mass * Eigen::Matrix3d::Identity();
    M.block<3, 3>(9, 9) = 0.5 * (b->inertia + b->inertia.transpose());
  }
  const Eigen::Matrix3d nn = normal * normal.transpose();
  const Eigen::Matrix3d tt = Eigen::Matrix3d::Identity() - nn;
  Eigen::MatrixXd J(3, dof);
  for (std::size_t i = 0; i < points.size(); ++i) {
    // Relative displacement of the node: u_a - u_b, u = U + theta x r = U - [r]x theta.
    J.setZero();
    J.block<3, 3>(0, 0) = Eigen::Matrix3d::Identity();
    J.block<3, 3>(0, 3) = -cross_matrix(points[i] - a.com);
    if (b) {
      J.block<3, 3>(0, 6) = -Eigen::Matrix3d::Identity();
      J.block<3, 3>(0, 9) = cross_matrix(points[i] - b->com);
    }
    const ContactLinearization lin = law.linearize(areas[i], m_red * areas[i] / total_area, overlap);
    const Eigen::Matrix3d S = lin.normal_stiffness * nn + lin.tangential_stiffness * tt;
    const Eigen::Matrix3d D = lin.normal_damping * nn + lin.tangential_damping * tt;
    K.noalias() += J.transpose() * S * J;
    C.noalias() += J.transpose() * D * J;
  }

  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(K, M);
  if (eig.info() != Eigen::Success)
    throw InputError("contact time step: the eigenvalue solver failed");
  const Eigen::VectorXd& lambda = eig.eigenvalues();
  const double lambda_max = lambda(dof - 1);
  ContactModes out;
  out.omega_max = std::sqrt(std::max(lambda_max, 0.0));
  out.time_step = std::numeric_limits<double>::infinity();
  for (int j = 0; j < dof; ++j) {
    // Modes without stiffness (a body free to move along or about the
    // contact, e.g. rotation about a line of nodes) cannot go unstable.
    if (!(lambda(j) > 1e-12 * lambda_max)) continue;
    const Eigen::VectorXd phi = eig.eigenvectors().col(j);
    const double omega = std::sqrt(lambda(j));
    // Modal damping ratio of the undamped mode (exact when C is proportional to K).
    const double zeta = phi.dot(C * phi) / (2.0 * omega * phi.dot(M * phi));
    const double step = 2.0 / (omega * (std::sqrt(1.0 + zeta * zeta) + zeta));
    if (step < out.time_step) {
      out.time_step = step;
      out.damping_ratio = zeta;
      out.omega = omega;
    }
  }
  return out;
}

double recommended_time_step_fraction(const ContactLaw& law) {
  return law.params().law == NormalLaw::kHertz ? kHertzTimeStepFraction : kLinearTimeStepFraction;
}

void check_time_step(const ContactLaw& law, double dt, double dt_critical, std::string_view what) {
  if (!(std::isfinite(dt) && dt > 0.0))
    throw InputError(fmt::format("{}: timestep must be > 0, got {}", what, dt));
  if (dt > dt_critical) {
    const double fraction = recommended_time_step_fraction(law);
    throw InputError(fmt::format(
        "{}: timestep {:.3g} s is above the critical time step {:.3g} s of the contact law "
        "and the run would blow up; use timestep {:.3g} or less ({} of the critical step, "
        "which keeps restitution within 1 % of its target)",
        what, dt, dt_critical, fraction * dt_critical, fraction));
  }
}

}  // namespace freestand
