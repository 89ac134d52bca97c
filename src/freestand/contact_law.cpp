#include "freestand/contact_law.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "freestand/input_error.h"

namespace freestand {

namespace {

constexpr double kPi = 3.14159265358979323846;

// -ln e of the clamped single-dof impact as a function of zeta (the exponent
// of restitution_from_damping_ratio). Continuous and strictly increasing,
// g(0) = 0, g(1) = 2, g -> 2 ln(2 zeta) as zeta -> infinity.
double log_restitution_loss(double zeta) {
  if (zeta == 0.0) return 0.0;
  if (zeta < 1.0) {
    // x (pi - 2 atan x) = 2 x atan(1/x), stable as x -> infinity (zeta -> 1).
    const double x = zeta / std::sqrt((1.0 - zeta) * (1.0 + zeta));
    return 2.0 * x * std::atan(1.0 / x);
  }
  if (zeta == 1.0) return 2.0;
  const double y = std::sqrt((zeta - 1.0) * (zeta + 1.0)) / zeta;
  // 2 atanh(y) / y; for y near 1 use atanh(y) = ln((1 + y) zeta), which
  // avoids the cancellation in 1 - y (1 - y^2 = 1/zeta^2 exactly).
  if (y < 0.5) return 2.0 * std::atanh(y) / y;
  return 2.0 * std::log((1.0 + y) * zeta) / y;
}

void require(bool ok, const std::string& message) {
  if (!ok) throw InputError("contact law: " + message);
}

}  // namespace

double restitution_from_damping_ratio(double zeta) {
  require(std::isfinite(zeta) && zeta >= 0.0,
          fmt::format("damping_ratio must be a finite number >= 0, got {}", zeta));
  return std::exp(-log_restitution_loss(zeta));
}

double damping_ratio_from_restitution(double e) {
  require(std::isfinite(e) && e > 0.0 && e <= 1.0,
          fmt::format("restitution must be in (0, 1], got {}", e));
  const double target = -std::log(e);
  if (target == 0.0) return 0.0;
  double lo = 0.0, hi = 1.0;
  while (log_restitution_loss(hi) < target) {
    lo = hi;
    hi *= 2.0;
  }
  // Bisection: g is monotone, so this converges to the last bit.
  for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (log_restitution_loss(mid) < target)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

double unclamped_restitution(double zeta) {
  require(std::isfinite(zeta) && zeta >= 0.0,
          fmt::format("damping_ratio must be a finite number >= 0, got {}", zeta));
  if (zeta >= 1.0) return 0.0;
  return std::exp(-kPi * zeta / std::sqrt((1.0 - zeta) * (1.0 + zeta)));
}

Eigen::Vector3d rotate_into_tangent_plane(const Eigen::Vector3d& xi, const Eigen::Vector3d& n) {
  const double old2 = xi.squaredNorm();
  if (old2 == 0.0) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d projected = xi - xi.dot(n) * n;
  const double new2 = projected.squaredNorm();
  // Parallel to n (to 1e-12 in angle): there is no direction left to keep.
  if (new2 <= 1e-24 * old2) return Eigen::Vector3d::Zero();
  return projected * std::sqrt(old2 / new2);
}

ContactLaw::ContactLaw(const ContactParams& p) : params_(p) {
  require(std::isfinite(p.stiffness_per_area) && p.stiffness_per_area > 0.0,
          fmt::format("stiffness_per_area must be a finite number > 0 (N/m^3), got {}",
                      p.stiffness_per_area));
  if (p.law == NormalLaw::kHertz) {
    require(std::isfinite(p.hertz_reference_overlap) && p.hertz_reference_overlap > 0.0,
            fmt::format("hertz_reference_overlap must be a finite number > 0 (m) for the "
                        "Hertz law, got {}",
                        p.hertz_reference_overlap));
  }
  require(!(p.damping_ratio && p.restitution),
          "give either damping_ratio or restitution, not both");
  require(p.damping_ratio || p.restitution, "damping_ratio or restitution must be given");
  if (p.damping_ratio) {
    require(std::isfinite(*p.damping_ratio) && *p.damping_ratio >= 0.0,
            fmt::format("damping_ratio must be a finite number >= 0, got {}", *p.damping_ratio));
    zeta_ = *p.damping_ratio;
  } else {
    zeta_ = damping_ratio_from_restitution(*p.restitution);
  }
  require(std::isfinite(p.tangential_stiffness_ratio) && p.tangential_stiffness_ratio > 0.0,
          fmt::format("tangential_stiffness_ratio must be a finite number > 0, got {}",
                      p.tangential_stiffness_ratio));
  require(std::isfinite(p.tangential_damping_ratio) && p.tangential_damping_ratio >= 0.0,
          fmt::format("tangential_damping_ratio must be a finite number >= 0, got {}",
                      p.tangential_damping_ratio));
  require(!std::isnan(p.mu_s), "mu_s is not set (static friction coefficient)");
  require(!std::isnan(p.mu_k), "mu_k is not set (kinetic friction coefficient)");
  require(std::isfinite(p.mu_s) && p.mu_s >= 0.0,
          fmt::format("mu_s must be a finite number >= 0, got {}", p.mu_s));
  require(std::isfinite(p.mu_k) && p.mu_k >= 0.0,
          fmt::format("mu_k must be a finite number >= 0, got {}", p.mu_k));
  require(p.mu_k <= p.mu_s,
          fmt::format("mu_k ({}) must not exceed mu_s ({})", p.mu_k, p.mu_s));
  require(std::isfinite(p.friction_decay) && p.friction_decay >= 0.0,
          fmt::format("friction_decay must be a finite number >= 0 (s/m), got {}",
                      p.friction_decay));

  if (p.law == NormalLaw::kHertz) {
    k_h_ = p.stiffness_per_area / std::sqrt(p.hertz_reference_overlap);
    c_norm_ = std::sqrt(5.0) * zeta_;  // alpha of the Tsuji dashpot
  } else {
    c_norm_ = 2.0 * zeta_;
  }
  c_tang_ = 2.0 * p.tangential_damping_ratio;
}

double ContactLaw::kinetic_friction(double sliding_speed) const {
  if (params_.friction_decay == 0.0) return params_.mu_k;
  return params_.mu_k +
         (params_.mu_s - params_.mu_k) * std::exp(-params_.friction_decay * std::abs(sliding_speed));
}

double ContactLaw::linearized_damping_ratio() const {
  return params_.law == NormalLaw::kHertz ? zeta_ * std::sqrt(5.0 / 6.0) : zeta_;
}

double ContactLaw::elastic_force(double area, double overlap) const {
  if (!(overlap > 0.0)) return 0.0;
  if (params_.law == NormalLaw::kLinear) return params_.stiffness_per_area * area * overlap;
  return k_h_ * area * overlap * std::sqrt(overlap);
}

double ContactLaw::elastic_energy(double area, double overlap) const {
  if (!(overlap > 0.0)) return 0.0;
  if (params_.law == NormalLaw::kLinear)
    return 0.5 * params_.stiffness_per_area * area * overlap * overlap;
  return 0.4 * k_h_ * area * overlap * overlap * std::sqrt(overlap);
}

ContactLinearization ContactLaw::linearize(double area, double effective_mass,
                                           double overlap) const {
  ContactLinearization out;
  if (params_.law == NormalLaw::kLinear) {
    out.normal_stiffness = params_.stiffness_per_area * area;
    out.normal_damping = c_norm_ * std::sqrt(out.normal_stiffness * effective_mass);
  } else {
    const double d = std::max(overlap, 0.0);
    const double sd = std::sqrt(d);
    out.normal_stiffness = 1.5 * k_h_ * area * sd;
    out.normal_damping = c_norm_ * std::sqrt(k_h_ * area * effective_mass) * std::sqrt(sd);
  }
  out.tangential_stiffness = params_.tangential_stiffness_ratio * out.normal_stiffness;
  out.tangential_damping = c_tang_ * std::sqrt(out.tangential_stiffness * effective_mass);
  return out;
}

double ContactLaw::overlap_under_load(double face_area, double load) const {
  const double linear = load / (params_.stiffness_per_area * face_area);
  if (params_.law == NormalLaw::kLinear) return linear;
  const double dref = params_.hertz_reference_overlap;
  return dref * std::cbrt((linear / dref) * (linear / dref));
}

double ContactLaw::impact_overlap(double face_area, double mass, double speed) const {
  if (params_.law == NormalLaw::kLinear)
    return std::abs(speed) * std::sqrt(mass / (params_.stiffness_per_area * face_area));
  return std::pow(5.0 * mass * speed * speed / (4.0 * k_h_ * face_area), 0.4);
}

ContactForce ContactLaw::compute(const ContactPoint& point, double dt,
                                 ContactHistory& history) const {
  ContactForce out;
  const double delta = point.overlap;
  if (!(delta > 0.0)) {
    history = ContactHistory{};
    return out;
  }
  const Eigen::Vector3d& n = point.normal;
  const double vn = n.dot(point.velocity);  // < 0 while approaching
  const Eigen::Vector3d vt = point.velocity - vn * n;
  const double m = point.effective_mass;

  // Normal: spring + dashpot, never attractive.
  double elastic, damping, kn;
  if (params_.law == NormalLaw::kLinear) {
    kn = params_.stiffness_per_area * point.area;
    elastic = kn * delta;
    damping = c_norm_ * std::sqrt(kn * m);
  } else {
    const double sd = std::sqrt(delta);
    const double kha = k_h_ * point.area;
    elastic = kha * delta * sd;
    damping = c_norm_ * std::sqrt(kha * m) * std::sqrt(sd);
    kn = 1.5 * kha * sd;  // tangent stiffness, for Mindlin's k_t
  }
  const double fn = std::max(0.0, elastic - damping * vn);

  // Tangential: rotate the spring into the current tangent plane, load it by
  // this step's tangential displacement, and return-map onto the cone.
  const double kt = params_.tangential_stiffness_ratio * kn;
  const double ct = c_tang_ * std::sqrt(kt * m);
  const double old_xi2 = history.displacement().squaredNorm();  // rotation keeps |xi|
  Eigen::Vector3d xi = rotate_into_tangent_plane(history.displacement(), n) + vt * dt;
  const Eigen::Vector3d trial = -kt * xi - ct * vt;
  const double trial2 = trial.squaredNorm();
  const double mu = history.is_sliding() ? kinetic_friction(vt.norm()) : params_.mu_s;
  const double limit = mu * fn;
  // Inside the cone, with 1e-12 of slack so that a spring just reset to the
  // limit (xi = -F_t / k_t, rounded) counts as on it, not outside.
  const double bound = limit * (1.0 + 1e-12);
  Eigen::Vector3d ft;
  bool sliding;
  if (trial2 <= bound * bound) {
    ft = trial;
    sliding = false;
  } else {
    ft = trial * (limit / std::sqrt(trial2));
    xi = kt > 0.0 ? Eigen::Vector3d(-ft / kt) : Eigen::Vector3d::Zero();
    sliding = true;
  }

  // Energy ledger (docs/fix_rigid_convex.md, "Energy ledger"): the dashpot
  // part of the applied normal force, F_n - F_el (with the clamp: -F_el),
  // works against the normal velocity the law used; stuck, the tangential
  // dashpot dissipates c_t |v_t|^2 dt; sliding, the contact takes the
  // frictional work -F_t . v_t dt and gives back what its spring loses in the
  // return map, E_t,old - E_t,new.
  out.normal_energy = params_.law == NormalLaw::kLinear ? 0.5 * elastic * delta : 0.4 * elastic * delta;
  out.normal_dissipation = -(fn - elastic) * vn * dt;
  const double new_xi2 = xi.squaredNorm();
  out.tangential_energy = 0.5 * kt * new_xi2;
  if (sliding)
    out.friction_dissipation = -ft.dot(vt) * dt + 0.5 * kt * (old_xi2 - new_xi2);
  else
    out.friction_dissipation = ct * vt.squaredNorm() * dt;

  history.xi[0] = xi.x();
  history.xi[1] = xi.y();
  history.xi[2] = xi.z();
  history.sliding = sliding ? 1.0 : 0.0;
  out.normal = fn;
  out.tangential = ft;
  out.force = fn * n + ft;
  out.sliding = sliding;
  return out;
}

}  // namespace freestand
