#ifndef FREESTAND_POST_DIAGNOSIS_STATISTICS_H
#define FREESTAND_POST_DIAGNOSIS_STATISTICS_H

// The statistics of `freestand diagnose` (docs/diagnose.md, "Nominal, ensemble, features and
// the likelihood"): recorded event features against simulated ones whose scatter (chaos and
// noise) a small ensemble estimates. A single run serves the profiles (common random numbers);
// every test and verdict compares the recording with an ensemble's mean, each feature's ratio
// taken as Student's t (the scatter is estimated from a few members) and turned into a normal z,
// and a chi2 drop is trusted only down to its Monte Carlo uncertainty.

#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "diagnosis.h"

namespace freestand::diagnosis {

// P(chi2_1 > d).
double chi2_1_tail(double d);

// The standard-normal z with the tail probability of Student's t with nu degrees of freedom
// (nu may be fractional; infinite: z = t).
double t_as_z(double t, double nu);

// The standard-normal z of a new draw's `difference` from an ensemble mean when the draw's
// variance is scatter' + floor2: scatter' estimated as `scatter` with nu degrees of freedom, the
// floor known. The tail is averaged over scatter' ~ nu scatter / chi2_nu (the predictive; with
// no floor exactly Student's t). Welch-Satterthwaite's t instead takes its dof from the same
// estimate as the ratio and undercounts the tail when the estimate is small by chance (5.8 x
// at a two-sided 2.5e-4 for a floor of half the scatter, 6 members, measured).
double predictive_z(double difference, double scatter, double nu, double floor2);
// 99 % quantile of chi2 with n degrees of freedom (Wilson-Hilferty, within 1 % for n >= 5).
double chi2_quantile_99(int n);
// The |z| that any of n independent normal features exceeds by chance with probability at most
// alpha (Bonferroni: the two-sided normal quantile at alpha / n).
double family_wise_z(double alpha, int n);

// The z of an event's existence when `agree` of `members` simulations have it as the recording
// does (both have it, or both lack it): the normal quantile whose two-sided tail is the
// predictive probability of the recorded outcome, q = (agree + 1/2) / (members + 1) (Jeffreys'
// prior on the members' rate). Bounded: |z| 1.80 when none of 6 members agree, 0.09 when all do.
double existence_z(int agree, int members);

// The least degrees of freedom of a feature's scatter for its value to be compared: fewer
// members with the event leave its scatter unknown, and only its existence counts.
constexpr double kMinScatterDof = 2;

// The recorded features with the scatter of each, and which are held out.
struct Target {
  Features recorded;  // the recording's features, and (present false) events only simulations have
  std::map<std::string, double> ensemble_var;  // variance about their mean of the members that have the feature
  std::map<std::string, double> dof;           // degrees of freedom of ensemble_var (present members - 1, summed)
  std::set<std::string> held_out;

  // Whether a simulation failed (kFailedSimulation): its chi2 and any ensemble's with it are infinite.
  static bool failed(const Features& sim);
  // Whether a feature's value is compared: recorded, with a scatter known (dof >= kMinScatterDof).
  bool compares_value(const std::string& name, const FeatureValue& f) const;
  // One simulation against the recording: the sum of z^2 over the fit set (held false) or the
  // held-out set (true), z = predictive_z(sim - recorded) with the members' scatter and the
  // floor for a value (the tails of the few members' estimate), existence_z(agree, 1) for an event.
  // For profiles, where the noise seed is common.
  double chi2(const Features& sim, bool held) const;
  // The mean of feature `name` over the members that have it, member `skip` left out (the
  // jackknife; -1: none). NaN when none has it.
  static double ensemble_mean(const std::string& name, const std::vector<Features>& members, int skip);
  // The recording's z against the members, existence and value in quadrature: existence_z for
  // an event, and predictive_z of recorded - mean (over the k members with the feature) with
  // the scatter var (1 + 1/k) (a new draw against the mean of k draws) and the floor (known).
  double ensemble_z(const std::string& name, const FeatureValue& f, const std::vector<Features>& members,
                    int skip) const;
  // Sum of ensemble_z^2 over the fit set (held false), the held-out set (true) or all (nullopt).
  double ensemble_chi2(const std::vector<Features>& members, std::optional<bool> held = std::nullopt,
                       int skip = -1) const;
  // The same scatter with a simulation in the recording's place: is it a draw of the ensemble?
  Target with_recorded(const Features& sim) const;
  // Features in the fit set (held false), the held-out set (true) or all (nullopt).
  int count(std::optional<bool> held = std::nullopt) const;
  // Features with |ensemble z| beyond `threshold`, in time order.
  std::vector<Mismatch> mismatches(const std::vector<Features>& members, double threshold) const;
};

// The target of `recorded` against ensembles of members: each feature's scatter pooled over
// the members that have it (their variances weighted by their dof), plus its floor; events that
// members have and the recording lacks added with present false (their absence is evidence).
// Nothing held out.
Target target_of(const Features& recorded, const std::vector<std::vector<Features>>& ensembles);

// A chi2 drop and its Monte Carlo standard error (0 when not estimated).
struct Drop {
  double value = 0, se = 0;
};

// The chi2 drop from ensemble `before` (against target t0) to ensemble `at` (against t1), with
// its Monte Carlo s.e. from the jackknife over the member pairs (member e of every ensemble has
// the same perturbation and noise seed, so the pairs share what chaos and noise they can).
Drop ensemble_drop(const Target& t0, const std::vector<Features>& before, const Target& t1,
                   const std::vector<Features>& at, std::optional<bool> held);

// Whether a chi2 drop is above `margin` at its lower Monte Carlo bound (drop - 2 s.e., as score).
bool exceeds(const Drop& drop, double margin);

// -2 log of a candidate's prior at `value` relative to its nominal (0 without a prior).
double prior_penalty(const Candidate& c, double value);

// The test statistics of a fit from its chi2 drop, taken at its lower Monte Carlo bound
// (drop - 2 s.e.) less the prior's penalty: boundary-corrected LRT p-value and BIC difference
// (one parameter, n fit-set features).
void score(FittedCandidate& f, const Drop& drop, int n);

// The sequential ensemble test after its first look: a fit that fails at its Monte Carlo bound
// but would pass on the drop as measured is undecided (more members can tell), not refuted.
// f is scored on `drop` over n fit-set features; `passes` is the acceptance rule.
bool undecided(const FittedCandidate& f, const Drop& drop, int n, const std::function<bool(const FittedCandidate&)>& passes);

// The minimum of a profile (points (u, chi2), sorted by u) from the least-squares parabola
// through the `span` points around its lowest one, and the s.d. there (chi2 rises by 1 at one
// s.d.), both in scaled units. Through three points the parabola interpolates; through more it
// averages the jitter a chaotic run puts on each point, which the lowest point alone picks up.
// The minimum must lie between the lowest point's neighbours.
struct ProfileMinimum {
  double u = std::numeric_limits<double>::quiet_NaN();   // NaN: not convex, a point did not run, or beyond a neighbour
  double sd = std::numeric_limits<double>::quiet_NaN();  // NaN with u
};
ProfileMinimum profile_minimum(const std::vector<std::pair<double, double>>& points, int span);

// The points of a profile (points (u, chi2), sorted by u) about the local minimum reached
// downhill from the point nearest u, out to where the curve stops rising on either side: one
// valley of a profile that may have several.
struct Valley {
  double from = 0, to = 0;  // scaled bounds, both profile points
};
Valley valley_of(const std::vector<std::pair<double, double>>& points, double u);

// The lowest point (scaled u) of a profile (points (u, chi2)) on the other side of the nominal
// u0 from `at`, if it lies below `base` (the model as given): a second valley, where one
// member's chaos may have put the profile's lowest point on the wrong side. NaN if none.
double lowest_across_nominal(const std::vector<std::pair<double, double>>& points, double u0, double at, double base);

// Standard error (scaled units) from the parabola with its minimum at the fit u through the
// model before it (u0), `drop` below: |u - u0| / sqrt(drop). NaN without a drop.
double secant_sd(double u0, double u, double drop);

// max(1, sqrt(chi2 / (n - 1))): a misfit beyond the noise widens a profile's s.d. by it.
double birge_ratio(double chi2, int features);

}  // namespace freestand::diagnosis

#endif
