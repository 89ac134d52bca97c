// freestand diagnose on recordings the simulator made with one known effect
// plus noise: the diagnosis must name the effect and recover its parameter;
// with no effect it must find no missing physics; bad input is refused.

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>

#include "calibration.h"
#include "diagnosis.h"
#include "diagnosis_report.h"
#include "diagnosis_verdict.h"
#include "freestand/input_error.h"
#include "../reference/housner.h"
#include "diagnosis_statistics.h"
#include "scenario.h"
#include "signal_tools.h"
#include "synthetic_motion.h"
#include "synthetic_recording.h"
#include "temp_dir.h"

namespace freestand {
namespace {

using nlohmann::json;

const double kStiffness = 2e7;  // N/m^3 per area, as in test_calibration.cpp: rocking feels it
const double kMu = 0.6;

// A 0.2 x 0.2 x 0.6 m, 60 kg block released at rest tilted by half its
// slenderness about y (pivot on the +x edge), rocking freely for 1.5 s.
json rocking_scenario(double restitution) {
  const double b = 0.1, tilt = 0.5 * std::atan(1.0 / 3.0);
  return {{"bodies", {{{"name", "block"}, {"shape", "box"}, {"half_extents", {b, b, 0.3}}, {"mass", 60.0},
                       {"position", {b - b * std::cos(tilt), 0.0, b * std::sin(tilt)}},
                       {"orientation", {std::cos(tilt / 2), 0.0, std::sin(tilt / 2), 0.0}},
                       {"nodes", {{"layout", "vertices"}}}}}},
          {"interfaces", {{{"lower", "table"}, {"upper", "block"}, {"mu", kMu}, {"restitution", restitution}}}},
          {"contact", {{"stiffness", kStiffness}}},
          {"simulation", {{"duration", 1.5}, {"time_step", 1e-4}, {"output_rate", 200}}}};
}

// The model diagnosed: the same numerics, the recording supplies bodies and interfaces.
json model(double restitution) {
  return {{"simulation", {{"time_step", 1e-4}}},
          {"contact", {{"stiffness", kStiffness}, {"restitution", restitution}, {"mu", kMu}}}};
}

// The reported s.e. against the known truth: the error within 3 s.e. (99.7 % for a calibrated
// s.e.), and the s.e. under a quarter of the truth (fine enough for the 25 % recovery target;
// an s.e. as wide as the range would pass the first check by saying nothing). A log-scale
// parameter's s.e. is of its natural log: the error and the quarter are relative.
void expect_standard_error_covers(const diagnosis::FittedCandidate& fit, double truth) {
  const bool log = fit.candidate.log_scale;
  const double error = log ? std::log(fit.value / truth) : fit.value - truth;
  std::cout << fmt::format("measured: {} = {:.4g} (s.e. {:.3g}{}) for {:.4g}\n", fit.candidate.name, fit.value,
                           fit.standard_error, log ? " in log" : "", truth);
  EXPECT_LT(std::abs(error), 3 * fit.standard_error) << fit.candidate.name << " = " << fit.value;
  EXPECT_LT(fit.standard_error, 0.25 * (log ? 1.0 : std::abs(truth))) << fit.candidate.name;
}

// Only rock_x carries the motion; the other channels are dropped so that the
// search stays small (restitution, stiffness, COM x and y) and the test fast.
Recording rocking_recording(const json& truth, const test::TempDir& dir, unsigned seed) {
  Recording r = synthetic_recording(truth, dir / "truth", {1e-3, 5e-4, seed});
  for (json& b : r.nominal["bodies"]) b.erase("com");  // concealed: the experimenter believes it centred
  std::vector<RecordingChannel> kept;
  for (const RecordingChannel& c : r.channels)
    if (c.name == "block.rock_x" || c.name == "block.rock_y") kept.push_back(c);
  r.channels = kept;
  r.nominal["sensor_noise"] = {{"angle", 1e-3}, {"length", 5e-4}};
  r.path = "synthetic_rocking";
  return r;
}

diagnosis::Options fast_options(const test::TempDir& dir) {
  diagnosis::Options o;
  o.ensemble = 4;
  o.max_effects = 2;
  o.sensor_gain_sd = 0;  // synthetic_recording reads through exact sensors, and the test says so
  o.work_directory = dir / "runs";
  return o;
}

// Truth e = 0.35 (between grid points of the profile), model e = 0.6: the amplitudes after each impact differ by a
// factor of ~2, far beyond the noise (1 mrad on 0.16 rad). Tolerance on the
// recovered value: 0.05, twice the fit's s.e. (0.025, which expect_standard_error_covers checks
// against the truth); the value is the refined profile's parabola minimum, between points at
// most 0.06 in e apart (a bracket of at most 0.59 of [0.02, 0.95], each side cut in thirds
// twice: a ninth of it).
diagnosis::Diagnosis diagnose_restitution(const test::TempDir& dir, const diagnosis::Options& o) {
  const Recording recording = rocking_recording(rocking_scenario(0.35), dir, 11);
  const diagnosis::Diagnosis d = diagnosis::diagnose(model(0.6), {recording}, o);
  std::cerr << d.verdict;
  EXPECT_FALSE(d.effects.empty());
  if (d.effects.empty()) return d;
  EXPECT_EQ(d.effects.front().fit.candidate.entry, "restitution");
  EXPECT_NEAR(d.effects.front().fit.value, 0.35, 0.05);
  expect_standard_error_covers(d.effects.front().fit, 0.35);
  EXPECT_GT(d.effects.front().fit.held_out_delta, 0);
  // The profile reported (--json) is the one fitted: every point, by value, lowest at the
  // parabola's bracket (the value lies between the lowest point's neighbours).
  const auto& profile = d.effects.front().fit.profile;
  EXPECT_EQ(static_cast<int>(profile.size()), d.effects.front().fit.evaluations);
  EXPECT_TRUE(std::is_sorted(profile.begin(), profile.end()));
  const auto lowest = std::min_element(profile.begin(), profile.end(), [](auto& a, auto& b) { return a.second < b.second; });
  if (lowest != profile.begin() && lowest + 1 != profile.end()) {
    EXPECT_GT(d.effects.front().fit.value, (lowest - 1)->first);
    EXPECT_LT(d.effects.front().fit.value, (lowest + 1)->first);
  }
  return d;
}

// A recording read through sensors whose gains are known to 1 % (a lab's calibration) is one
// more draw of a right model only when the members are read with such gains too: a 0.2 rad
// rocking amplitude then carries a 2e-3 rad error, 4 angle-noise s.d., that no member shows,
// and the misfit it adds is what a candidate that scales amplitudes (a narrower base, a
// softer contact) would be credited with. Free rocking has no chaos, so the members differ
// only in what the sensors add; the reference is the 99 % noise limit's rate.
TEST(DiagnosisMeasurement, ChannelGainsKeepARightModelWithinItsNoiseLimit) {
  using diagnosis::Features, diagnosis::Target, diagnosis::chi2_quantile_99;
  const reference::HousnerBlock block{0.2, 0.6};
  const double noise = 5e-4, gain_sd = 0.01;
  const test::SyntheticRocking rocking = test::free_rocking(block.p(), block.alpha(), block.e(), 0.2, 0.005, 4.0);
  Recording motion;
  motion.nominal = {{"bodies", {{{"name", "block"}, {"shape", "box"}, {"half_extents", {0.2, 0.2, 0.6}},
                                 {"mass", 500.0}, {"supported_by", "table"}}}},
                    {"sampling_hz", 200},
                    {"sensor_noise", {{"angle", noise}, {"length", noise}}}};
  motion.time = rocking.t;
  motion.channels.push_back({"block.rock_x", rocking.theta});
  auto read = [&](unsigned seed, double sd) {
    Recording r = motion;
    add_measurement_noise(r, {noise, noise, seed, sd});
    return diagnosis::event_features(r, r.nominal);
  };
  const int trials = 300;
  int beyond_with = 0, beyond_without = 0;
  for (int trial = 0; trial < trials; ++trial) {
    const Features recorded = read(1000000 + trial, gain_sd);  // seeds apart from the members'
    std::vector<Features> with, without;
    for (unsigned m = 0; m < 6; ++m)
      with.push_back(read(100 * trial + m, gain_sd)), without.push_back(read(100 * trial + m, 0));
    const Target t_with = diagnosis::target_of(recorded, {with}), t_without = diagnosis::target_of(recorded, {without});
    beyond_with += t_with.ensemble_chi2(with) > chi2_quantile_99(static_cast<int>(t_with.recorded.size()));
    beyond_without += t_without.ensemble_chi2(without) > chi2_quantile_99(static_cast<int>(t_without.recorded.size()));
  }
  std::cout << fmt::format("measured: beyond the 99 % noise limit in {} of {} trials with the members' gains, {} "
                           "without\n", beyond_with, trials, beyond_without);
  // 1 % expected (3 of 300, binomial s.d. 1.7); the predictive z is conservative (step 2): at
  // most 3 %. Without the gains, 5 %: 7 s.d. above the 1 % a right model should show (measured
  // 28 of 300, 2.6 s.d. of that count above the bound).
  EXPECT_LE(beyond_with, 0.03 * trials);
  EXPECT_GT(beyond_without, 0.05 * trials);
}

TEST(Diagnosis, NamesAndRecoversRestitution) {
  test::TempDir dir;
  const diagnosis::Diagnosis d = diagnose_restitution(dir, fast_options(dir));
  ASSERT_FALSE(d.effects.empty());
  EXPECT_FALSE(d.mismatches.empty());  // the model as given was located as wrong
  // The model as given is beyond the 99 % noise limit, the improved one within it (a right
  // model's misfit is a chi2 draw: 21.6 for 24 features, measured).
  EXPECT_GT(d.chi2_nominal, d.chi2_noise_limit);
  EXPECT_LT(d.chi2_final, d.chi2_noise_limit);
  EXPECT_NEAR(d.improved["interfaces"][0]["restitution"].get<double>(), d.effects.front().fit.value, 1e-12);
  EXPECT_TRUE(d.measurement.empty());  // no delay or gain was put in
  // The report overlays the mismatched channel and lists the accepted candidate.
  HtmlReport report("diagnosis");
  diagnosis::add_diagnosis_sections(report, d);
  const std::string html = report.html();
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_NE(html.find("block.rock_x"), std::string::npos);
  EXPECT_NE(html.find("improved model"), std::string::npos);
  EXPECT_NE(html.find("restitution[table/block]"), std::string::npos);
}

// The same recording with every profile point run as the ensemble's first two members, their
// chi2 averaged (--profile-members 2): the profiles' baseline, their points, the refinement and
// the sensor candidates' baseline must all take the same members, or the drops mix a member's
// jitter into the ranking. Same truth and tolerances as above: the averaged profile is as smooth
// in e as one member's, so the refined value must stay within the same 0.05.
TEST(Diagnosis, ProfilesOverTwoMembersNameTheSameRestitution) {
  test::TempDir dir;
  diagnosis::Options o = fast_options(dir);
  o.profile_members = 2;
  const diagnosis::Diagnosis d = diagnose_restitution(dir, o);
  EXPECT_LT(d.chi2_final, d.chi2_noise_limit);
}

// The catalogue's `similar` lists are symmetric, and body candidates are alike only on one body:
// a tower's COM offset meets the tower's inset, not the pedestal's, nor the pedestal's COM.
TEST(DiagnosisCatalogue, SimilarSignaturesAreSymmetricAndBodyCandidatesMeetOnTheirOwnBody) {
  for (const diagnosis::CatalogueEntry& e : diagnosis::catalogue())
    for (const std::string& other : e.similar) {
      const diagnosis::CatalogueEntry* back = diagnosis::catalogue_entry(other);
      ASSERT_NE(back, nullptr) << e.name << " lists " << other;
      EXPECT_EQ(std::count(back->similar.begin(), back->similar.end(), e.name), 1) << other << " -> " << e.name;
    }
  const auto candidate = [](const std::string& entry, const std::string& where) {
    diagnosis::Candidate c;
    c.entry = entry, c.where = where;
    return c;
  };
  const auto com = candidate("com_offset_x", "tower");
  EXPECT_TRUE(diagnosis::of_similar_signature(com, candidate("edge_inset", "tower")));
  EXPECT_TRUE(diagnosis::of_similar_signature(candidate("edge_inset", "tower"), com));
  EXPECT_FALSE(diagnosis::of_similar_signature(com, candidate("edge_inset", "pedestal")));
  EXPECT_FALSE(diagnosis::of_similar_signature(com, candidate("com_offset_x", "tower")));  // not listed: the same entry
  EXPECT_TRUE(diagnosis::of_similar_signature(com, candidate("table_pitch", "table")));
  EXPECT_TRUE(diagnosis::of_similar_signature(candidate("edge_inset", "pedestal"),
                                              candidate("interface_compliance", "pedestal/tower")));
  EXPECT_FALSE(diagnosis::of_similar_signature(candidate("sensor_delay", "tower"), com));  // no catalogue entry
}

// A variant of the model with a stiffer or more damped contact rings faster than the model, and
// keeps the model's share of its critical step. References: the exact scaling of the modes,
// omega ~ sqrt(k) with a restitution's zeta the same at every stiffness (ten times the stiffness
// takes the step divided by sqrt(10), to round-off), and the runs themselves: each variant is
// refused at the model's step (by `freestand run`'s check, the fix's computation, whose limit
// ContactTimeStep.RestingBlockLimitIsSharp shows is where Verlet blows up) and runs at its kept
// one. A softer contact keeps the step (a variant is never run coarser than the model).
TEST(DiagnosisNumerics, AVariantKeepsTheModelsShareOfItsCriticalStep) {
  test::TempDir dir;
  json truth = rocking_scenario(0.3);
  truth["simulation"]["duration"] = 0.3;
  const Recording recording = rocking_recording(truth, dir, 3);
  json document = recording_scenario(model(0.3), recording, "table_motion.csv");
  document["simulation"]["time_step"] = 2e-3;
  const double share = step_share(document);
  EXPECT_GT(share, 0.3);
  EXPECT_LT(share, 0.7);
  const std::vector<diagnosis::Candidate> all = diagnosis::candidates_for(document, recording, 0, nullptr);
  const auto entry = [&](const std::string& name) {
    const auto c = std::find_if(all.begin(), all.end(), [&](const diagnosis::Candidate& x) { return x.entry == name; });
    EXPECT_NE(c, all.end()) << name;
    return *c;
  };
  json stiff = document, soft = document;
  entry("contact_stiffness").apply(stiff, 10 * kStiffness);
  EXPECT_THROW(simulate_recording(stiff, recording, dir / "stiff_as_given"), std::exception);
  keep_step_share(stiff, share);
  EXPECT_NEAR(stiff["simulation"]["time_step"].get<double>(), 2e-3 / std::sqrt(10.0), 1e-9 * 2e-3);
  EXPECT_NO_THROW(simulate_recording(stiff, recording, dir / "stiff"));
  entry("contact_stiffness").apply(soft, kStiffness / 10);
  keep_step_share(soft, share);
  EXPECT_EQ(soft["simulation"]["time_step"], 2e-3);

  // Restitution's low end: heavy damping shortens Verlet's critical step by sqrt(1 + zeta^2) -
  // zeta (0.60 from e = 0.3 to e = 0.02), so a model run at 0.9 of its critical step loses it.
  document["simulation"]["time_step"] = 0.9 * 2e-3 / share;
  json damped = document;
  entry("restitution").apply(damped, 0.02);
  EXPECT_THROW(simulate_recording(damped, recording, dir / "damped_as_given"), std::exception);
  keep_step_share(damped, step_share(document));
  EXPECT_LT(damped["simulation"]["time_step"].get<double>(), 0.8 * document["simulation"]["time_step"].get<double>());
  EXPECT_NO_THROW(simulate_recording(damped, recording, dir / "damped"));
}

// The centre of mass 12 mm off the axis toward the pivot edge (of b = 100 mm):
// the block rocks on +x edge with a smaller lever arm, on -x with a larger one,
// so the half-cycles on the two sides differ. Tolerance 3 mm: the last
// refinement's spacing (a bracket of 0.15 of 50 mm, each side cut in thirds twice: 0.8 mm) is finer; the rest is the
// trade-off with restitution, which also changes the amplitudes, allowed at
// a quarter of the offset.
TEST(Diagnosis, NamesAndRecoversCentreOfMassOffset) {
  test::TempDir dir;
  json truth = rocking_scenario(0.3);
  truth["bodies"][0]["com"] = {0.012, 0.0, 0.3};
  const Recording recording = rocking_recording(truth, dir, 13);
  const diagnosis::Diagnosis d = diagnosis::diagnose(model(0.3), {recording}, fast_options(dir));
  std::cerr << d.verdict;
  ASSERT_FALSE(d.effects.empty());
  EXPECT_EQ(d.effects.front().fit.candidate.entry, "com_offset_x");
  EXPECT_EQ(d.effects.front().verdict, "missing physics");  // the nominal states no com
  EXPECT_NEAR(d.effects.front().fit.value, 0.012, 0.003);
  expect_standard_error_covers(d.effects.front().fit, 0.012);
  // An inset edge also brings a pivot nearer the centre of mass (similar signature): where its
  // profile dropped, it met the offset on the ensemble (a Monte Carlo s.e.) and was not named.
  const auto& round = d.rounds.front();
  const auto inset = std::find_if(round.begin(), round.end(),
                                  [](const auto& f) { return f.candidate.name == "edge_inset[block]"; });
  ASSERT_NE(inset, round.end());
  const auto& similar = d.effects.front().similar;
  if (std::any_of(similar.begin(), similar.end(), [](const auto& s) { return s.first == "edge_inset[block]"; }))
    EXPECT_GT(inset->delta_se, 0);
}

// The closing verdict is read on twice the members where the first M put the misfit beyond the
// noise limit (a Monte Carlo estimate against chi2's limit), and on M where they did not. A 12 mm
// COM offset with no effect allowed stays beyond the limit on 2 M (measured: 304.0 on 8 members
// against 48.3); the model with the truth reads within it on M (13.3 on 4).
// Members are counted over every recording (two recordings of the truth).
TEST(Diagnosis, ReadsTheClosingVerdictOnMoreMembersWhereTheMisfitIsBeyondTheLimit) {
  test::TempDir dir;
  json truth = rocking_scenario(0.3);
  truth["bodies"][0]["com"] = {0.012, 0.0, 0.3};
  const Recording recording = rocking_recording(truth, dir, 13);
  diagnosis::Options o = fast_options(dir);
  o.max_effects = 0;
  const diagnosis::Diagnosis off = diagnosis::diagnose(model(0.3), {recording}, o);
  std::cerr << off.verdict;
  EXPECT_EQ(off.closing_members, 2 * o.ensemble);
  EXPECT_GT(off.chi2_final, off.chi2_noise_limit);
  EXPECT_NE(off.verdict.find("Unexplained"), std::string::npos);
  Recording stated = recording;  // the nominal states the truth's COM
  stated.nominal["bodies"][0]["com"] = truth["bodies"][0]["com"];
  const diagnosis::Diagnosis on = diagnosis::diagnose(model(0.3), {stated}, o);
  EXPECT_EQ(on.closing_members, o.ensemble);
  EXPECT_LE(on.chi2_final, on.chi2_noise_limit);
  // A member is one run of every recording: with two it is still counted once (the cube tosses
  // read "on 1 members" for 12 over 10 recordings before).
  const diagnosis::Diagnosis two = diagnosis::diagnose(model(0.3), {stated, stated}, o);
  EXPECT_EQ(two.closing_members, two.chi2_final > two.chi2_noise_limit ? 2 * o.ensemble : o.ensemble);
  std::cout << fmt::format("measured: closing misfit {:.1f} on {} members (COM as given 0), {:.1f} on {} (the truth's)\n",
                           off.chi2_final, off.closing_members, on.chi2_final, on.closing_members);
}

// Rounded edges: the block rocks on edges 15 mm inside its 100 mm half-width, so it rocks at a
// lower slenderness (faster, from a lower threshold) on both sides alike. Tolerance 3 mm: the last
// refinement's spacing is 0.8 mm (a bracket of 0.15 of the 50 mm range, each side in thirds twice); the
// rest is the trade-off with restitution, which also changes the decay, allowed as for the COM.
TEST(Diagnosis, NamesAndRecoversEdgeInset) {
  test::TempDir dir;
  json truth = rocking_scenario(0.3);
  truth["bodies"][0]["base"] = {{"edge_inset", 0.015}};
  Recording recording = rocking_recording(truth, dir, 14);
  for (json& b : recording.nominal["bodies"]) b.erase("base");  // concealed: the experimenter believes the edges sharp
  // The user suspects two causes (--hypothesis): the truth, and a centre of mass off by 10 mm.
  diagnosis::Options o = fast_options(dir);
  o.hypotheses = {{{"edge_inset[block]", 0.015}}, {{"com_offset_x[block]", 0.01}}};
  const diagnosis::Diagnosis d = diagnosis::diagnose(model(0.3), {recording}, o);
  std::cerr << d.verdict;
  ASSERT_FALSE(d.effects.empty());
  EXPECT_EQ(d.effects.front().fit.candidate.entry, "edge_inset");
  EXPECT_EQ(d.effects.front().verdict, "missing physics");
  EXPECT_NEAR(d.effects.front().fit.value, 0.015, 0.003);
  expect_standard_error_covers(d.effects.front().fit, 0.015);
  EXPECT_NEAR(d.improved["bodies"][0]["base"]["edge_inset"].get<double>(), d.effects.front().fit.value, 1e-12);
  // The misfits it gives are over the test's members (M, or 2M once undecided or settled), and
  // the verdict says so: a model far off reads a larger misfit on more members.
  const int members = d.effects.front().fit.members;
  EXPECT_TRUE(members == o.ensemble || members == 2 * o.ensemble) << members;
  EXPECT_NE(d.verdict.find(fmt::format("on {} members of each model", members)), std::string::npos);
  // A softer contact also moves the pivot inward: the verdict says it helped too (its profile
  // dropped 66.8 against the inset's more, measured), in words and in the JSON.
  const auto& similar = d.effects.front().similar;
  EXPECT_TRUE(std::any_of(similar.begin(), similar.end(),
                          [](const auto& s) { return s.first == "contact_stiffness[table/block]" && s.second > 0; }));
  EXPECT_NE(d.verdict.find("Of similar signature"), std::string::npos);
  EXPECT_EQ(diagnosis::diagnosis_json(d)["effects"][0]["similar_signature"].size(), similar.size());
  // ... and met the inset on the ensemble (a tested candidate has a Monte Carlo s.e.) and lost.
  const auto& round = d.rounds.front();
  const auto rival = std::find_if(round.begin(), round.end(),
                                  [](const auto& f) { return f.candidate.name == "contact_stiffness[table/block]"; });
  ASSERT_NE(rival, round.end());
  EXPECT_GT(rival->delta_se, 0);
  EXPECT_TRUE(d.effects.front().indistinguishable.empty());
  // The true cause stated as a hypothesis is supported and fits as the found inset does (the
  // same model up to the fit's error); the wrong one fits worse than the improved model.
  ASSERT_EQ(d.hypotheses.size(), 2u);
  EXPECT_TRUE(d.hypotheses[0].supported);
  EXPECT_EQ(d.hypotheses[0].against_improved, "alike");
  EXPECT_EQ(d.hypotheses[1].against_improved, "worse");
  EXPECT_EQ(diagnosis::diagnosis_json(d)["hypotheses"].size(), 2u);
  EXPECT_NE(d.verdict.find("Hypothesis 1: edge_inset[block] = 0.015 m"), std::string::npos);
  // Met with each other, the COM offset fits worse than the true inset.
  ASSERT_EQ(d.hypothesis_pairs.size(), 1u);
  EXPECT_EQ(d.hypothesis_pairs[0].second_fits, "worse");
}

// A contact seven times softer than stated (off the quick profile's 1.15, 1.8, 10 ladder, so
// the refinement must find it) also moves the pivot inward (the block sinks into its edge) and
// so lowers the rocking threshold, as an inset edge does: the two entries are of similar
// signature (catalogue), and the softer contact must be named, or the two said alike, not the
// inset alone. Tolerance: a factor 2 on k: rocking feels k only through how far the pivot edge
// sinks and how long an impact lasts, so the event features pin k loosely (the s.e. check
// states how loosely: x/ 1.20, measured).
TEST(Diagnosis, NamesASofterContactNotANarrowerBase) {
  test::TempDir dir;
  json truth = rocking_scenario(0.3);
  truth["contact"]["stiffness"] = kStiffness / 7;
  Recording recording = rocking_recording(truth, dir, 16);
  recording.nominal["contact"] = {{"stiffness", kStiffness}};  // what the experimenter believes
  const diagnosis::Diagnosis d = diagnosis::diagnose(model(0.3), {recording}, fast_options(dir));
  std::cerr << d.verdict;
  ASSERT_FALSE(d.effects.empty());
  const diagnosis::Effect& e = d.effects.front();
  const bool alike = std::any_of(e.indistinguishable.begin(), e.indistinguishable.end(),
                                 [](const auto& g) { return g.candidate.name == "contact_stiffness[table/block]"; });
  EXPECT_TRUE(e.fit.candidate.entry == "contact_stiffness" || alike) << e.fit.candidate.name;
  if (e.fit.candidate.entry == "contact_stiffness") {
    EXPECT_GT(e.fit.value, kStiffness / 14);
    EXPECT_LT(e.fit.value, kStiffness / 3.5);
    expect_standard_error_covers(e.fit, kStiffness / 7);
  }
}

// One corner short: released onto its +x edge, the block stands on the +x -y corner alone
// (the +x +y one is 3 mm short), so it also rolls about x, which no other candidate does with
// a symmetric base. Tolerance 1 mm: a third of the gap; the last refinement's spacing is 0.3 mm
// (0.15 of the +-10 mm range, each side in thirds twice), the rest is the trade-off with the COM in y.
TEST(Diagnosis, NamesAndRecoversShortCorner) {
  test::TempDir dir;
  json truth = rocking_scenario(0.3);
  truth["bodies"][0]["base"] = {{"corner_gaps", {{{"corner", {1.0, 1.0}}, {"gap", 0.003}}}}};
  Recording recording = rocking_recording(truth, dir, 15);
  for (json& b : recording.nominal["bodies"]) b.erase("base");
  const diagnosis::Diagnosis d = diagnosis::diagnose(model(0.3), {recording}, fast_options(dir));
  std::cerr << d.verdict;
  ASSERT_FALSE(d.effects.empty());
  EXPECT_EQ(d.effects.front().fit.candidate.name, "base_not_flat[block:+x+y]");
  EXPECT_NEAR(d.effects.front().fit.value, 0.003, 0.001);
  expect_standard_error_covers(d.effects.front().fit, 0.003);
}

// The model is the truth: nothing significant may be found.
//
// The SCENARIO here also states the block with another contact grid: the recording's nominal
// supplies the bodies, so that grid never runs, and the improved scenario must state the grid
// that did (the nominal's corners), or `freestand run` of it would simulate another model
// than the one judged (a distributed base rocks differently: study 18).
TEST(Diagnosis, NoEffectFindsNoMissingPhysics) {
  test::TempDir dir;
  const Recording recording = rocking_recording(rocking_scenario(0.3), dir, 12);
  diagnosis::Options o = fast_options(dir);
  o.max_effects = 1;
  json scenario = model(0.3);
  scenario["bodies"] = rocking_scenario(0.3)["bodies"];
  scenario["bodies"][0]["nodes"] = {{"layout", "surface"}, {"per_edge", 4}};
  const diagnosis::Diagnosis d = diagnosis::diagnose(scenario, {recording}, o);
  std::cerr << d.verdict;
  EXPECT_TRUE(d.effects.empty());
  EXPECT_NE(d.verdict.find("No missing physics found"), std::string::npos);
  EXPECT_EQ(d.improved["bodies"][0]["nodes"], recording.nominal["bodies"][0]["nodes"]);
  // The truth's own step, 1e-4 s (0.025 of the critical 3.9e-3 s): a quarter of it must read as
  // one more draw of the model (measured: 4.3 against a limit of 25, chi2's mean), and be kept.
  const auto step = std::find_if(d.numerics_checks.begin(), d.numerics_checks.end(),
                                 [](const diagnosis::NumericsCheck& c) { return c.quantity == "time step"; });
  ASSERT_NE(step, d.numerics_checks.end());
  std::cout << fmt::format("measured: time step check {:.1f} against {:.1f}\n", step->distance, step->limit);
  EXPECT_FALSE(step->adopted);
  EXPECT_EQ(d.improved["simulation"]["time_step"], 1e-4);
}

// Diagnoses `recording`, every channel already read through the system under test, against
// the model with the truth's restitution: a measurement issue of `whose` (a body's name, or
// kEveryBody) must be reported, no physics.
diagnosis::Diagnosis diagnose_system_issue(const Recording& recording, const test::TempDir& dir, const std::string& whose) {
  diagnosis::Options o = fast_options(dir);
  o.max_effects = 1;
  const diagnosis::Diagnosis d = diagnosis::diagnose(model(0.3), {recording}, o);
  std::cerr << d.verdict;
  EXPECT_TRUE(d.effects.empty());
  EXPECT_FALSE(d.measurement.empty());
  if (!d.measurement.empty()) EXPECT_EQ(d.measurement.front().channel, whose);
  return d;
}

// As diagnose_system_issue, with every channel shifted 40 ms late: that delay must be measured.
diagnosis::Diagnosis diagnose_clock_offset(Recording recording, const test::TempDir& dir, const std::string& whose) {
  for (RecordingChannel& c : recording.channels) {
    const std::vector<double> y = c.values;
    for (std::size_t k = 0; k < y.size(); ++k) c.values[k] = signal::interpolate(recording.time, y, recording.time[k] - 0.04);
  }
  const diagnosis::Diagnosis d = diagnose_system_issue(recording, dir, whose);
  if (d.measurement.empty()) return d;
  EXPECT_TRUE(d.measurement.front().delay_significant);
  EXPECT_NEAR(d.measurement.front().delay, 0.04, 0.01);
  return d;
}

// The block of the tests below released tilted toward its +x +y corner, so that both rock
// channels carry the motion.
json corner_released_block() {
  json truth = rocking_scenario(0.3);
  // Tilted by t about (-1, 1, 0)/sqrt(2), the +x +y corner (b, b, 0) kept in place: the base
  // centre goes to (b - b cos t, b - b cos t, sqrt(2) b sin t).
  const double b = 0.1, t = 0.5 * std::atan(std::sqrt(2.0) * b / 0.3);
  truth["bodies"][0]["position"] = {b - b * std::cos(t), b - b * std::cos(t), std::sqrt(2.0) * b * std::sin(t)};
  truth["bodies"][0]["orientation"] = {std::cos(t / 2), -std::sin(t / 2) / std::sqrt(2.0), std::sin(t / 2) / std::sqrt(2.0), 0.0};
  return truth;
}

// Every sensor of the block on another clock, 40 ms behind the table's (here the release at
// t = 0): the physics is the model's own, so the diagnosis must report a delay, a measurement
// issue, and name no physics. Both rock channels carry the motion: a delay of one channel
// explains half the late events, the body's clock all of them, and that is what must be named.
// A late record looks like a block that tips more slowly or rocks on a narrower base: without
// the candidate for a body's clock a chaotic tower's 80 ms was taken for a narrower base (case15
// of the proof study). Tolerance 10 ms: two steps of the delay grid (5 ms), which the event
// times (1 mrad noise on a 0.1 rad swing) resolve.
TEST(Diagnosis, MeasuresAClockOffsetOfABodysSensorsNotPhysics) {
  test::TempDir dir;
  const diagnosis::Diagnosis d = diagnose_clock_offset(rocking_recording(corner_released_block(), dir, 14), dir, "block");
  if (d.measurement.empty()) return;
  std::cout << fmt::format("measured: delay of {} = {:.4f} s for 0.04\n", d.measurement.front().channel,
                           d.measurement.front().delay);
}

// The corner-released block's recording with every one of its channels read `gain` times high
// (one calibration its sensors share).
Recording block_read_high(const test::TempDir& dir, double gain) {
  Recording recording = rocking_recording(corner_released_block(), dir, 14);
  for (RecordingChannel& c : recording.channels)
    if (c.name.rfind("block.", 0) == 0)
      for (double& v : c.values) v *= gain;
  return recording;
}

// Every sensor of the block read through one calibration 10 % high (a shared amplifier or ADC
// reference): the block rocks as the model says, so a gain of the body's system must be
// reported, not physics. A uniformly scaled record keeps the decay per impact but pairs each
// swing's half-period with an amplitude 10 % too large, which no physical candidate does to
// every event at once; one channel's gain explains half of it. Tolerance 0.02: two steps of
// the gain grid (0.01125), the amplitudes (0.1 rad against 1 mrad of noise) resolve 1 %.
TEST(Diagnosis, MeasuresAGainOfABodysSensorsNotPhysics) {
  test::TempDir dir;
  const Recording recording = block_read_high(dir, 1.1);
  const diagnosis::Diagnosis d = diagnose_system_issue(recording, dir, "block");
  if (d.measurement.empty()) return;
  EXPECT_TRUE(d.measurement.front().gain_significant);
  EXPECT_NEAR(d.measurement.front().gain, 1.1, 0.02);
  EXPECT_NE(d.verdict.find("every channel of block reads"), std::string::npos);
  std::cout << fmt::format("measured: gain of {} = {:.4f} +- {:.4f} for 1.1\n", d.measurement.front().channel,
                           d.measurement.front().gain, d.measurement.front().gain_sd);
}

// The same block read 50 % high, beyond any calibrated sensor and the gain's range (0.8-1.25):
// the fit of the body's gain still improves at 1.25, so it found no minimum and stands in for
// something else (case14 of the proof study: a table's vertical motion was taken for every
// body's gain at 1.25). It must not be reported as a measurement, and the notes must say why.
TEST(Diagnosis, TakesNoSensorGainThatStillImprovesAtItsRangeEnd) {
  test::TempDir dir;
  const Recording recording = block_read_high(dir, 1.5);
  diagnosis::Options o = fast_options(dir);
  o.max_effects = 1;
  const diagnosis::Diagnosis d = diagnosis::diagnose(model(0.3), {recording}, o);
  std::cerr << d.verdict;
  for (const diagnosis::MeasurementIssue& m : d.measurement)
    EXPECT_FALSE(m.gain_significant && m.gain > 1.24) << m.text;
  const auto note = std::find_if(d.notes.begin(), d.notes.end(), [](const std::string& n) {
    return n.find("sensor_gain[block.*] still improves at its range end") != std::string::npos;
  });
  EXPECT_NE(note, d.notes.end());
}

// Two blocks rocking freely side by side, every body channel 40 ms late (the specimen's
// acquisition on another clock than the table's): the delay of every body is named, not one
// body's, and it takes the evidence of both (its drop at least each body's own). Tolerance as
// above: 10 ms, two steps of the delay grid.
TEST(Diagnosis, MeasuresTheSpecimensClockOffsetOverEveryBody) {
  test::TempDir dir;
  json truth = rocking_scenario(0.3);
  json second = truth["bodies"][0];
  const double b = 0.1, t = 0.4 * std::atan(1.0 / 3.0);  // the other block tilted less, so it rocks apart
  second["name"] = "second";
  second["position"] = {b - b * std::cos(t), 0.6, b * std::sin(t)};
  second["orientation"] = {std::cos(t / 2), 0.0, std::sin(t / 2), 0.0};
  truth["bodies"].push_back(second);
  json joint = truth["interfaces"][0];
  joint["upper"] = "second";
  truth["interfaces"].push_back(joint);
  Recording recording = synthetic_recording(truth, dir / "truth", {1e-3, 5e-4, 17});
  std::vector<RecordingChannel> kept;
  for (const RecordingChannel& c : recording.channels)
    if (c.name.find(".rock_") != std::string::npos) kept.push_back(c);
  recording.channels = kept;
  for (json& body : recording.nominal["bodies"]) body.erase("com");
  recording.path = "synthetic_two_blocks";
  const diagnosis::Diagnosis d = diagnose_clock_offset(recording, dir, diagnosis::kEveryBody);
  if (d.measurement.empty()) return;
  EXPECT_NE(d.verdict.find("every channel of every body lags"), std::string::npos);
  ASSERT_FALSE(d.rounds.empty());
  std::map<std::string, double> drop;  // round 1's profile drop of each clock
  for (const diagnosis::FittedCandidate& f : d.rounds.front()) drop[f.candidate.name] = f.delta;
  ASSERT_EQ(drop.count("sensor_delay[*.*]"), 1u);
  EXPECT_GE(drop["sensor_delay[*.*]"], std::max(drop["sensor_delay[block.*]"], drop["sensor_delay[second.*]"]));
  std::cout << fmt::format("measured: delay of every body = {:.4f} s for 0.04\n", d.measurement.front().delay);
}

// The truth rocks on a distributed base (surface grid, 8 segments per edge); the recording
// states no grid, so the model starts on the default corners. The numerics check must see
// that the finest grid is not a draw of the corner model, refine before looking for physics,
// and then find nothing missing: an unconverged grid must not pass for an effect.
TEST(Diagnosis, RefinesAnUnconvergedContactGridBeforeLookingForPhysics) {
  test::TempDir dir;
  json truth = rocking_scenario(0.3);
  truth["bodies"][0]["nodes"] = {{"layout", "surface"}, {"per_edge", 8}};
  Recording recording = rocking_recording(truth, dir, 16);
  for (json& b : recording.nominal["bodies"]) b.erase("nodes");
  diagnosis::Options o = fast_options(dir);
  o.max_effects = 1;
  const diagnosis::Diagnosis d = diagnosis::diagnose(model(0.3), {recording}, o);
  std::cerr << d.verdict;
  ASSERT_FALSE(d.numerics_checks.empty());
  EXPECT_EQ(d.numerics_checks.front().quantity, "contact grid");
  EXPECT_TRUE(d.numerics_checks.front().adopted);  // measured: 188 against a limit of 21 (n)
  const json& nodes = d.improved["bodies"][0]["nodes"];  // the refined grid is the improved model's
  EXPECT_EQ(nodes.value("layout", ""), "surface");
  EXPECT_GE(nodes.value("per_edge", 0), 2);
  EXPECT_TRUE(d.effects.empty());
  EXPECT_NE(d.verdict.find("No missing physics found"), std::string::npos);
}

// A grid converged for the model as given need not be for a softer contact (study 18 of
// docs/diagnose.md): the block is believed stiffer (10 x kStiffness) than it is (7 times
// softer than that, on a distributed base, 8 per edge). The grid check at the nominal converges
// on a grid coarser than the finest (measured: 4 per edge); the check
// at the softest stiffness the profile reaches must then adopt the finest grid, and the
// search, on it, name the softer contact. Tolerance on k: a factor 2, as in
// NamesASofterContactNotANarrowerBase (rocking pins k loosely).
TEST(Diagnosis, RefinesTheGridForTheSoftContactsItWillTest) {
  test::TempDir dir;
  const double believed = 10 * kStiffness, truth_k = believed / 7;
  json truth = rocking_scenario(0.3);
  truth["contact"]["stiffness"] = truth_k;
  truth["bodies"][0]["nodes"] = {{"layout", "surface"}, {"per_edge", 8}};
  Recording recording = rocking_recording(truth, dir, 17);
  for (json& b : recording.nominal["bodies"]) b.erase("nodes");
  recording.nominal["contact"] = {{"stiffness", believed}};
  json scenario = model(0.3);
  scenario["contact"]["stiffness"] = believed;
  diagnosis::Options o = fast_options(dir);
  o.max_effects = 1;
  const diagnosis::Diagnosis d = diagnosis::diagnose(scenario, {recording}, o);
  std::cerr << d.verdict;
  std::vector<diagnosis::NumericsCheck> grid;
  std::copy_if(d.numerics_checks.begin(), d.numerics_checks.end(), std::back_inserter(grid),
               [](const diagnosis::NumericsCheck& c) { return c.quantity == "contact grid"; });
  ASSERT_GE(grid.size(), 2u);
  const diagnosis::NumericsCheck& as_given = grid[grid.size() - 2];
  const diagnosis::NumericsCheck& soft = grid.back();
  EXPECT_EQ(as_given.model, "as given");
  EXPECT_FALSE(as_given.adopted);  // converged for the nominal on a grid coarser than the finest (measured: 4 per edge)
  EXPECT_EQ(soft.model.rfind("with soft contacts", 0), 0u);
  EXPECT_TRUE(soft.adopted);
  for (const diagnosis::NumericsCheck& c : d.numerics_checks)
    std::cout << fmt::format("measured: {} check {}: {:.1f} against {:.1f}\n", c.quantity, c.model, c.distance, c.limit);
  EXPECT_EQ(d.improved["bodies"][0]["nodes"].value("per_edge", 0), 8);
  ASSERT_FALSE(d.effects.empty());
  const diagnosis::Effect& e = d.effects.front();
  EXPECT_EQ(e.fit.candidate.entry, "contact_stiffness");
  if (e.fit.candidate.entry == "contact_stiffness") {
    EXPECT_GT(e.fit.value, truth_k / 2);
    EXPECT_LT(e.fit.value, truth_k * 2);
    expect_standard_error_covers(e.fit, truth_k);
  }
}

// A block rocks for 1.9 s and then rests. A drift of 1 mrad/s added to its rock_x channel
// must be measured where the recording and the simulation both rest (until the drift itself
// tilts the channel beyond the rest threshold at about 3.5 s: 1.6 s of 1 mrad noise at 200 Hz,
// slope s.d. 0.12 mrad/s; tolerance 0.3 mrad/s, 2.5 s.d.; measured 0.94), and the same
// recording without it must report none.
TEST(Diagnosis, MeasuresASensorDriftOnlyWhereThereIsOne) {
  test::TempDir dir;
  json truth = rocking_scenario(0.3);
  truth["simulation"]["duration"] = 6.0;
  const Recording clean = rocking_recording(truth, dir, 17);
  Recording drifting = clean;
  for (RecordingChannel& c : drifting.channels)
    if (c.name == "block.rock_x")
      for (std::size_t k = 0; k < c.values.size(); ++k) c.values[k] += 0.001 * (drifting.time[k] - drifting.time.front());
  diagnosis::Options o = fast_options(dir);
  o.max_effects = 0;
  auto drifts = [&](const Recording& r) {
    std::vector<diagnosis::MeasurementIssue> out;
    for (const diagnosis::MeasurementIssue& m : diagnosis::diagnose(model(0.3), {r}, o).measurement)
      if (m.drift_significant) out.push_back(m);
    return out;
  };
  EXPECT_TRUE(drifts(clean).empty());
  const std::vector<diagnosis::MeasurementIssue> found = drifts(drifting);
  ASSERT_EQ(found.size(), 1u);
  std::cerr << found.front().text << "\n";
  EXPECT_EQ(found.front().channel, "block.rock_x");
  EXPECT_NEAR(found.front().drift, 0.001, 3e-4);
}

// The scenario commands a 3 Hz table motion of 0.3 m/s^2 (far below the block's uplift at
// g b/h = 3.3 m/s^2 and sliding at 5.9 m/s^2: it stands still), but the table lagged it by
// 12 ms at 97 % of its amplitude. Diagnose must report that as a measurement issue (within
// 4 of its reported s.d.), find no physics missing (the simulations replay the recorded
// table), and never move the model.
TEST(Diagnosis, ReportsATableThatLaggedItsCommand) {
  test::TempDir dir;
  std::string record = "t,command,table\n";
  const auto command = [](double t) { return t <= 0 ? 0.0 : 0.3 * std::sin(2 * M_PI * 3 * t) * std::min(1.0, t / 0.3); };
  for (int k = 0; k <= 1600; ++k)
    record += fmt::format("{:.3f},{:.10g},{:.10g}\n", k * 1e-3, command(k * 1e-3), 0.97 * command(k * 1e-3 - 0.012));
  const std::string path = dir.write("table.csv", record);
  const auto axis = [&](const char* column) {
    return json{{"x", {{"record", path}, {"format", "csv"}, {"column", column}, {"units", "m/s^2"}}}};
  };
  json truth = rocking_scenario(0.3);
  truth["bodies"][0]["position"] = {0.0, 0.0, 0.0};
  truth["bodies"][0]["orientation"] = {1.0, 0.0, 0.0, 0.0};
  truth["table_motion"] = axis("table");
  Recording recording = synthetic_recording(truth, dir / "truth", {1e-3, 5e-4, 14});
  recording.path = "lagging_table";
  json scenario = model(0.3);
  scenario["table_motion"] = axis("command");
  diagnosis::Options o = fast_options(dir);
  o.max_effects = 1;
  const diagnosis::Diagnosis d = diagnosis::diagnose(scenario, {recording}, o);
  std::cerr << d.verdict;
  ASSERT_EQ(d.table.size(), 1u);
  EXPECT_EQ(d.table[0].channel, "table_ax");
  EXPECT_NEAR(d.table[0].delay, 0.012, 4 * d.table[0].delay_sd);
  EXPECT_NEAR(d.table[0].gain, 0.97, 4 * d.table[0].gain_sd);
  EXPECT_NE(d.verdict.find("did not follow its command"), std::string::npos);
  EXPECT_TRUE(d.effects.empty());
}

// One-sine table acceleration pulses, amplitude * sin(2 pi f (t - start)) for start <= t <=
// start + 1/f, else rest, written at 1 kHz: each carries the table amplitude / (2 pi f^2) and
// stops it there.
struct Pulse {
  double start, amplitude, frequency;  // s, m/s^2, Hz
};

json pulses_table(const test::TempDir& dir, const std::string& name, const std::vector<Pulse>& pulses, double duration) {
  std::string record = "t,ax\n";
  for (int k = 0; k <= static_cast<int>(std::round(duration * 1e3)); ++k) {
    const double t = k * 1e-3;
    double a = 0;
    for (const Pulse& p : pulses)
      if (t >= p.start && t <= p.start + 1 / p.frequency) a += p.amplitude * std::sin(2 * M_PI * p.frequency * (t - p.start));
    record += fmt::format("{:.3f},{:.10g}\n", t, a);
  }
  const std::string path = dir.write(name + ".csv", record);
  return {{"x", {{"record", path}, {"format", "csv"}, {"column", "ax"}, {"units", "m/s^2"}}}};
}

json pulse_table(const test::TempDir& dir, double amplitude, double frequency, double duration) {
  return pulses_table(dir, fmt::format("pulse_{:+g}", amplitude), {{0.0, amplitude, frequency}}, duration);
}

// `document` with its table turned in step with its x motion by the diagnosis candidate `entry`
// itself ("table_pitch", "table_roll"), so the truth uses exactly the option diagnose fits.
json driven_table(json document, const std::string& entry, double c) {
  Recording channels;  // the candidates need only a recorded table_ax and a rocking body
  channels.channels = {{"table_ax", {}}, {"block.rock_x", {}}};
  bool applied = false;
  for (const diagnosis::Candidate& k : diagnosis::candidates_for(document, channels, 0, nullptr))
    if (k.entry == entry) k.apply(document, c), applied = true;
  EXPECT_TRUE(applied) << "no candidate " << entry;  // else the truth would silently lack the effect
  return document;
}

// The block standing upright on a table moved by `table` for `duration` s.
json standing_on(const json& table, double duration) {
  json truth = rocking_scenario(0.3);
  truth["bodies"][0]["position"] = {0.0, 0.0, 0.0};
  truth["bodies"][0]["orientation"] = {1.0, 0.0, 0.0, 0.0};
  truth["simulation"]["duration"] = duration;
  truth["table_motion"] = table;
  return truth;
}

// The block standing on a table moved by a 2.5 Hz one-sine pulse of `amplitude`, the table turned
// with its travel by `entry` (coefficient c), 3 s (at rest from about 2.1 s). Only table_ax (the
// model replays it) and the rock channels are kept, as in rocking_recording.
Recording pulse_recording(const test::TempDir& dir, double amplitude, const std::string& entry, double c,
                          unsigned seed) {
  const json truth = driven_table(standing_on(pulse_table(dir, amplitude, 2.5, 3.0), 3.0), entry, c);
  Recording r = synthetic_recording(truth, dir / fmt::format("truth_{}", seed), {1e-3, 5e-4, seed});
  std::vector<RecordingChannel> kept;
  for (const RecordingChannel& k : r.channels)
    if (k.name == "table_ax" || k.name == "block.rock_x" || k.name == "block.rock_y") kept.push_back(k);
  r.channels = kept;
  r.path = fmt::format("pulse_{:+g}", amplitude);
  return r;
}

// `freestand run` of the improved scenario, its table record written beside it, replays the first
// recording: same duration, and the block rocks as recorded. (It kept the model's own table motion
// before, none here, and the block stood still.) Tolerance 10 % of the recorded peak rock_x: the
// fitted parameter's allowed error moves it by at most 4 % (the pitch test below: 0.015 rad/m at
// 0.38 rad of peak per rad/m, on a 0.147 rad peak), the sensor noise by 1 mrad.
void expect_improved_scenario_replays(const test::TempDir& dir, const diagnosis::Diagnosis& d, const Recording& first) {
  ASSERT_FALSE(d.improved_table.empty());
  std::filesystem::create_directories(dir / "improved");
  dir.write("improved/" + diagnosis::Options().improved_table_file, d.improved_table);
  const Recording replayed = run_scenario_document(d.improved, dir / "improved");
  EXPECT_NEAR(replayed.time.back() - replayed.time.front(), first.time.back() - first.time.front(), 1e-9);
  const auto peak = [](const std::vector<double>& v) {
    double p = 0;
    for (double x : v) p = std::isfinite(x) ? std::max(p, std::abs(x)) : p;
    return p;
  };
  const double recorded = peak(first.body_channel("block", "rock_x"));
  std::cout << fmt::format("measured: improved scenario's peak rock_x {:.4f} rad, recorded {:.4f}\n",
                           peak(replayed.body_channel("block", "rock_x")), recorded);
  EXPECT_NEAR(peak(replayed.body_channel("block", "rock_x")), recorded, 0.1 * recorded);
}

// The table pitches with its travel, pitch = c x (c = 0.05 rad/m: 5 mrad per 0.1 m), made by the
// simulator (the table_pitch option itself); the recordings state no pitch. A 2.5 Hz one-sine
// pulse of 3.6 m/s^2 (1.1 g b/h: the block rocks to 0.13 rad, far from overturning at 0.32)
// carries the table 92 mm, which tilts it by 4.6 mrad. The pitch matters in two ways: near
// its peak the block is close to its overturning angle, where the tilt's g theta is a sizeable
// share of the restoring moment (peak rock_x 0.128 -> 0.147 rad, 19 noise s.d.); and once at rest
// the block leans with the table (residual rock_x 4.6 mrad, in world axes), which no table gain or
// body candidate can produce. That lean comes last, so a single recording holds it out (its later
// half): the pulse is run twice, +x then -x (the lean follows the travel, either way), and the
// second run is held out. Tolerance 0.015 rad/m: the last refinement's spacing is at most 0.01 (the
// profile's best point bracketed by its neighbours, at most 0.032 and 0.1, each side in thirds twice); the
// rest is the trade-off with the table gain: the profile runs on one ensemble member, which
// replays the table with its own gain (s.d. 2 %), and 2 % of gain moves the peak as much as
// 0.026 rad/m of pitch (+10 mrad); weighed against the lean, which fixes c whatever the gain,
// that is about 0.005 rad/m per gain s.d., allowed at 1.5 s.d.
TEST(Diagnosis, NamesAndRecoversTablePitch) {
  test::TempDir dir;
  const double c = 0.05;
  const std::vector<Recording> recordings = {pulse_recording(dir, 3.6, "table_pitch", c, 21),
                                             pulse_recording(dir, -3.6, "table_pitch", c, 22)};
  for (const Recording& r : recordings)
    EXPECT_EQ(r.nominal.dump().find("pitch"), std::string::npos);  // concealed: no table rotation recorded
  diagnosis::Options o = fast_options(dir);
  o.max_effects = 1;  // the first effect is the test; a second round would double the runs
  const diagnosis::Diagnosis d = diagnosis::diagnose(model(0.3), recordings, o);
  std::cerr << d.verdict;
  ASSERT_FALSE(d.effects.empty());
  EXPECT_EQ(d.effects.front().fit.candidate.entry, "table_pitch");
  EXPECT_EQ(d.effects.front().verdict, "missing physics");
  EXPECT_NEAR(d.effects.front().fit.value, c, 0.015);
  expect_standard_error_covers(d.effects.front().fit, c);
  EXPECT_GT(d.effects.front().fit.held_out_delta, 0);  // the -x run leans the other way, as predicted
  expect_improved_scenario_replays(dir, d, recordings.front());
  // c lies past the quick ladder's last rung (0.032 rad/m: 16 % of the range from 0), where the
  // profile is still falling: it goes on to the next rung, 2x out (the refinement's points lie
  // in thirds between 0.032 and the range's end 0.1, none at 0.064).
  const auto pitch = std::find_if(d.rounds.front().begin(), d.rounds.front().end(),
                                  [](const auto& f) { return f.candidate.entry == "table_pitch"; });
  ASSERT_NE(pitch, d.rounds.front().end());
  EXPECT_TRUE(std::any_of(pitch->profile.begin(), pitch->profile.end(),
                          [](const auto& point) { return std::abs(point.first - 0.064) < 1e-9; }));
}

// The table also moves vertically, a_z = k a_x (k = 0.2), which the recordings do not state. A
// slow one-sine pulse (1 m/s^2 at 0.5 Hz, far below the block's uplift at 3.3 m/s^2) carries the
// table 0.64 m along x, and so 0.13 m up, while the block stands on it; a 2.5 Hz pulse of
// 3.6 m/s^2 then rocks it (with 0.72 m/s^2 of vertical shaking). Measured against the model,
// the standing block's uplift rises with the table at k 0.32 m/s (its mean speed along x): a
// sensor drift would look the same at rest. It is physics here: the vertical candidate explains
// it, and the diagnosis must name it, not correct the recording for a drift first and then find
// the right candidate failing the held-out run (docs/diagnose-studies.md, study 3, case14). Two runs, +x
// then -x (the table rises, then sinks), the second held out. Tolerance 0.05 (a quarter of k):
// the last refinement's spacing is 0.03 (a bracket of 0.27 of the +-0.5 range, each side in
// thirds twice); the rest is the trade-off with the table gain, which scales the rocking pulse as k's
// vertical shaking does. A drift left against the improved model is the carry of its error in
// k: at most 0.05 x 0.32 m/s.
TEST(Diagnosis, TakesAVerticalTableCarryForPhysicsNotForADrift) {
  test::TempDir dir;
  const double k = 0.2;
  std::vector<Recording> recordings;
  for (double sign : {1.0, -1.0}) {
    const json table = pulses_table(dir, fmt::format("carry_{:+g}", sign), {{0.0, sign, 0.5}, {2.2, 3.6 * sign, 2.5}}, 4.0);
    const json truth = driven_table(standing_on(table, 4.0), "vertical_table_motion", k);
    Recording r = synthetic_recording(truth, dir / fmt::format("truth_{:+g}", sign), {1e-3, 5e-4, sign > 0 ? 31u : 32u});
    std::vector<RecordingChannel> kept;
    for (const RecordingChannel& c : r.channels)
      if (c.name == "table_ax" || c.name == "block.rock_x" || c.name == "block.rock_y" || c.name == "block.uplift")
        kept.push_back(c);
    r.channels = kept;
    r.path = fmt::format("carry_{:+g}", sign);
    EXPECT_EQ(r.nominal.dump().find("\"z\""), std::string::npos);  // concealed: no vertical table motion stated
    recordings.push_back(r);
  }
  diagnosis::Options o = fast_options(dir);
  o.max_effects = 1;
  const diagnosis::Diagnosis d = diagnosis::diagnose(model(0.3), recordings, o);
  std::cerr << d.verdict;
  ASSERT_FALSE(d.effects.empty());
  EXPECT_EQ(d.effects.front().fit.candidate.entry, "vertical_table_motion");
  EXPECT_NEAR(d.effects.front().fit.value, k, 0.05);
  expect_standard_error_covers(d.effects.front().fit, k);
  EXPECT_GT(d.effects.front().fit.held_out_delta, 0);
  for (const diagnosis::MeasurementIssue& m : d.measurement)  // the carry is explained, not corrected away
    if (m.drift_significant) EXPECT_LT(std::abs(m.drift), 0.05 * 0.32) << m.text;
}

// A block stands on a table that travels 25 mm out, back and out again in three 2.5 Hz
// one-sine pulses of 1 m/s^2 (far below its uplift at 3.3 m/s^2; the travel is not in step with
// time, so a drift and a carry can be told apart). Its uplift channel is given a carry of k per
// m of that travel (a vertical table component in step with x) and a sensor drift of 1 mm/s,
// and its rock_x channel k rad per m (a table that pitches) and 1 mrad/s.
// Each feature must read k, not the drift: within 3 of its s.d. (the floor, from the noise over
// the travel at rest), for k = 0.0125 (the proof study's concealed vertical table) and 0, and
// the uplift's s.d. must be fine enough to tell 0.0125 from 0 (below a third of it). The tilt
// must read k and not the block's own lean (a block on a compliant contact leans under the
// pulses' acceleration; read on the travel alone that lean was 0.0264 rad/m with no pitch), within
// 3 of its s.d. (from the 1 mrad angle noise, and the acceleration fitted beside the travel:
// 0.0067, measured; too coarse to tell 0.0125 from 0 at this noise, but the lean read on the
// travel alone, 0.0264 with no pitch, is outside it). At 0.1 mrad of noise the leaning block
// is no longer at rest, so the noise is not lowered to sharpen it.
TEST(DiagnosisFeatures, ReadsARestingBodysCarryByTheTableApartFromADrift) {
  test::TempDir dir;
  const json truth =
      standing_on(pulses_table(dir, "carry", {{0.2, 1.0, 2.5}, {1.5, -1.0, 2.5}, {2.8, 1.0, 2.5}}, 4.0), 4.0);
  const Recording clean = synthetic_recording(truth, dir / "truth", {1e-3, 5e-4, 51});
  for (double k : {0.0125, 0.0}) {
    Recording r = clean;
    const std::vector<double> travel = *r.table_channel('d', 'x');
    // The same for the tilt: a table pitching by k rad per m of travel (the proof study's case13
    // pitches 0.02), with a gyro drift of 1 mrad/s.
    for (RecordingChannel& c : r.channels)
      if (c.name == "block.uplift" || c.name == "block.rock_x")
        for (std::size_t i = 0; i < c.values.size(); ++i) c.values[i] += k * travel[i] + 1e-3 * r.time[i];
    const diagnosis::Features f = diagnosis::event_features(r, r.nominal);
    const auto tilt = f.find("block.rock_x.table_carry");
    ASSERT_NE(tilt, f.end());
    std::cout << fmt::format("measured: tilt {:.5f} +- {:.5f} for {}\n", tilt->second.value, tilt->second.floor, k);
    EXPECT_NEAR(tilt->second.value, k, 3 * tilt->second.floor);
    const auto carry = f.find("block.uplift.table_carry");
    ASSERT_NE(carry, f.end());
    std::cout << fmt::format("measured: carry {:.5f} +- {:.5f} for {}\n", carry->second.value, carry->second.floor, k);
    EXPECT_NEAR(carry->second.value, k, 3 * carry->second.floor);
    EXPECT_LT(carry->second.floor, 0.0125 / 3);
    // A ratio of two channels is known no better than their gains: at a gain s.d. of 50 % the
    // floor is half the carry where that exceeds the noise's s.d.
    const diagnosis::Features g = diagnosis::event_features(r, r.nominal, nullptr, {0.5, 0});
    const auto loose = g.find("block.uplift.table_carry");
    ASSERT_NE(loose, g.end());
    EXPECT_DOUBLE_EQ(loose->second.floor, std::max(carry->second.floor, 0.5 * std::abs(carry->second.value)));
  }
}

// The pivot's lever on each side (pivot_levers.h) of a block rocking freely on the simulator,
// against its geometry: a centre of mass 12 mm off the axis toward +x leaves 88 mm to the +x
// edge and 112 mm to the -x edge of the 0.1 m half-width. The half-difference of the two sides
// is the offset alone (a contact that sinks the pivot under load shortens both alike); each side
// is allowed 3 s.d. of its floor plus 2 mm of sinking.
TEST(DiagnosisFeatures, ReadsACentreOfMassOffFromTheLeverOnEachSide) {
  test::TempDir dir;
  json truth = rocking_scenario(0.3);
  truth["bodies"][0]["com"] = {0.012, 0.0, 0.3};
  const Recording r = synthetic_recording(truth, dir / "truth", {1e-3, 5e-4, 21});
  const diagnosis::Features f = diagnosis::event_features(r, r.nominal);
  ASSERT_TRUE(f.count("block.rock_x.lever_pos") && f.count("block.rock_x.lever_neg"));
  const diagnosis::FeatureValue& pos = f.at("block.rock_x.lever_pos");
  const diagnosis::FeatureValue& neg = f.at("block.rock_x.lever_neg");
  std::cout << fmt::format("measured: lever + {:.5f} +- {:.5f}, - {:.5f} +- {:.5f} (0.088, 0.112)\n", pos.value,
                           pos.floor, neg.value, neg.floor);
  EXPECT_NEAR(pos.value, 0.088, 3 * pos.floor + 2e-3);
  EXPECT_NEAR(neg.value, 0.112, 3 * neg.floor + 2e-3);
  EXPECT_NEAR((neg.value - pos.value) / 2, 0.012, 3 * std::hypot(pos.floor, neg.floor) / 2);
  EXPECT_LT(pos.time, neg.time);  // released leaning to +x
  EXPECT_FALSE(pos.splits);  // read from the whole record: its date does not move the held-out split

  // Split at the third impact, as the held-out rule splits a record: each part reads its own
  // levers, the later ones dated after the split (held out), both sides near the truth.
  const double split = f.at("block.rock_x.impact3.time").value;
  const diagnosis::Features g = diagnosis::event_features(r, r.nominal, nullptr, {}, split);
  for (const char* side : {"pos", "neg"}) {
    const std::string name = fmt::format("block.rock_x.lever_{}", side);
    ASSERT_TRUE(g.count(name) && g.count(name + ".later")) << name;
    const diagnosis::FeatureValue& early = g.at(name);
    const diagnosis::FeatureValue& later = g.at(name + ".later");
    std::cout << fmt::format("measured: {} up to {:.3f} s {:.5f} +- {:.5f}, after it {:.5f} +- {:.5f}\n", side, split,
                             early.value, early.floor, later.value, later.floor);
    const double truth = side == std::string("pos") ? 0.088 : 0.112;
    EXPECT_NEAR(early.value, truth, 3 * early.floor + 2e-3);
    EXPECT_NEAR(later.value, truth, 3 * later.floor + 2e-3);
    EXPECT_LE(early.time, split);
    EXPECT_GT(later.time, split);
  }
}

// The pivot's sink (pivot_levers.h) of a block rocked by a table pulse on a soft Winkler bed,
// simulated, against the continuum's s = -sqrt(2 W / (k D)): the 0.2 m block of 60 kg standing
// on k = 2e7 N/m^3, rocked to 0.13 rad by a 2.5 Hz pulse of 3.6 m/s^2 (its contact 0.08 to
// 0.04 m wide at 0.05 to 0.15 rad: 3 to 6 rows of a 16-per-edge grid), gives -0.0172 m/sqrt(rad).
// The simulated edge depth itself follows the formula within 4 % at 0.01-0.1 rad (a block
// released tilted, study 38); the fitted s is less exact, since over one record's tilts the
// root and the lever it is fitted beside trade off: measured 20 % low here (8 per edge: 16 %),
// 20 % low with the lever 5 % low on the released block once its release transient (a 10 mm
// vertical bounce) has passed. Tolerance 25 %. On a bed 100 times stiffer the sink must read
// under a quarter of the soft one's: the contact is then narrower than a row.
TEST(DiagnosisFeatures, ReadsAContactsComplianceFromThePivotsSink) {
  test::TempDir dir;
  const double weight = 60 * 9.81, depth = 0.2, area = 0.04, soft = 2e7;
  const json table = pulse_table(dir, 3.6, 2.5, 3.0);
  const auto sink = [&](double k, unsigned seed) {
    json truth = standing_on(table, 3.0);
    truth["bodies"][0]["nodes"] = {{"layout", "surface"}, {"per_edge", 16}};
    truth["interfaces"][0]["contact_stiffness"] = k * area;
    const Recording r = synthetic_recording(truth, dir / fmt::format("truth_{}", seed), {1e-3, 5e-4, seed});
    const diagnosis::Features f = diagnosis::event_features(r, r.nominal);
    EXPECT_TRUE(f.count("block.pivot_sink"));
    return f.count("block.pivot_sink") ? f.at("block.pivot_sink") : diagnosis::FeatureValue{};
  };
  const double theory = -std::sqrt(2 * weight / (soft * depth));
  const diagnosis::FeatureValue on_soft = sink(soft, 31), on_stiff = sink(100 * soft, 32);
  std::cout << fmt::format("measured: pivot sink {:.5f} +- {:.5f} on k = {:g} (Winkler {:.5f}), {:.5f} +- {:.5f} on {:g}\n",
                           on_soft.value, on_soft.floor, soft, theory, on_stiff.value, on_stiff.floor, 100 * soft);
  EXPECT_NEAR(on_soft.value, theory, 0.25 * std::abs(theory));
  EXPECT_LT(std::abs(on_stiff.value), 0.25 * std::abs(theory));
}

// A small block standing on the block rides the block's carry by the table: the carry is a
// feature once, of the body on the table, not again of the body on top (on the tower benchmark
// the top body's own moved the held-out split; study 28).
TEST(DiagnosisFeatures, CountsTheCarryByTheTableOnceOnTheBodyOnTheTable) {
  test::TempDir dir;
  json truth = standing_on(pulses_table(dir, "carry", {{0.2, 1.0, 2.5}, {1.5, -1.0, 2.5}}, 3.0), 3.0);
  truth["bodies"].push_back({{"name", "top"}, {"shape", "box"}, {"half_extents", {0.05, 0.05, 0.1}}, {"mass", 5.0},
                             {"supported_by", "block"}, {"nodes", {{"layout", "vertices"}}}});
  truth["interfaces"].push_back({{"lower", "block"}, {"upper", "top"}, {"mu", kMu}, {"restitution", 0.3}});
  const Recording r = synthetic_recording(truth, dir / "truth", {1e-3, 5e-4, 52});
  const diagnosis::Features f = diagnosis::event_features(r, r.nominal);
  EXPECT_TRUE(f.count("top.uplift.peak_max"));  // the top body is analysed ...
  EXPECT_FALSE(f.count("top.uplift.table_carry"));  // ... but its carry is the block's
  EXPECT_TRUE(f.count("block.uplift.table_carry"));
}

// Slips are the same event when they overlap, one to one, nearest onsets first: an extra
// short slip, or one split in two by a pause, renumbers none of the others.
TEST(DiagnosisFeatures, MatchesSlipsByTimeNotByOrder) {
  auto slip = [](double onset, double stop) {
    analysis::SlipEvent e;
    e.onset = onset, e.stop = stop;
    return e;
  };
  const std::vector<analysis::SlipEvent> reference = {slip(1.0, 1.3), slip(2.0, 2.4), slip(3.0, 3.2)};
  // An extra slip between the first two, the rest 20 ms late.
  EXPECT_EQ(diagnosis::matched_slips({slip(1.02, 1.32), slip(1.5, 1.55), slip(2.02, 2.42), slip(3.02, 3.22)}, reference),
            (std::vector<int>{0, -1, 1, 2}));
  // The second slip split by a pause: its first part is the event (the nearer onset), the
  // second matches nothing; the third is missing.
  EXPECT_EQ(diagnosis::matched_slips({slip(1.0, 1.3), slip(2.01, 2.1), slip(2.15, 2.4)}, reference),
            (std::vector<int>{0, 1, -1}));
  // One slip spanning two: the nearer onset, the other reference slip left unmatched.
  EXPECT_EQ(diagnosis::matched_slips({slip(1.9, 3.1)}, reference), (std::vector<int>{1}));
  EXPECT_EQ(diagnosis::matched_slips({slip(3.5, 3.6)}, reference), (std::vector<int>{-1}));
  EXPECT_EQ(diagnosis::matched_slips(reference, reference), (std::vector<int>{0, 1, 2}));
}

// A squat-enough block (b/h = 1/3) on friction 0.2 slides and cannot rock: sliding caps the
// table's pull at mu g = 1.96 m/s^2, below the 3.3 m/s^2 that lifts an edge. Three one-sine
// pulses of 3 m/s^2 at 2 Hz make six slips, and the block's sensors run 30 ms behind the
// table's. A slider has no impacts to date: its slip onsets are what the delay moves (the table
// acceleration that starts each slip is the recorded one replayed), and the diagnosis must
// report the delay and name no physics. Tolerance 10 ms: two steps of the delay grid (5 ms).
const double kSliderMu = 0.2, kSliderDelay = 0.03;

// That block's recording, its slide channels kSliderDelay late and, with `knock` > 0, carrying
// a push of `knock` metres and back before the shaking (0.06-0.12 s), which the model does not
// have. Only table_ax and the slide channels are kept.
Recording late_slider(const test::TempDir& dir, double knock) {
  json truth = standing_on(pulses_table(dir, "slides", {{0.2, 3.0, 2.0}, {1.2, -3.0, 2.0}, {2.2, 3.0, 2.0}}, 3.5), 3.5);
  truth["interfaces"][0]["mu"] = kSliderMu;
  Recording r = synthetic_recording(truth, dir / "truth", {1e-3, 5e-4, 41});
  const double knock_start = 0.06, knock_length = 0.06;
  std::vector<RecordingChannel> kept;
  for (RecordingChannel& c : r.channels) {
    if (c.name != "table_ax" && c.name != "block.slide_x" && c.name != "block.slide_y") continue;
    if (c.name == "block.slide_x")
      for (std::size_t k = 0; k < c.values.size(); ++k) {
        const double u = (r.time[k] - knock_start) / knock_length;
        if (u > 0 && u < 1) c.values[k] += knock * std::pow(std::sin(M_PI * u), 2);
      }
    const std::vector<double> y = c.values;
    if (c.name != "table_ax")
      for (std::size_t k = 0; k < y.size(); ++k) c.values[k] = signal::interpolate(r.time, y, r.time[k] - kSliderDelay);
    kept.push_back(c);
  }
  r.channels = kept;
  r.path = "late_slider";
  return r;
}

// A slider's recording diagnosed against the model with its stated friction, one round.
diagnosis::Diagnosis diagnose_slider(const test::TempDir& dir, const Recording& recording) {
  diagnosis::Options o = fast_options(dir);
  o.max_effects = 1;
  json scenario = model(0.3);
  scenario["contact"]["mu"] = kSliderMu;
  const diagnosis::Diagnosis d = diagnosis::diagnose(scenario, {recording}, o);
  std::cerr << d.verdict;
  return d;
}

// The slider's clock delay, measured from its slip onsets, and no physics named.
void expect_slider_clock(const test::TempDir& dir, const Recording& recording) {
  const diagnosis::Diagnosis d = diagnose_slider(dir, recording);
  EXPECT_TRUE(d.effects.empty());
  ASSERT_FALSE(d.measurement.empty());
  // The body's clock or slide_x's alone: slide_y stays at zero, so the two fit alike (and the
  // verdict says so).
  EXPECT_EQ(d.measurement.front().channel.rfind("block", 0), 0u) << d.measurement.front().channel;
  EXPECT_TRUE(d.measurement.front().delay_significant);
  EXPECT_NEAR(d.measurement.front().delay, kSliderDelay, 0.01);
  std::cout << fmt::format("measured: delay of {} = {:.4f} s for {}\n", d.measurement.front().channel,
                           d.measurement.front().delay, kSliderDelay);
}

TEST(Diagnosis, MeasuresASlidersClockOffsetFromItsSlipOnsets) {
  test::TempDir dir;
  expect_slider_clock(dir, late_slider(dir, 0));
}

// The same clock when the recording has a slip the model lacks, first of all (a knock of 3 mm
// and back): the slips numbered in order would compare every later onset with another event's
// (case22 of the proof study, docs/diagnose-studies.md study 21); matched by time they meet their own.
TEST(Diagnosis, MeasuresASlidersClockOffsetPastASlipTheModelLacks) {
  test::TempDir dir;
  const Recording r = late_slider(dir, 0.003);
  const diagnosis::Features f = diagnosis::event_features(r, r.nominal);
  ASSERT_TRUE(f.count("block.slip1.time"));  // the knock is a slip of the recording's, before the pulses
  EXPECT_LT(f.at("block.slip1.time").value, 0.2);
  expect_slider_clock(dir, r);
}

// Friction that weakens with the sliding speed, mu(v) = mu_k + (mu_s - mu_k) exp(-decay |v|), on
// the sliding block of the clock tests (six slips): mu_k = 0.6 mu_s and a decay of 2.5 s/m,
// between two of the decays the settle tries (1.25 and 5 s/m). The recording's nominal states a
// constant friction (synthetic_recording drops the law), the model mu_s. Slips alone hardly
// tell the decay from mu_k (a faster weakening to a higher mu_k slips alike: measured, chi2
// 17.3, 17.7 and 18.3 at the three decays' best on 8 members), so what is checked is what the
// verdict claims: the law is named, and the truth lies within the values of the decays said to
// fit alike (the one taken among them), within a quarter of the change 1 - 0.6 (the proof
// study's recovery target) outside their span.
TEST(Diagnosis, NamesAndRecoversVelocityWeakening) {
  test::TempDir dir;
  const double ratio = 0.6, decay = 2.5;
  json truth = standing_on(pulses_table(dir, "weakens", {{0.2, 3.0, 2.0}, {1.2, -3.0, 2.0}, {2.2, 3.0, 2.0}}, 3.5), 3.5);
  truth["interfaces"][0] = {{"lower", "table"}, {"upper", "block"}, {"mu_s", kSliderMu}, {"mu_k", ratio * kSliderMu},
                            {"friction_decay", decay}, {"restitution", 0.3}};
  Recording r = synthetic_recording(truth, dir / "truth", {1e-3, 5e-4, 43});
  std::vector<RecordingChannel> kept;
  for (RecordingChannel& c : r.channels)
    if (c.name == "table_ax" || c.name == "block.slide_x" || c.name == "block.slide_y") kept.push_back(c);
  r.channels = kept;
  r.path = "weakening_slider";
  const diagnosis::Diagnosis d = diagnose_slider(dir, r);
  ASSERT_FALSE(d.effects.empty());
  const diagnosis::FittedCandidate& fit = d.effects.front().fit;
  EXPECT_EQ(fit.candidate.entry, "velocity_weakening");
  double low = fit.value, high = fit.value;
  for (const auto& [shape, value] : fit.alike_shapes) low = std::min(low, value), high = std::max(high, value);
  EXPECT_GT(ratio, low - 0.25 * (1 - ratio));
  EXPECT_LT(ratio, high + 0.25 * (1 - ratio));
  std::cout << fmt::format("measured: {} = {:.4g}{}, {:.3g} to {:.3g} over the decays that fit alike, for {} at {} s/m\n",
                           fit.candidate.name, fit.value, diagnosis::format_shape(fit.candidate), low, high, ratio, decay);
  EXPECT_GT(fit.held_out_delta, 0);
}

// A cube dropped flat from 13 cm bounces and settles: half its event features lie at the
// release (t = 0), where the held-out split then falls, and a fit window up to it would hold
// one sample, which no run's analysis takes (it ended the process from a worker's thread). The
// profiles must run whole instead, and the model, the truth's own, be found to fit.
TEST(Diagnosis, ACubeDroppedFlatIsDiagnosedWithoutAFitWindow) {
  test::TempDir dir;
  json truth = rocking_scenario(0.5);
  json& cube = truth["bodies"][0];
  cube["half_extents"] = {0.1, 0.1, 0.1};
  cube["mass"] = 20.0;
  cube["position"] = {0.0, 0.0, 0.13};
  cube.erase("orientation");
  truth["simulation"]["duration"] = 1.0;
  truth["simulation"]["output_rate"] = 500;
  Recording recording = synthetic_recording(truth, dir / "truth", {0.0, 0.0, 21});
  recording.nominal["sensor_noise"] = {{"angle", 1e-3}, {"length", 5e-4}};
  diagnosis::Options o = fast_options(dir);
  o.max_effects = 0;
  const diagnosis::Diagnosis d = diagnosis::diagnose(model(0.5), {recording}, o);
  std::cerr << d.verdict;
  for (const std::string& note : d.notes) EXPECT_EQ(note.find("fit window"), std::string::npos) << note;
  EXPECT_NE(d.verdict.find("No missing physics found"), std::string::npos);
}

// A cube tossed tilted onto the table (launched: a stated velocity and spin, so its touchdowns
// and bounces are features) lands on an edge, so its bounces are decided by the contact law's
// integration, not by a milliradian of tilt as a flat drop's are (study 29). Recorded at the
// truth's step (0.03 of the critical 3.48e-3 s) and modelled at 0.9 of it, where the contact
// lasts two or three steps and its restitution is off (the second bounce's peak 146 mm against
// 155 at the fine step; `freestand run`, study 30): the time-step check must see the model's step
// as not converged and adopt a finer one before it looks for physics. Limit: chi2's mean (10 for
// the toss's 10 features).
TEST(Diagnosis, RefinesATimeStepTheBouncesHaveNotConvergedOn) {
  test::TempDir dir;
  json truth = rocking_scenario(0.5);
  json& cube = truth["bodies"][0];
  const double tilt = 0.35;
  cube["half_extents"] = {0.1, 0.1, 0.1};
  cube["mass"] = 20.0;
  cube["position"] = {0.0, 0.0, 0.25};
  cube["orientation"] = {std::cos(tilt / 2), 0.8 * std::sin(tilt / 2), 0.6 * std::sin(tilt / 2), 0.0};
  cube["velocity"] = {0.2, 0.0, -0.5};
  cube["omega"] = {1.0, -0.5, 0.3};
  truth["simulation"]["duration"] = 1.2;
  truth["simulation"]["output_rate"] = 500;
  Recording recording = synthetic_recording(truth, dir / "truth", {1e-3, 5e-4, 23});
  recording.nominal["sensor_noise"] = {{"angle", 1e-3}, {"length", 5e-4}};
  recording.path = "synthetic_toss";
  diagnosis::Options o = fast_options(dir);
  o.max_effects = 0;
  json coarse = model(0.5);
  coarse["simulation"]["time_step"] = 0.9 * 3.48e-3;
  const diagnosis::Diagnosis d = diagnosis::diagnose(coarse, {recording}, o);
  std::cerr << d.verdict;
  const auto step = std::find_if(d.numerics_checks.begin(), d.numerics_checks.end(),
                                 [](const diagnosis::NumericsCheck& c) { return c.quantity == "time step"; });
  ASSERT_NE(step, d.numerics_checks.end());
  std::cout << fmt::format("measured: time step check {:.1f} against {:.1f}, adopted {}\n", step->distance, step->limit,
                           step->setting);
  EXPECT_TRUE(step->adopted);
  EXPECT_LT(d.improved["simulation"]["time_step"].get<double>(), coarse["simulation"]["time_step"].get<double>());
  // Measured with seeds 23, 5 and 7: 23-25 against a limit of 10 at 0.9 of the critical step,
  // 20-21 at 0.11 of it (4e-4 s: still refined), 4.1-4.4 at the truth's own step (kept).
  EXPECT_NE(d.verdict.find("time step was not converged"), std::string::npos);
}

TEST(Diagnosis, BadInputIsRefusedWithoutAVerdict) {
  test::TempDir dir;
  Recording r;
  r.path = "short.csv";
  r.nominal = {{"bodies", {{{"name", "block"}, {"shape", "box"}, {"half_extents", {0.1, 0.1, 0.3}}}}}};
  for (int k = 0; k < 20; ++k) r.time.push_back(0.005 * k);
  r.channels = {{"block.rock_x", std::vector<double>(20, 0.0)}};
  try {
    diagnosis::diagnose(model(0.3), {r}, fast_options(dir));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("too short"), std::string::npos);
  }
  for (int k = 20; k < 400; ++k) r.time.push_back(0.005 * k);
  r.channels = {{"block.rock_x", std::vector<double>(400, 0.0)}};
  json other = model(0.3);
  other["bodies"] = {{{"name", "statue"}, {"shape", "box"}, {"half_extents", {0.1, 0.1, 0.3}}}};
  try {
    diagnosis::diagnose(other, {r}, fast_options(dir));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("statue"), std::string::npos);
  }
  r.channels = {{"block.x", std::vector<double>(400, 0.0)}};
  EXPECT_THROW(diagnosis::diagnose(model(0.3), {r}, fast_options(dir)), InputError);
  r.channels = {{"block.rock_x", std::vector<double>(400, 0.0)}};
  // A hypothesis must name a candidate of this scenario and lie in its range, before any run.
  for (const diagnosis::StatedValue& h : {diagnosis::StatedValue{"edge_inset[statue]", 0.01},
                                          diagnosis::StatedValue{"edge_inset[block]", 0.5}}) {
    diagnosis::Options o = fast_options(dir);
    o.hypotheses = {{{"restitution[table/block]", 0.3}, h}};
    try {
      diagnosis::diagnose(model(0.3), {r}, o);
      FAIL();
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--hypothesis " + h.candidate), std::string::npos) << e.what();
    }
  }
  diagnosis::Options more_than_the_ensemble = fast_options(dir);
  more_than_the_ensemble.profile_members = more_than_the_ensemble.ensemble + 1;
  try {
    diagnosis::diagnose(model(0.3), {r}, more_than_the_ensemble);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--profile-members"), std::string::npos);
  }
}

}  // namespace
}  // namespace freestand
