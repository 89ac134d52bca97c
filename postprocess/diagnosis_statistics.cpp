#include "diagnosis_statistics.h"

#include <Eigen/Dense>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "signal_tools.h"

namespace freestand::diagnosis {

namespace {
const double kMonteCarloBound = 2;  // a chi2 drop is tested at drop - 2 Monte Carlo s.e. (97.7 % one-sided)
}

double chi2_1_tail(double d) { return d <= 0 ? 1.0 : std::erfc(std::sqrt(d / 2)); }

// A feature's s.d. estimated from a few ensemble members makes its ratio t-, not normal-distributed,
// and a sum of t^2 would count the heavy tails as misfit (E t^2 = nu / (nu - 2): 5/3 for 6 members).
double t_as_z(double t, double nu) {
  if (t == 0 || !(nu < 1e6)) return t;
  const double tail = boost::math::cdf(boost::math::complement(boost::math::students_t(nu), std::abs(t)));
  if (tail < 1e-300) return t;  // beyond double precision only the size matters
  return std::copysign(boost::math::quantile(boost::math::complement(boost::math::normal(), tail)), t);
}

namespace {

// Nodes of the average over sigma^2 ~ nu s^2 / chi2_nu: chi2_nu quantiles at probabilities
// u^4 (u at the midpoints of kNodes equal steps; dense where chi2 is small, sigma^2 large:
// the far tail of the predictive comes from there), with weights 4 u^3 / kNodes.
const int kNodes = 48;
struct ScatterNodes {
  std::vector<double> chi2, weight;
};
const ScatterNodes& scatter_nodes(double nu) {
  static std::map<double, ScatterNodes> cache;  // a diagnosis has a few distinct dof
  auto [at, fresh] = cache.try_emplace(nu);
  if (fresh)
    for (int k = 0; k < kNodes; ++k) {
      const double u = (k + 0.5) / kNodes;
      at->second.chi2.push_back(boost::math::quantile(boost::math::chi_squared(nu), std::pow(u, 4)));
      at->second.weight.push_back(4 * std::pow(u, 3) / kNodes);
    }
  return at->second;
}

}  // namespace

double predictive_z(double difference, double scatter, double nu, double floor2) {
  if (scatter <= 0 || !(nu < 1e6)) return difference / std::sqrt(scatter + floor2);
  if (floor2 <= 0) return t_as_z(difference / std::sqrt(scatter), nu);
  const ScatterNodes& nodes = scatter_nodes(nu);
  double tail = 0;  // two-sided: P(|new draw - mean| > |difference|)
  for (int k = 0; k < kNodes; ++k)
    tail += nodes.weight[k] * std::erfc(std::abs(difference) / std::sqrt(2 * (nu * scatter / nodes.chi2[k] + floor2)));
  if (tail < 1e-300) return difference / std::sqrt(scatter + floor2);  // beyond double precision only the size matters
  return std::copysign(boost::math::quantile(boost::math::complement(boost::math::normal(), tail / 2)), difference);
}

double chi2_quantile_99(int n) {
  const double a = 2.0 / (9.0 * n);
  return n * std::pow(1 - a + 2.326 * std::sqrt(a), 3);
}

double family_wise_z(double alpha, int n) {
  return boost::math::quantile(boost::math::complement(boost::math::normal(), alpha / (2.0 * std::max(1, n))));
}

double existence_z(int agree, int members) {
  const double q = (agree + 0.5) / (members + 1.0);
  return boost::math::quantile(boost::math::complement(boost::math::normal(), q / 2));
}

// ------------------------------------------------------------------ Target

bool Target::failed(const Features& sim) { return sim.count(kFailedSimulation) > 0; }

bool Target::compares_value(const std::string& name, const FeatureValue& f) const {
  return f.present && dof.at(name) >= kMinScatterDof;
}

double Target::chi2(const Features& sim, bool held) const {
  if (failed(sim)) return std::numeric_limits<double>::infinity();
  double sum = 0;
  for (const auto& [name, f] : recorded) {
    if (held_out.count(name) != static_cast<std::size_t>(held)) continue;
    const auto s = sim.find(name);
    const bool has = s != sim.end();
    if (f.event) sum += std::pow(existence_z(has == f.present, 1), 2);
    // The tails of the test's z (predictive_z): as a Gaussian z^2, one feature off by 200 s.d.
    // outweighs forty off by 5, and the profiles would rank candidates by that one feature.
    if (has && compares_value(name, f))
      sum += std::pow(predictive_z(s->second.value - f.value, ensemble_var.at(name), dof.at(name), f.floor * f.floor), 2);
  }
  return sum;
}

double Target::ensemble_mean(const std::string& name, const std::vector<Features>& members, int skip) {
  double sum = 0;
  int n = 0;
  for (int m = 0; m < static_cast<int>(members.size()); ++m) {
    const auto s = members[m].find(name);
    if (m != skip && s != members[m].end()) sum += s->second.value, ++n;
  }
  return n > 0 ? sum / n : signal::kNaN;
}

double Target::ensemble_z(const std::string& name, const FeatureValue& f, const std::vector<Features>& members,
                          int skip) const {
  int m = 0, k = 0;
  for (int j = 0; j < static_cast<int>(members.size()); ++j) {
    if (j == skip) continue;
    if (failed(members[j])) return std::numeric_limits<double>::infinity();
    ++m, k += members[j].count(name) > 0;
  }
  const double existence = f.event ? existence_z(f.present ? k : m - k, m) : 0.0;
  if (k == 0 || !compares_value(name, f)) return f.present ? existence : -existence;
  const double scatter = ensemble_var.at(name) * (1 + 1.0 / k);
  const double value = predictive_z(f.value - ensemble_mean(name, members, skip), scatter, dof.at(name), f.floor * f.floor);
  return std::copysign(std::hypot(existence, value), value);
}

double Target::ensemble_chi2(const std::vector<Features>& members, std::optional<bool> held, int skip) const {
  double sum = 0;
  for (const auto& [name, f] : recorded)
    if (!held || held_out.count(name) == static_cast<std::size_t>(*held))
      sum += std::pow(ensemble_z(name, f, members, skip), 2);
  return sum;
}

Target Target::with_recorded(const Features& sim) const {
  Target t = *this;
  for (auto& [name, f] : t.recorded) {
    const auto s = sim.find(name);
    f.present = s != sim.end();
    if (f.present) f.value = s->second.value;
  }
  return t;
}

int Target::count(std::optional<bool> held) const {
  int n = 0;
  for (const auto& [name, f] : recorded) n += !held || held_out.count(name) == static_cast<std::size_t>(*held);
  return n;
}

std::vector<Mismatch> Target::mismatches(const std::vector<Features>& members, double threshold) const {
  std::vector<Mismatch> out;
  for (const auto& [name, f] : recorded) {
    const double z = ensemble_z(name, f, members, -1);
    if (std::abs(z) > threshold)
      out.push_back({name, name.substr(0, name.find('.')), f.mode, f.time, f.present ? f.value : signal::kNaN,
                     ensemble_mean(name, members, -1), z});
  }
  std::sort(out.begin(), out.end(), [](const Mismatch& a, const Mismatch& b) { return a.time < b.time; });
  return out;
}

namespace {

struct MemberScatter {
  double variance = 0;  // about the mean of the members that have the feature
  double dof = 0;       // those members - 1 (0 for fewer than 2)
};

MemberScatter member_scatter(const std::string& name, const std::vector<Features>& members) {
  std::vector<double> v;
  for (const Features& m : members)
    if (const auto s = m.find(name); s != m.end()) v.push_back(s->second.value);
  if (v.size() < 2) return {};
  double mean = 0, var = 0;
  for (double x : v) mean += x / v.size();
  for (double x : v) var += (x - mean) * (x - mean) / (v.size() - 1);
  return {var, v.size() - 1.0};
}

}  // namespace

Target target_of(const Features& recorded, const std::vector<std::vector<Features>>& ensembles) {
  Target t;
  t.recorded = recorded;
  for (const std::vector<Features>& members : ensembles)
    for (const Features& m : members)
      for (const auto& [name, f] : m)
        if (f.event && !t.recorded.count(name)) {
          t.recorded[name] = f;
          t.recorded[name].present = false;
        }
  for (const auto& [name, f] : t.recorded) {
    double sum = 0, dof = 0;
    for (const std::vector<Features>& members : ensembles) {
      const MemberScatter s = member_scatter(name, members);
      sum += s.variance * s.dof, dof += s.dof;
    }
    const double var = dof > 0 ? sum / dof : 0.0;
    t.ensemble_var[name] = var;
    t.dof[name] = dof;
  }
  return t;
}

// ------------------------------------------------------------------ tests of a fit

Drop ensemble_drop(const Target& t0, const std::vector<Features>& before, const Target& t1,
                   const std::vector<Features>& at, std::optional<bool> held) {
  Drop d{t0.ensemble_chi2(before, held) - t1.ensemble_chi2(at, held), 0};
  const int m = static_cast<int>(std::min(before.size(), at.size()));
  if (m < 3) return d;
  std::vector<double> left_out;
  for (int k = 0; k < m; ++k) left_out.push_back(t0.ensemble_chi2(before, held, k) - t1.ensemble_chi2(at, held, k));
  double mean = 0, sum = 0;
  for (double x : left_out) mean += x / m;
  for (double x : left_out) sum += (x - mean) * (x - mean);
  d.se = std::sqrt((m - 1.0) / m * sum);  // 0.8 of the true scatter for 6 members (DiagnosisStatistics test)
  return d;
}

bool exceeds(const Drop& drop, double margin) { return drop.value - kMonteCarloBound * drop.se > margin; }

double prior_penalty(const Candidate& c, double value) {
  return c.prior_sd > 0 ? std::pow((value - c.nominal) / c.prior_sd, 2) : 0.0;
}

// The drop at its lower Monte Carlo bound: the ensemble means are estimates, and a drop they
// could produce by chance is no evidence.
void score(FittedCandidate& f, const Drop& drop, int n) {
  f.delta = drop.value;
  f.delta_se = drop.se;
  const double sure = drop.value - kMonteCarloBound * drop.se - prior_penalty(f.candidate, f.value);
  const double p_one = chi2_1_tail(sure);
  f.p_value = f.candidate.at_boundary ? 0.5 * p_one : p_one;  // Self & Liang (1987): 0.5 chi2_0 + 0.5 chi2_1 at a bound
  f.delta_bic = sure - std::log(std::max(1, n));
}

bool undecided(const FittedCandidate& f, const Drop& drop, int n, const std::function<bool(const FittedCandidate&)>& passes) {
  if (passes(f)) return false;
  FittedCandidate exact = f;
  score(exact, {drop.value, 0}, n);
  return passes(exact);
}

ProfileMinimum profile_minimum(const std::vector<std::pair<double, double>>& points, int span) {
  const auto n = static_cast<std::ptrdiff_t>(points.size());
  const std::ptrdiff_t used = std::min<std::ptrdiff_t>(span, n);
  if (used < 3) return {};
  std::ptrdiff_t lowest = 0;
  for (std::ptrdiff_t i = 1; i < n; ++i) if (points[i].second < points[lowest].second) lowest = i;
  const std::ptrdiff_t first = std::clamp<std::ptrdiff_t>(lowest - used / 2, 0, n - used);
  const double centre = points[lowest].first;  // conditioning: u about the lowest point
  Eigen::MatrixXd basis(used, 3);
  Eigen::VectorXd chi2(used);
  for (std::ptrdiff_t i = 0; i < used; ++i) {
    const auto [u, c] = points[first + i];
    if (!std::isfinite(c)) return {};  // a point did not run
    basis.row(i) << (u - centre) * (u - centre), u - centre, 1.0;
    chi2(i) = c;
  }
  const Eigen::Vector3d fit = basis.colPivHouseholderQr().solve(chi2);
  if (!(fit(0) > 0)) return {};
  // Between the lowest point's neighbours: on a chaotic run's profile, not a parabola over the
  // whole window, the minimum may refine the lowest point but never pass a neighbour.
  const double u = centre - fit(1) / (2 * fit(0));
  if (u < points[std::max<std::ptrdiff_t>(lowest - 1, 0)].first || u > points[std::min(lowest + 1, n - 1)].first)
    return {};
  return {u, 1 / std::sqrt(fit(0))};
}

Valley valley_of(const std::vector<std::pair<double, double>>& points, double u) {
  if (points.empty()) return {u, u};
  std::size_t m = 0;
  for (std::size_t k = 1; k < points.size(); ++k)
    if (std::abs(points[k].first - u) < std::abs(points[m].first - u)) m = k;
  for (bool moved = true; moved;) {
    moved = false;
    for (std::size_t n : {m - 1, m + 1})  // m - 1 wraps past the end at m = 0
      if (n < points.size() && points[n].second < points[m].second) m = n, moved = true;
  }
  std::size_t a = m, b = m;
  while (a > 0 && points[a - 1].second >= points[a].second) --a;
  while (b + 1 < points.size() && points[b + 1].second >= points[b].second) ++b;
  return {points[a].first, points[b].first};
}

double lowest_across_nominal(const std::vector<std::pair<double, double>>& points, double u0, double at, double base) {
  double best = signal::kNaN, lowest = base;
  for (const auto& [u, chi2] : points)
    if ((u - u0) * (at - u0) < 0 && chi2 < lowest) best = u, lowest = chi2;
  return best;
}

double secant_sd(double u0, double u, double drop) { return drop > 0 ? std::abs(u - u0) / std::sqrt(drop) : signal::kNaN; }

// The curvature alone assumes the model fits the data; a misfit beyond the noise (chi2 per
// degree of freedom above 1) means the data say less: the Birge ratio.
double birge_ratio(double chi2, int features) {
  return features > 1 ? std::max(1.0, std::sqrt(chi2 / (features - 1))) : 1.0;
}

}  // namespace freestand::diagnosis
