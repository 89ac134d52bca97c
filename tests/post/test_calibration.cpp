// freestand calibrate on recordings the simulator made with known contact
// parameters plus noise: the fit must find the parameters again. Also the
// pose metrics of the cube-toss comparison on an exactly known offset.

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "calibration.h"
#include "scenario.h"
#include "freestand/input_error.h"
#include "synthetic_recording.h"
#include "temp_dir.h"

namespace freestand {
namespace {

using nlohmann::json;

// Known parameters of the synthetic recordings.
const double kStiffness = 2e7;   // N/m^3 per area: the block sinks 0.75 mm at rest, enough for rocking to feel it
const double kRestitution = 0.3;
const double kMuS = 0.35, kMuK = 0.25;  // in the recordings; the test fits restitution only

// A 0.2 x 0.2 x 0.6 m, 60 kg block on its corners, released at rest tilted by
// half its slenderness (alpha = atan(1/3)) about the y axis, pivot on the +x edge.
json rocking_scenario() {
  const double b = 0.1, tilt = 0.5 * std::atan(1.0 / 3.0);
  return {{"bodies", {{{"name", "block"}, {"shape", "box"}, {"half_extents", {b, b, 0.3}}, {"mass", 60.0},
                       {"position", {b - b * std::cos(tilt), 0.0, b * std::sin(tilt)}},
                       {"orientation", {std::cos(tilt / 2), 0.0, std::sin(tilt / 2), 0.0}},
                       {"nodes", {{"layout", "vertices"}}}}}},
          {"interfaces", {{{"lower", "table"}, {"upper", "block"}, {"mu_s", kMuS}, {"mu_k", kMuK},
                           {"restitution", kRestitution}}}},
          {"contact", {{"stiffness", kStiffness}}},
          {"simulation", {{"duration", 1.5}, {"time_step", 2e-4}, {"output_rate", 200}}}};
}

// A squat 0.5 x 0.5 x 0.3 m, 100 kg block (it slides, never rocks) on a table
// sweeping 1 -> 3 Hz at 6 m/s^2: stick, slip both ways, at varying velocity.
json sliding_scenario() {
  json s = rocking_scenario();
  s["bodies"] = {{{"name", "slider"}, {"shape", "box"}, {"half_extents", {0.25, 0.25, 0.15}}, {"mass", 100.0},
                  {"nodes", {{"layout", "vertices"}}}}};
  s["interfaces"][0]["upper"] = "slider";
  s["table_motion"] = {{"x", {{"motion", "sweep"}, {"amplitude", "6 m/s^2"}, {"frequency", 1.0},
                              {"frequency_end", 3.0}, {"duration", 1.5}}}};
  return s;
}

// The rocking block dropped flat from 5 cm: the bounce (restitution) and the
// contact phase and sink at rest (stiffness) show in its uplift.
json drop_scenario() {
  json s = rocking_scenario();
  s["bodies"][0]["position"] = {0.0, 0.0, 0.05};
  s["bodies"][0].erase("orientation");
  s["simulation"]["duration"] = 0.4;
  return s;
}

// The model the calibration starts from: same numerics and stiffness.
json model() { return {{"simulation", {{"time_step", 2e-4}}}, {"contact", {{"stiffness", kStiffness}}}}; }

// Restitution from noisy free rocking, stiffness and friction known.
// Tolerance 0.02 on e = 0.3: the per-impact amplitudes carry 0.6 % noise
// (1 mrad of 0.16 rad).
TEST(Calibration, RecoversRestitutionFromNoisyFreeRocking) {
  test::TempDir dir;
  const MeasurementNoise noise{1e-3, 5e-4, 7};  // 1 mrad on the angles, 0.5 mm on lengths
  std::vector<Recording> recordings = {synthetic_recording(rocking_scenario(), dir / "rocking", noise)};
  recordings[0].path = "rocking";
  ASSERT_EQ(classify_recording(recordings[0]), RecordingKind::kRocking);
  ASSERT_EQ(classify_recording(synthetic_recording(sliding_scenario(), dir / "sliding", noise)),
            RecordingKind::kHistory);
  CalibrationOptions options;
  options.parameters = {parse_calibration_parameter("restitution:0.05:0.8:0.5")};
  options.max_evaluations = 25;
  options.work_directory = dir / "runs";
  const CalibrationResult fit = calibrate(model(), recordings, options);
  EXPECT_NEAR(fit.estimates[0].value, kRestitution, 0.02);
  // The interval is believable: it holds the truth (measured with
  // Levenberg-Marquardt 0.2992, 95 % interval [0.2978, 0.3007]; with BOBYQA
  // 0.3003, [0.2988, 0.3018]; before the amplitudes were read from a
  // parabola's vertex, 0.3089 with a standard error of 0.0005).
  EXPECT_LE(fit.estimates[0].lower95, kRestitution);
  EXPECT_GE(fit.estimates[0].upper95, kRestitution);
  EXPECT_TRUE(std::isfinite(fit.estimates[0].standard_error));
  EXPECT_LT(fit.objective, 0.01 * fit.objective_start);  // the mismatch at the start was real
  EXPECT_NEAR(fit.model["interfaces"][0]["restitution"].get<double>(), fit.estimates[0].value, 1e-12);
}

const MeasurementNoise kNoise{1e-3, 5e-4, 7};  // 1 mrad on the angles, 0.5 mm on lengths

// A point stiffer than the model keeps the model's share of its critical step. The model runs at
// half its critical step; started at five times its stiffness, whose critical step is 1/sqrt(5)
// of the model's (the modes' exact scaling), the first evaluation was refused ("the simulation
// with the starting values failed"). Now it runs at half its own critical step, and the fit
// reaches the truth from there (the drop's sink at rest pins the stiffness: 1.97e7 for 2e7 in
// ten evaluations; the misfit left is the model's default restitution). The calibrated
// scenario carries the step its runs had.
TEST(Calibration, AStifferPointKeepsTheModelsShareOfItsCriticalStep) {
  test::TempDir dir;
  std::vector<Recording> recordings = {synthetic_recording(drop_scenario(), dir / "drop", kNoise)};
  recordings[0].path = "drop";
  json coarse = model();
  const double critical = critical_time_step({"model", recording_scenario(coarse, recordings[0], "t.csv"), {}});
  coarse["simulation"]["time_step"] = 0.5 * critical;
  CalibrationOptions options;
  options.parameters = {parse_calibration_parameter("stiffness:2e6:2e8:1e8")};
  options.max_evaluations = 10;
  options.work_directory = dir / "runs";
  const CalibrationResult fit = calibrate(coarse, recordings, options);
  std::cout << fmt::format("measured: stiffness {:.3g} from 1e8 (truth {:.3g}), objective {:.3g} -> {:.3g}\n",
                           fit.estimates[0].value, kStiffness, fit.objective_start, fit.objective);
  EXPECT_LT(fit.objective, fit.objective_start);
  EXPECT_EQ(fit.failed_runs, 0);
  EXPECT_LT(std::abs(std::log(fit.estimates[0].value / kStiffness)), std::log(1.5));  // expect_recovered's bound
  const json scenario = calibrated_scenario(coarse, fit.estimates, recordings[0], "table_motion.csv");
  const double k = fit.estimates[0].value, kept = 0.5 * critical * std::sqrt(std::min(1.0, kStiffness / k));
  EXPECT_NEAR(scenario["simulation"]["time_step"].get<double>(), kept, 1e-9 * kept);
}

// A run lost to its process once (the launcher killed on its first call, by a stand-in for
// `stdbuf` first on PATH) is run again and gives exactly the recording of a run never lost; a
// model that cannot run fails both times and passes on why.
TEST(Calibration, ARunLostOnceIsRunAgainAndAModelThatCannotRunSaysWhy) {
  test::TempDir dir;
  const Recording recorded = synthetic_recording(drop_scenario(), dir / "drop", kNoise);
  const json good = recording_scenario(model(), recorded, "table_motion.csv");
  json bad = good;
  bad["contact"]["stiffness"] = -1.0;
  const Recording reference = simulate_recording(good, recorded, dir / "reference");
  const std::filesystem::path bin = dir / "bin";
  std::filesystem::create_directories(bin);
  const std::string lost = dir / "lost";
  dir.write("bin/stdbuf", "#!/bin/sh\nif [ ! -e '" + lost + "' ]; then : > '" + lost + "'; kill -9 $$; fi\n"
                          "exec /usr/bin/stdbuf \"$@\"\n");
  std::filesystem::permissions(bin / "stdbuf", std::filesystem::perms::owner_all);
  const std::string path = std::getenv("PATH");
  setenv("PATH", (bin.string() + ":" + path).c_str(), 1);
  std::vector<Recording> out(2);
  std::vector<std::string> errors(2);
  simulate_each({good, bad}, {&recorded, &recorded}, dir / "runs", 1,
                [&](std::size_t i, Recording&& simulated, std::exception_ptr failure) {
                  out[i] = std::move(simulated);
                  try {
                    if (failure) std::rethrow_exception(failure);
                  } catch (const std::exception& e) {
                    errors[i] = e.what();
                  }
                });
  setenv("PATH", path.c_str(), 1);
  EXPECT_TRUE(std::filesystem::exists(lost)) << "the stand-in was never called";
  EXPECT_EQ(errors[0], "");
  ASSERT_EQ(out[0].channels.size(), reference.channels.size());
  for (std::size_t k = 0; k < reference.channels.size(); ++k)
    EXPECT_EQ(out[0].channels[k].values, reference.channels[k].values) << reference.channels[k].name;
  EXPECT_NE(errors[1].find("stiffness"), std::string::npos) << errors[1];
}

// What the per-run callback throws (an analysis refusing a run's record) must reach the caller
// as an error, not end the process from the worker's thread (std::terminate), and stop the runs
// not yet started: two workers, four runs, the first handed over throws.
TEST(Calibration, AnErrorInThePerRunWorkReachesTheCallerAndStopsTheRuns) {
  test::TempDir dir;
  const Recording recorded = synthetic_recording(drop_scenario(), dir / "drop", kNoise);
  const json good = recording_scenario(model(), recorded, "table_motion.csv");
  std::atomic<int> handed{0};
  const auto each = [&] {
    simulate_each({good, good, good, good}, {&recorded, &recorded, &recorded, &recorded}, dir / "runs", 2,
                  [&](std::size_t, Recording&&, std::exception_ptr) {
                    if (handed++ == 0) throw InputError("motion analysis: refused");
                  });
  };
  EXPECT_THROW(each(), InputError);
  EXPECT_LE(handed.load(), 2);  // the run under way on the other worker at most, none started after
}

// Replayed at the true parameters, the recorded table acceleration reproduces
// the sliding record (made with the analytic sweep) to within its noise: the
// residuals, divided by the stated noise, are unit normal, so their sum of
// squares is chi-square with n degrees of freedom (mean n, sd sqrt(2 n)).
// Measured without noise: slide_x of the replay within 0.06 mm of the record.
TEST(Calibration, SlidingReplayAtTheTrueParametersReproducesTheRecord) {
  test::TempDir dir;
  const Recording recorded = synthetic_recording(sliding_scenario(), dir / "sliding", kNoise);
  ASSERT_EQ(classify_recording(recorded), RecordingKind::kHistory);
  json run = recording_scenario(model(), recorded, "table_motion.csv");
  apply_parameters(run, {parse_calibration_parameter("restitution"), parse_calibration_parameter("mu_s"),
                         parse_calibration_parameter("mu_k")}, {kRestitution, kMuS, kMuK});
  const std::vector<double> r =
      calibration_residuals(RecordingKind::kHistory, recorded, simulate_recording(run, recorded, dir / "replay"));
  double chi2 = 0.0;
  for (double x : r) chi2 += x * x;
  const double n = static_cast<double>(r.size());
  EXPECT_GE(n, 301.0);  // every sample of slide_x compared
  EXPECT_NEAR(chi2, n, 4.0 * std::sqrt(2.0 * n));
}

// The three synthetic recordings of the joint fit (free rocking, a face-on
// drop, sliding on a sweep), noise kNoise with `seed`.
std::vector<Recording> contact_and_friction_recordings(const test::TempDir& dir, unsigned seed) {
  MeasurementNoise noise = kNoise;
  noise.seed = seed;
  std::vector<Recording> recordings = {synthetic_recording(rocking_scenario(), dir / "rocking", noise),
                                       synthetic_recording(drop_scenario(), dir / "drop", noise),
                                       synthetic_recording(sliding_scenario(), dir / "sliding", noise)};
  const char* names[] = {"rocking", "drop", "sliding"};
  for (int i = 0; i < 3; ++i) recordings[i].path = names[i];
  return recordings;
}

const char* const kContactParameters[] = {"stiffness:2e6:2e8:5e7", "restitution:0.05:0.8:0.45"};
const char* const kFrictionParameters[] = {"mu_s:0.1:0.8:0.5", "mu_k:0.1:0.8:0.4"};

CalibrationResult fit(const json& start, const std::vector<Recording>& recordings,
                      const std::vector<std::string>& parameters, const std::string& algorithm, int max_evaluations,
                      const std::string& directory) {
  CalibrationOptions options;
  for (const std::string& p : parameters) options.parameters.push_back(parse_calibration_parameter(p));
  options.algorithm = algorithm;
  options.max_evaluations = max_evaluations;
  options.work_directory = directory;
  return calibrate(start, recordings, options);
}

// Stiffness, restitution, mu_s and mu_k from all three recordings at once,
// started away from the truth (x2.5 on stiffness, +50 % on the others).
CalibrationResult fit_contact_and_friction(const test::TempDir& dir, const std::vector<Recording>& recordings,
                                           const std::string& algorithm, int max_evaluations) {
  return fit(model(), recordings,
             {kContactParameters[0], kContactParameters[1], kFrictionParameters[0], kFrictionParameters[1]},
             algorithm, max_evaluations, dir / ("joint_" + algorithm));
}

// The seed paper's procedure: stiffness and restitution from the rocking
// record and the drop, then mu_s and mu_k from the sliding record with them.
std::vector<CalibrationResult> fit_in_stages(const test::TempDir& dir, const std::vector<Recording>& recordings,
                                             const std::string& algorithm, int max_evaluations) {
  const CalibrationResult contact = fit(model(), {recordings[0], recordings[1]},
                                        {kContactParameters[0], kContactParameters[1]}, algorithm, max_evaluations,
                                        dir / ("contact_" + algorithm));
  const CalibrationResult friction = fit(contact.model, {recordings[2]}, {kFrictionParameters[0], kFrictionParameters[1]},
                                         algorithm, max_evaluations, dir / ("friction_" + algorithm));
  return {contact, friction};
}

const double kTruth[] = {kStiffness, kRestitution, kMuS, kMuK};
// Evaluations per stage: Levenberg-Marquardt costs 2 x 2 (the Jacobian) + 1
// or more per iteration; 40 give 7 or more iterations.
const int kStageEvaluations = 40;

// How far an estimate is from the truth in its standard errors (of log for stiffness).
double error_in_standard_errors(const ParameterEstimate& e, double truth) {
  return (e.parameter.log_scale ? std::log(e.value / truth) : e.value - truth) / e.standard_error;
}
// Each estimate against the truth: within 4 of its standard errors (a
// larger miss is a bias, not noise: probability 6e-5 for a correct standard
// error), and within a useful relative bound, the precision a calibration
// must reach to be worth its cost: a factor 1.5 on stiffness (the sink at
// rest to 50 %), +-0.05 on restitution, +-0.03 on the friction coefficients
// (about 10 %). Returns whether the 95 % interval holds the truth.
bool expect_recovered(const ParameterEstimate& e, double truth) {
  SCOPED_TRACE(e.parameter.name);
  EXPECT_TRUE(std::isfinite(e.standard_error));
  EXPECT_LT(std::abs(error_in_standard_errors(e, truth)), 4.0);
  const double useful = e.parameter.log_scale ? std::log(1.5) : e.parameter.name == "restitution" ? 0.05 : 0.03;
  EXPECT_LT(std::abs(e.parameter.log_scale ? std::log(e.value / truth) : e.value - truth), useful);
  return e.lower95 <= truth && truth <= e.upper95;
}

// The seed paper's procedure with Levenberg-Marquardt, from a start away
// from the truth (x2.5 on stiffness, +50 % on the others): stiffness and
// restitution from the rocking record and the drop (rocking alone does not
// separate them: they trade off along a valley of its objective, fitted
// 1.4e8 and 0.15 against 2e7 and 0.3; the drop's contact phase and sink at
// rest pin stiffness, its bounce restitution), then mu_s and mu_k from the
// sliding record. Measured (seed 7, 2 cores): 30-40 s, 38 + 41 evaluations;
// stiffness 1.944e7 (-0.7 standard errors), restitution 0.3028 (+1.6),
// mu_s 0.337 (-1.1), mu_k 0.2512 (+2.4: its 95 % interval misses the truth;
// coverage over seeds: DISABLED_RecoveryOverSeeds, docs/calibration.md).
TEST(Calibration, RecoversStiffnessRestitutionAndFriction) {
  test::TempDir dir;
  const std::vector<Recording> recordings = contact_and_friction_recordings(dir, kNoise.seed);
  ASSERT_EQ(classify_recording(recordings[0]), RecordingKind::kRocking);
  ASSERT_EQ(classify_recording(recordings[1]), RecordingKind::kHistory);
  const std::vector<CalibrationResult> fits = fit_in_stages(dir, recordings, "lm", kStageEvaluations);
  int i = 0;
  for (const CalibrationResult& f : fits) {
    EXPECT_LT(f.objective, 0.01 * f.objective_start);  // the mismatch at the start was real
    for (const ParameterEstimate& e : f.estimates) expect_recovered(e, kTruth[i++]);
  }
}

// The coverage of the 95 % intervals over noise seeds 1..N (N from
// FREESTAND_CALIBRATION_SEEDS, default 5; about 40 s each), staged as above
// or, with FREESTAND_CALIBRATION_JOINT=1, all four parameters fitted to the
// three recordings at once (budget 2 x kStageEvaluations); the optimiser from
// FREESTAND_CALIBRATION_ALGORITHM (default lm). Prints one line per
// seed: each parameter's error in standard errors.
//   build/post_tests --gtest_also_run_disabled_tests --gtest_filter='Calibration.DISABLED_RecoveryOverSeeds'
TEST(Calibration, DISABLED_RecoveryOverSeeds) {
  const char* count = std::getenv("FREESTAND_CALIBRATION_SEEDS");
  const bool joint = std::getenv("FREESTAND_CALIBRATION_JOINT") != nullptr;
  const std::string algorithm = std::getenv("FREESTAND_CALIBRATION_ALGORITHM") ? std::getenv("FREESTAND_CALIBRATION_ALGORITHM") : "lm";
  int covered[4] = {0, 0, 0, 0}, seeds = count ? std::atoi(count) : 5;
  for (int seed = 1; seed <= seeds; ++seed) {
    test::TempDir dir;
    const std::vector<Recording> recordings = contact_and_friction_recordings(dir, seed);
    const auto start = std::chrono::steady_clock::now();
    const std::vector<CalibrationResult> fits =
        joint ? std::vector<CalibrationResult>{fit_contact_and_friction(dir, recordings, algorithm, 2 * kStageEvaluations)}
              : fit_in_stages(dir, recordings, algorithm, kStageEvaluations);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("seed %2d %5.1f s, objective / residuals", seed, seconds);
    for (const CalibrationResult& f : fits) std::printf(" %.0f / %d", f.objective, f.residual_count);
    int i = 0;
    for (const CalibrationResult& f : fits)
      for (const ParameterEstimate& e : f.estimates) {
        std::printf(" | %s %.4g (%+.1f se)", e.parameter.name.c_str(), e.value, error_in_standard_errors(e, kTruth[i]));
        covered[i] += expect_recovered(e, kTruth[i]);
        ++i;
      }
    std::printf("\n");
  }
  std::printf("95 %% intervals holding the truth (of %d): stiffness %d, restitution %d, mu_s %d, mu_k %d\n", seeds,
              covered[0], covered[1], covered[2], covered[3]);
}

// The pose metrics on a trajectory displaced by a known amount: a recording
// against itself shifted by 0.01 m in x and turned by 0.2 rad about z.
TEST(Calibration, TrajectoryErrorsOfAKnownOffset) {
  Recording rec;
  rec.nominal = {{"bodies", {{{"name", "cube"}, {"shape", "box"}, {"half_extents", {0.05, 0.05, 0.05}}}}}};
  rec.time = {0.0, 0.1, 0.2, 0.3};
  const std::vector<double> x = {0.0, 0.1, 0.15, 0.15};
  rec.channels = {{"cube.x", x}, {"cube.y", {0, 0, 0, 0}}, {"cube.z", {0.05, 0.05, 0.05, 0.05}},
                  {"cube.qw", {1, 1, 1, 1}}, {"cube.qx", {0, 0, 0, 0}}, {"cube.qy", {0, 0, 0, 0}},
                  {"cube.qz", {0, 0, 0, 0}}};
  Recording sim = rec;
  for (double& v : sim.channels[0].values) v += 0.01;
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()));
  sim.channels[3].values.assign(4, turn.w());
  sim.channels[6].values.assign(4, turn.z());
  EXPECT_DOUBLE_EQ(body_size(rec, "cube"), 0.1);
  const TrajectoryErrors e = trajectory_errors(rec, sim, "cube", 0.1);
  EXPECT_NEAR(e.mean_position, 0.1, 1e-12);
  EXPECT_NEAR(e.final_position, 0.1, 1e-12);
  EXPECT_NEAR(e.final_rotation, 0.2, 1e-12);
  EXPECT_TRUE(e.same_rest_face);  // a turn about the vertical keeps the face down
  EXPECT_DOUBLE_EQ(e.rest_time_recorded, 0.2);  // x stops changing at 0.2 s
  const std::vector<double> r = calibration_residuals(RecordingKind::kTrajectory, rec, sim);
  ASSERT_EQ(r.size(), 4u * 6u);
  EXPECT_NEAR(r[0], 0.1, 1e-12);  // x offset / size
  EXPECT_NEAR(r[5], 0.5 * -0.2, 1e-12);  // rotation vector of R_sim^T R_rec, times size/2 over size
}

TEST(Calibration, ParameterErrorsNameTheParameter) {
  EXPECT_THROW(parse_calibration_parameter("stifness"), InputError);
  EXPECT_THROW(parse_calibration_parameter("mu:0.5:0.2"), InputError);
  EXPECT_THROW(parse_calibration_parameter("stiffness:0:1e9"), InputError);
  try {
    parse_calibration_parameter("restitution:0.1");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("restitution:0.1"), std::string::npos);
  }
}

TEST(Calibration, KineticFrictionIsCappedAtStatic) {
  json doc = {{"interfaces", {{{"lower", "table"}, {"upper", "b"}, {"mu", 0.4}}}}};
  apply_parameters(doc, {parse_calibration_parameter("mu_k")}, {0.6});
  EXPECT_DOUBLE_EQ(doc["interfaces"][0]["mu_s"].get<double>(), 0.4);  // kept from mu
  EXPECT_DOUBLE_EQ(doc["interfaces"][0]["mu_k"].get<double>(), 0.4);  // capped
  EXPECT_FALSE(doc["interfaces"][0].contains("mu"));
}

}  // namespace
}  // namespace freestand
