// diagnosis_statistics: the tests of `freestand diagnose` must hold their stated error rates
// when the model is right. A recording that is one more draw of the model (Gaussian features,
// scatter estimated from 6 members as diagnose does) must pass the 99 % noise limit 99 % of the
// time, and a candidate that changes nothing must not be accepted more often than its alpha,
// also when an undecided test looks a second time on more members, and when a value fitted on
// the fit set is judged on every feature.

#include "diagnosis_statistics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace freestand::diagnosis {
namespace {

const int kFeatures = 40;   // a rocking record's event features (28-60 in docs/diagnose.md)
const int kMembers = 6;     // diagnose's default ensemble
const int kTrials = 4000;

// A model of kFeatures Gaussian features: means, scatters spread over three decades (angles,
// times, lengths), and a floor on every other one. With `events`, each feature dates an event
// that happens in a run with its own probability (0.05-1: impacts late in a record, slips).
struct FeatureModel {
  std::vector<double> mean, sd, floor, existence;
  bool events;
  explicit FeatureModel(std::mt19937& rng, bool with_events = false) : events(with_events) {
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < kFeatures; ++i) {
      mean.push_back(u(rng));
      sd.push_back(std::pow(10.0, -3 * u(rng)));
      floor.push_back(i % 2 ? 0.5 * sd.back() : 0.0);
      existence.push_back(events ? 0.05 + 0.95 * u(rng) : 1.0);
    }
  }
  std::string name(int i) const { return "block.f" + std::to_string(i); }
  // One simulation: the features' chaos and noise, without the floor (what the model misses).
  Features member(std::mt19937& rng) const {
    std::normal_distribution<double> n(0, 1);
    std::uniform_real_distribution<double> u(0, 1);
    Features f;
    for (int i = 0; i < kFeatures; ++i) {
      const double value = mean[i] + sd[i] * n(rng);
      if (u(rng) < existence[i]) f[name(i)].value = value, f[name(i)].event = events;
    }
    return f;
  }
  std::vector<Features> ensemble(std::mt19937& rng) const {
    std::vector<Features> out;
    for (int m = 0; m < kMembers; ++m) out.push_back(member(rng));
    return out;
  }
  // The recording: a draw of the model plus the floor's measurement error.
  Features recording(std::mt19937& rng) const {
    std::normal_distribution<double> n(0, 1);
    Features f = member(rng);
    for (int i = 0; i < kFeatures; ++i)
      if (f.count(name(i))) f[name(i)].value += floor[i] * n(rng), f[name(i)].floor = floor[i];
    return f;
  }
};

// The target as diagnose makes it (target_of); the fit set is the even features, the held-out
// set the odd ones.
Target target_with_held_out(const Features& recorded, const std::vector<std::vector<Features>>& ensembles) {
  Target t = target_of(recorded, ensembles);
  for (const auto& [name, f] : t.recorded)
    if (std::stoi(name.substr(name.find(".f") + 2)) % 2) t.held_out.insert(name);
  return t;
}

TEST(DiagnosisStatistics, StudentTBecomesTheNormalZOfTheSameTail) {
  // Tabulated two-sided quantiles (Abramowitz & Stegun 26.7): t(0.975, 5) = 2.5706,
  // t(0.995, 10) = 3.1693; normal z 1.95996, 2.57583. Tolerance: the tables' 4 decimals.
  EXPECT_NEAR(t_as_z(2.5706, 5), 1.95996, 2e-4);
  EXPECT_NEAR(t_as_z(-3.1693, 10), -2.57583, 2e-4);
  EXPECT_DOUBLE_EQ(t_as_z(1.7, std::numeric_limits<double>::infinity()), 1.7);
  EXPECT_GT(t_as_z(40, 5), 5);  // far in the tail: still large, not infinite
  EXPECT_TRUE(std::isfinite(t_as_z(1e6, 5)));
}

TEST(DiagnosisStatistics, ThePredictiveZHoldsItsTailRateWithAFloor) {
  // No floor: exactly Student's t.
  EXPECT_DOUBLE_EQ(predictive_z(3.0, 2.0, 5, 0), t_as_z(3.0 / std::sqrt(2.0), 5));
  // A new draw (sd 1) plus a known floor (0.5) against the mean of 6 draws whose scatter is
  // estimated: how often |z| passes the two-sided 1 % and 2.5e-4 quantiles (the latter is
  // the family-wise threshold for 40 features at alpha 1 %).
  std::mt19937 rng(17);
  std::normal_distribution<double> n(0, 1);
  const int trials = 400000, members = 6;
  const double floor = 0.5, z1 = 2.5758, z4 = 3.6623;  // A&S 26.2
  int beyond1 = 0, beyond4 = 0;
  for (int trial = 0; trial < trials; ++trial) {
    double mean = 0, ss = 0;
    std::vector<double> x(members);
    for (double& v : x) v = n(rng), mean += v / members;
    for (double v : x) ss += (v - mean) * (v - mean) / (members - 1);
    const double z = predictive_z(n(rng) + floor * n(rng) - mean, ss * (1 + 1.0 / members), members - 1, floor * floor);
    beyond1 += std::abs(z) > z1, beyond4 += std::abs(z) > z4;
  }
  // Never above the nominal rate (binomial s.d.: 1.6 % of 4000 and 10 % of 100 expected
  // events, so 1.2 x allows for it); the average over the scatter is conservative with a floor
  // (measured 0.81 and 0.97 x; Welch-Satterthwaite's t gave 1.5 and 5.8 x). Not below half.
  EXPECT_LT(beyond1, 1.2 * 0.01 * trials);
  EXPECT_GT(beyond1, 0.5 * 0.01 * trials);
  EXPECT_LT(beyond4, 1.2 * 2.5e-4 * trials);
  EXPECT_GT(beyond4, 0.5 * 2.5e-4 * trials);
}

TEST(DiagnosisStatistics, ADrawOfTheModelPassesTheNoiseLimitAtItsRate) {
  std::mt19937 rng(7);
  const FeatureModel model(rng);
  int beyond = 0, beyond_single = 0;
  double mean = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const std::vector<Features> members = model.ensemble(rng);
    const Features single = model.member(rng);
    const Target t = target_with_held_out(model.recording(rng), {members});
    const double chi2 = t.ensemble_chi2(members);
    mean += chi2 / kTrials;
    beyond += chi2 > chi2_quantile_99(kFeatures);
    beyond_single += t.chi2(single, false) + t.chi2(single, true) > chi2_quantile_99(kFeatures);
  }
  // 1 % expected; the binomial s.d. over 4000 trials is 0.16 %, and the predictive z is
  // conservative for the floored features: 0.3-2 % allowed (measured 0.6 %).
  EXPECT_GT(beyond, 0.003 * kTrials);
  EXPECT_LT(beyond, 0.02 * kTrials);
  // The mean of chi2(40) is 40; its s.e. over the trials is 0.14: 5 % allowed for the same
  // conservatism (measured 38.8).
  EXPECT_NEAR(mean, kFeatures, 0.05 * kFeatures);
  // What the ensemble mean replaces: one run against the recording (the profiles' chi2, with the
  // same tails) has twice the variance and exceeds the limit tens of times more often than 1 %
  // (measured 46 %; 95.5 % before it took the t tails): 20 % is far from both.
  EXPECT_GT(beyond_single, kTrials / 5);
}

TEST(DiagnosisStatistics, AnEventsExistenceWeighsOnlyWhatTheMembersCanTell) {
  // Two-sided tail of the normal (A&S 26.2.17 via erfc) at z: the predictive probability of the
  // recorded outcome, (agree + 1/2) / (members + 1).
  EXPECT_NEAR(std::erfc(existence_z(0, 6) / std::sqrt(2.0)), 0.5 / 7, 1e-9);
  EXPECT_NEAR(existence_z(0, 6), 1.803, 1e-3);  // A&S 26.2: P(|Z| > 1.803) = 0.0714
  EXPECT_LT(existence_z(6, 6), 0.1);
  FeatureValue impact{2.5, 2.5, 0.01, "rock", true};  // an impact at 2.5 s, timed to a sample
  FeatureValue other = impact;
  other.value = 3.0;
  // The recording has the impact and no member does: the old fallback (the record's end, with
  // no scatter) made this z = (2.5 - 20) / 0.01; now the 6 members say only that it is rare.
  std::vector<Features> none(kMembers, Features{});
  Target t = target_of({{"block.rock_y.impact1.time", impact}}, {none});
  EXPECT_NEAR(t.ensemble_z("block.rock_y.impact1.time", impact, none, -1), 1.803, 1e-3);
  // Every member has an impact the recording lacks: the absence is a feature, of the other sign.
  std::vector<Features> all(kMembers, Features{{"block.rock_y.impact1.time", other}});
  t = target_of({}, {all});
  ASSERT_EQ(t.recorded.size(), 1u);
  EXPECT_FALSE(t.recorded.begin()->second.present);
  EXPECT_NEAR(t.ensemble_z("block.rock_y.impact1.time", t.recorded.begin()->second, all, -1), -1.803, 1e-3);
  // 4 of 6 members have it, at the recorded time on average: only the existence counts
  // (the value's z is 0), and the value's scatter is that of the 4.
  std::vector<Features> some = none;
  for (int m = 0; m < 4; ++m) some[m]["block.rock_y.impact1.time"] = impact;
  some[0]["block.rock_y.impact1.time"].value = 2.4, some[1]["block.rock_y.impact1.time"].value = 2.6;
  t = target_of({{"block.rock_y.impact1.time", impact}}, {some});
  EXPECT_DOUBLE_EQ(t.dof.at("block.rock_y.impact1.time"), 3.0);
  EXPECT_NEAR(t.ensemble_var.at("block.rock_y.impact1.time"), 0.02 / 3, 1e-12);
  EXPECT_NEAR(t.ensemble_z("block.rock_y.impact1.time", impact, some, -1), existence_z(4, 6), 1e-6);  // the mean rounds
}

TEST(DiagnosisStatistics, ADrawOfAModelWithRareEventsPassesTheNoiseLimit) {
  // Events that happen in a run with probabilities of 0.05-1: the recording's chi2 (existence
  // and values) against 6 members must pass the 99 % limit of its feature count (the events of
  // the recording and those only members have) at least 98 % of the time. Existence is a coin,
  // not a Gaussian: its z^2 averages below 1 (a likely outcome adds almost nothing), so the
  // limit is conservative, never anti-conservative.
  std::mt19937 rng(23);
  const FeatureModel model(rng, true);
  int beyond = 0;
  double mean_chi2 = 0, mean_n = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const std::vector<Features> members = model.ensemble(rng);
    const Target t = target_with_held_out(model.recording(rng), {members});
    const double chi2 = t.ensemble_chi2(members);
    const int n = static_cast<int>(t.recorded.size());
    beyond += chi2 > chi2_quantile_99(n);
    mean_chi2 += chi2 / kTrials, mean_n += static_cast<double>(n) / kTrials;
  }
  // Binomial s.d. of 1 % over 4000 trials: 0.16 %; 2 % allowed (measured 0.23 %, mean chi2 35.1
  // for 36.2 features).
  EXPECT_LT(beyond, 0.02 * kTrials);
  EXPECT_LT(mean_chi2, mean_n);
  std::printf("beyond the 99 %% limit: %.2f %%; mean chi2 %.1f for %.1f features\n", 100.0 * beyond / kTrials,
              mean_chi2, mean_n);
}

TEST(DiagnosisStatistics, AModelThatDoesNotRunFitsNothing) {
  // A failed simulation has no events; were it read as "every event absent" it would fit a
  // recording better than the model that runs (bounded existence z against value z). Seen: a
  // stiffness beyond the time step's critical value was accepted on case03 of the case set,
  // and the improved model then failed to run.
  std::mt19937 rng(29);
  const FeatureModel model(rng);
  std::vector<Features> members = model.ensemble(rng);
  const Target t = target_with_held_out(model.recording(rng), {members});
  const Features failed = {{kFailedSimulation, FeatureValue{}}};
  EXPECT_TRUE(std::isinf(t.chi2(failed, false)));
  EXPECT_TRUE(std::isfinite(t.chi2(members.front(), false)));
  std::vector<Features> at = members;
  at.back() = failed;
  EXPECT_TRUE(std::isinf(t.ensemble_chi2(at)));
  FittedCandidate f;
  score(f, ensemble_drop(t, members, t, at, false), t.count(false));
  EXPECT_FALSE(f.p_value < 0.01 && f.delta_bic > 0);  // never accepted
  // Its profile point is no neighbour of a minimum: no standard error from it.
  EXPECT_TRUE(std::isnan(profile_minimum({{0.0, t.chi2(failed, false)}, {0.5, 1.0}, {1.0, 3.0}}, 3).sd));
}

TEST(DiagnosisStatistics, AProfilesParabolaFindsItsMinimumBetterThanItsLowestPoint) {
  // Exact: chi2 = 4 (u - 0.3)^2 + 2 through three points has its minimum at 0.3, where chi2
  // rises by 1 at 1 / sqrt(4) = 0.5.
  const auto exact = [](double u) { return 4 * (u - 0.3) * (u - 0.3) + 2; };
  const ProfileMinimum three = profile_minimum({{0.0, exact(0.0)}, {0.2, exact(0.2)}, {1.0, exact(1.0)}}, 3);
  EXPECT_NEAR(three.u, 0.3, 1e-12);
  EXPECT_NEAR(three.sd, 0.5, 1e-12);
  EXPECT_TRUE(std::isnan(profile_minimum({{0.0, 1.0}, {0.5, 2.0}, {1.0, 1.5}}, 3).u));  // concave: no minimum
  // A refined profile: 9 points 0.04 apart about a true minimum at 0.5 (s.d. 0.05 in u) and one
  // more near it, each chi2 with unit Gaussian jitter (a run's chaos at the noise level). Over
  // 4000 draws the 5-point parabola's minimum must err less than the lowest point, the value
  // a refined fit took before (measured: rms 0.020 against 0.024; in about a quarter of the
  // draws the parabola is not convex or its minimum lies beyond a neighbour of the lowest
  // point, which is then kept). 4000 draws put the rms within 2 % of itself, well inside the
  // 10 % the test asks for.
  std::mt19937 rng(41);
  std::normal_distribution<double> jitter(0, 1);
  std::uniform_real_distribution<double> near(-0.02, 0.02);
  double lowest_square = 0, parabola_square = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    std::vector<std::pair<double, double>> curve;
    for (int k = -4; k <= 4; ++k) curve.push_back({0.5 + 0.04 * k, 0.0});
    curve.push_back({0.5 + near(rng), 0.0});
    std::sort(curve.begin(), curve.end());
    for (auto& [u, chi2] : curve) chi2 = std::pow((u - 0.5) / 0.05, 2) + jitter(rng);
    const double lowest = std::min_element(curve.begin(), curve.end(), [](auto& a, auto& b) {
                            return a.second < b.second;
                          })->first;
    const ProfileMinimum fit = profile_minimum(curve, 5);
    lowest_square += std::pow(lowest - 0.5, 2);
    parabola_square += std::pow((std::isfinite(fit.u) ? fit.u : lowest) - 0.5, 2);
  }
  std::printf("rms error of the minimum: parabola %.4f, lowest point %.4f\n", std::sqrt(parabola_square / kTrials),
              std::sqrt(lowest_square / kTrials));
  EXPECT_LT(std::sqrt(parabola_square / kTrials), 0.9 * std::sqrt(lowest_square / kTrials));
}

// The profile of the tower benchmark's COM (10 mm) with the tilt's carry (study 42), in mm:
// two valleys, about 7.2 mm (where the screen ran it) and 16.9 mm (where the whole record
// overturns), parted by a rise at 12.1 mm. Each point's valley runs downhill to its own minimum
// and out to where the curve stops rising; a single parabola is one valley wherever one starts.
TEST(DiagnosisStatistics, AProfilesValleyEndsWhereTheCurveStopsRising) {
  const std::vector<std::pair<double, double>> tower = {
      {-28.944, 74.09}, {-7.236, 55.38}, {-1.809, 47.58}, {0.0, 44.37}, {1.809, 41.95}, {3.618, 37.46},
      {5.427, 36.12},   {7.236, 34.62},  {9.648, 35.74},  {12.06, 42.41}, {14.472, 23.42}, {16.884, 21.51},
      {19.296, 22.33},  {21.708, 25.58}, {28.944, 43.0}};
  const Valley near = valley_of(tower, 7.236);
  EXPECT_DOUBLE_EQ(near.from, -28.944);
  EXPECT_DOUBLE_EQ(near.to, 12.06);
  const Valley far = valley_of(tower, 17.7);  // nearest point 16.884, the far valley's minimum
  EXPECT_DOUBLE_EQ(far.from, 12.06);
  EXPECT_DOUBLE_EQ(far.to, 28.944);
  const Valley slope = valley_of(tower, 3.0);  // from a slope (3.618) downhill to 7.236
  EXPECT_DOUBLE_EQ(slope.to, 12.06);
  std::vector<std::pair<double, double>> parabola;
  for (int k = 0; k <= 10; ++k) parabola.push_back({0.1 * k, std::pow(0.1 * k - 0.3, 2)});
  for (double u : {0.0, 0.3, 1.0}) {
    EXPECT_DOUBLE_EQ(valley_of(parabola, u).from, 0.0);
    EXPECT_DOUBLE_EQ(valley_of(parabola, u).to, 1.0);
  }
}

// A quick profile in the manner of biax04's COM (session 59; mm about the nominal 0, the
// model as given at 175): its lowest point at -50 mm, a second valley at +16 mm. A screen
// run at either valley looks across the nominal to the other; a side with no point below the
// model as given, or only the nominal itself, has none.
TEST(DiagnosisStatistics, TheOtherValleyIsTheLowestPointAcrossTheNominalBelowTheModelAsGiven) {
  const std::vector<std::pair<double, double>> com = {
      {-50, 87.5}, {-32, 120.0}, {-16, 90.5}, {0, 98.0}, {16, 103.9}, {32, 297.0}};
  EXPECT_DOUBLE_EQ(lowest_across_nominal(com, 0, -50, 175), 16);
  EXPECT_DOUBLE_EQ(lowest_across_nominal(com, 0, -16, 175), 16);
  EXPECT_DOUBLE_EQ(lowest_across_nominal(com, 0, 16, 175), -50);
  EXPECT_TRUE(std::isnan(lowest_across_nominal(com, 0, -50, 100)));  // +16 mm did not drop
  EXPECT_TRUE(std::isnan(lowest_across_nominal({{0, 1.0}, {16, 90.0}}, 0, 16, 175)));
}

TEST(DiagnosisStatistics, TheUnexplainedFlagFiresOnARightModelAtItsFamilyWiseRate) {
  // Bonferroni: the two-sided normal quantile at 0.01 / 40 (A&S 26.2: z(1.25e-4) = 3.6623).
  EXPECT_NEAR(family_wise_z(0.01, 40), 3.6623, 1e-3);
  std::mt19937 rng(13);
  const FeatureModel model(rng);
  int flagged = 0, flagged_3sd = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const std::vector<Features> members = model.ensemble(rng);
    const Target t = target_with_held_out(model.recording(rng), {members});
    flagged += !t.mismatches(members, family_wise_z(0.01, kFeatures)).empty();
    flagged_3sd += !t.mismatches(members, 3).empty();
  }
  // At most alpha = 1 % with a right model (binomial s.d. 0.16 % over 4000 trials: 1.5 %;
  // measured 0.85 %).
  EXPECT_LT(flagged, 0.015 * kTrials);
  // What it replaces: a 3 s.d. flag on any of 40 features fires about 10 % of the time
  // (1 - 0.9973^40; measured 9.5 %); at least 5 %.
  EXPECT_GT(flagged_3sd, 0.05 * kTrials);
}

TEST(DiagnosisStatistics, ACandidateThatChangesNothingIsAcceptedNoMoreOftenThanAlpha) {
  std::mt19937 rng(11);
  const FeatureModel model(rng);
  int accepted = 0;
  std::vector<double> drops, ses;
  for (int trial = 0; trial < kTrials; ++trial) {
    const std::vector<Features> before = model.ensemble(rng), at = model.ensemble(rng);
    const Target t = target_with_held_out(model.recording(rng), {before, at});
    const Drop d = ensemble_drop(t, before, t, at, false);
    FittedCandidate f;
    score(f, d, t.count(false));
    accepted += f.p_value < 0.01 && f.delta_bic > 0;
    drops.push_back(d.value), ses.push_back(d.se);
  }
  double mean = 0, var = 0, se = 0;
  for (double x : drops) mean += x / kTrials;
  for (double x : drops) var += (x - mean) * (x - mean) / (kTrials - 1);
  for (double x : ses) se += x / kTrials;
  // The jackknife s.e. of 6 pairs against the drop's actual scatter over the trials: a jackknife
  // of a nonlinear statistic from 6 pairs is only roughly right (measured: 0.80 of the scatter,
  // 3.5 against 4.4); within a factor 1.5 either way.
  EXPECT_GT(se, std::sqrt(var) / 1.5);
  EXPECT_LT(se, std::sqrt(var) * 1.5);
  // alpha 0.01 with nothing to find: at most 1 % (binomial s.d. 0.16 %; measured 0.4 %), here
  // without the Holm factor and the held-out check that diagnose adds.
  EXPECT_LE(accepted, 0.01 * kTrials);
}

// How often a candidate moving the model from `before_model` to `at_model` is accepted over
// kTrials recordings of `at_model`: on one look of 6 members each at alpha 0.01, and by the
// sequential test diagnose runs (each look at 0.005; an undecided first look gets 6 more
// members for both ensembles). Without diagnose's Holm factor and held-out check.
struct Acceptances {
  int single = 0, sequential = 0, second_looks = 0;
};
Acceptances acceptances(const FeatureModel& before_model, const FeatureModel& at_model, std::mt19937& rng) {
  auto passes_at = [](double alpha) {
    return [alpha](const FittedCandidate& f) { return f.p_value < alpha && f.delta_bic > 0; };
  };
  Acceptances a;
  for (int trial = 0; trial < kTrials; ++trial) {
    std::vector<Features> before = before_model.ensemble(rng), at = at_model.ensemble(rng);
    const Features recorded = at_model.recording(rng);
    FittedCandidate f;
    auto look = [&] {
      const Target t = target_of(recorded, {before, at});
      const Drop d = ensemble_drop(t, before, t, at, false);
      score(f, d, t.count(false));
      return std::pair{d, t.count(false)};
    };
    const auto [first, n] = look();
    a.single += passes_at(0.01)(f);
    if (passes_at(0.005)(f)) {
      ++a.sequential;
    } else if (undecided(f, first, n, passes_at(0.005))) {
      ++a.second_looks;
      for (const Features& m : before_model.ensemble(rng)) before.push_back(m);
      for (const Features& m : at_model.ensemble(rng)) at.push_back(m);
      look();
      a.sequential += passes_at(0.005)(f);
    }
  }
  return a;
}

TEST(DiagnosisStatistics, TheSecondLookKeepsTheFalseAcceptanceRateAtAlpha) {
  std::mt19937 rng(17);
  const FeatureModel model(rng);
  const Acceptances a = acceptances(model, model, rng);
  std::printf("measured: nothing to find, accepted %d (sequential) and %d (one look) of %d; %d second looks\n",
              a.sequential, a.single, kTrials, a.second_looks);
  // Two looks at alpha / 2 each (Bonferroni over the looks): at most alpha = 1 % (binomial
  // s.d. 0.16 %; measured 0.53 %, one look at alpha 0.85 %; 9 % of the trials look twice).
  EXPECT_LE(a.sequential, 0.01 * kTrials);
}

TEST(DiagnosisStatistics, TheSecondLookFindsAnEffectOneLookCannotTell) {
  // An effect that moves every feature by 0.6 of its scatter: the recording's chi2 against the
  // model without it is about 40 x 0.36 = 14 higher, of the order of a 6-member drop's
  // Monte Carlo bound (2 s.e.), where one look often cannot decide. Measured over shifts of
  // 0.2-0.8 s.d.: the sequential test accepts 0.72 and 0.92 times as often as one look at twice
  // its level at 0.2 and 0.3 (where either accepts 1-3 %), 1.2-1.3 times from 0.4 up.
  std::mt19937 rng(19);
  const FeatureModel before(rng);
  FeatureModel at = before;
  for (int i = 0; i < kFeatures; ++i) at.mean[i] += 0.6 * at.sd[i];
  const Acceptances a = acceptances(before, at, rng);
  std::printf("measured: accepted %d (sequential) and %d (one look) of %d; %d second looks\n", a.sequential, a.single,
              kTrials, a.second_looks);
  // Measured 1203 against 914 (1.32); each count's binomial s.d. about 30, so the ratio is
  // known to +-0.06: at least 1.15 (3 s.d. below).
  EXPECT_GT(a.sequential, 1.15 * a.single);
}

// A one-parameter candidate fitted on the fit set and judged as diagnose judges it (compare):
// theta moves feature i by theta a_i sd_i, and the model as given has theta = 0. theta is
// fitted by least squares to the recording on the fit set alone, and the candidate's ensemble
// is the model's members moved by it (paired, as diagnose's common random numbers). Counted:
// acceptances when the drop is taken on the fit set (the rule until 2026-11-28) and on every
// feature, each with BIC and a positive held-out drop.
struct FittedAcceptances {
  int fit_set = 0, every_feature = 0;
};
FittedAcceptances fitted_on_fit_set(const FeatureModel& model, const std::vector<double>& a, double truth,
                                    std::mt19937& rng) {
  const auto moved = [&](Features f, double theta) {
    for (int i = 0; i < kFeatures; ++i) f[model.name(i)].value += theta * a[i] * model.sd[i];
    return f;
  };
  FittedAcceptances n;
  for (int trial = 0; trial < kTrials; ++trial) {
    const std::vector<Features> before = model.ensemble(rng);
    const Features recorded = moved(model.recording(rng), truth);
    double num = 0, den = 0;
    for (int i = 0; i < kFeatures; i += 2) {  // the fit set: the even features (target_with_held_out)
      num += a[i] * (recorded.at(model.name(i)).value - model.mean[i]) / model.sd[i];
      den += a[i] * a[i];
    }
    std::vector<Features> at;
    for (const Features& m : before) at.push_back(moved(m, num / den));
    const Target t = target_with_held_out(recorded, {before, at});
    const bool held = ensemble_drop(t, before, t, at, true).value > 0;
    FittedCandidate f;
    score(f, ensemble_drop(t, before, t, at, false), t.count(false));
    n.fit_set += held && f.p_value < 0.01 && f.delta_bic > 0;
    score(f, ensemble_drop(t, before, t, at, std::nullopt), t.count());
    n.every_feature += held && f.p_value < 0.01 && f.delta_bic > 0;
  }
  return n;
}

std::vector<double> directions(std::mt19937& rng, double fit_weight) {
  std::normal_distribution<double> n(0, 1);
  std::vector<double> a;
  for (int i = 0; i < kFeatures; ++i) a.push_back((i % 2 ? 1.0 : fit_weight) * n(rng));
  return a;
}

// The trials of fitted_on_fit_set with seed `seed`, printed as `what`.
FittedAcceptances measured_acceptances(const char* what, unsigned seed, double fit_weight, double truth) {
  std::mt19937 rng(seed);
  const FeatureModel model(rng);
  const FittedAcceptances n = fitted_on_fit_set(model, directions(rng, fit_weight), truth, rng);
  std::printf("measured: %s, accepted %d (every feature) and %d (fit set) of %d\n", what, n.every_feature,
              n.fit_set, kTrials);
  return n;
}

TEST(DiagnosisStatistics, AValueFittedOnTheFitSetJudgedOnEveryFeatureKeepsAlpha) {
  // Nothing to find: the held-out part of the drop, at a value fitted to the fit set's chance
  // features, has mean <= 0, so counting it keeps the test at its level.
  const FittedAcceptances n = measured_acceptances("nothing to find", 23, 1.0, 0.0);
  // At most alpha = 1 % (binomial s.d. 0.16 %), without diagnose's Holm factor. Measured 0.75 %
  // (the fit set alone 0.2 %: counting the held-out features spends more of alpha, not beyond it).
  EXPECT_LE(n.every_feature, 0.01 * kTrials);
}

TEST(DiagnosisStatistics, AnEffectThatShowsLateIsFoundOnEveryFeature) {
  // An effect that moves the held-out (later) features four times as much as the fit set's,
  // as a table pitch that builds up over the record (case13 of the second case set).
  const FittedAcceptances n = measured_acceptances("a late effect", 29, 0.25, 2.0);
  // Measured 3806 against 728 of 4000 (binomial s.d. about 25 each): at least twice as often.
  EXPECT_GT(n.every_feature, 2 * n.fit_set);
}

}  // namespace
}  // namespace freestand::diagnosis
