// freestand calibrate on recordings the simulator made with known contact
// parameters plus noise: the fit must find the parameters again. Also the
// pose metrics of the cube-toss comparison on an exactly known offset.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "calibration.h"
#include "freestand/input_error.h"
#include "synthetic_recording.h"
#include "temp_dir.h"

namespace freestand {
namespace {

using nlohmann::json;

// Known parameters of the synthetic recordings.
const double kStiffness = 2e7;   // N/m^3 per area: the block sinks 0.75 mm at rest, enough for rocking to feel it
const double kRestitution = 0.3;
const double kMuS = 0.35, kMuK = 0.25;

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
          {"simulation", {{"duration", 2.0}, {"time_step", 1e-4}, {"output_rate", 200}}}};
}

// A squat 0.5 x 0.5 x 0.3 m, 100 kg block (it slides, never rocks) on a table
// sweeping 1 -> 3 Hz at 6 m/s^2: stick, slip both ways, at varying velocity.
json sliding_scenario() {
  json s = rocking_scenario();
  s["bodies"] = {{{"name", "slider"}, {"shape", "box"}, {"half_extents", {0.25, 0.25, 0.15}}, {"mass", 100.0},
                  {"nodes", {{"layout", "vertices"}}}}};
  s["interfaces"][0]["upper"] = "slider";
  s["table_motion"] = {{"x", {{"motion", "sweep"}, {"amplitude", "6 m/s^2"}, {"frequency", 1.0},
                              {"frequency_end", 3.0}, {"duration", 2.0}}}};
  return s;
}

// The model the calibration starts from: same numerics, nothing known.
json model() { return {{"simulation", {{"time_step", 1e-4}}}}; }

TEST(Calibration, RecoversKnownParametersFromNoisyRockingAndSliding) {
  test::TempDir dir;
  // Noise: 1 mrad on the angles (0.6 % of the 0.16 rad release), 0.5 mm on
  // the slides (about 1 % of the peak slide).
  const MeasurementNoise noise{1e-3, 5e-4, 7};
  std::vector<Recording> recordings = {synthetic_recording(rocking_scenario(), dir / "rocking", noise),
                                       synthetic_recording(sliding_scenario(), dir / "sliding", noise)};
  recordings[0].path = "rocking", recordings[1].path = "sliding";
  ASSERT_EQ(classify_recording(recordings[0]), RecordingKind::kRocking);
  ASSERT_EQ(classify_recording(recordings[1]), RecordingKind::kHistory);
  CalibrationOptions options;
  options.parameters = {parse_calibration_parameter("stiffness:3e6:3e8:1e8"),
                        parse_calibration_parameter("restitution:0.05:0.8:0.5"),
                        parse_calibration_parameter("mu_s:0.1:0.6:0.45"),
                        parse_calibration_parameter("mu_k:0.1:0.6:0.4")};
  options.max_evaluations = 45;
  if (std::getenv("DIAG")) {
    options.parameters = {parse_calibration_parameter("stiffness:3e6:3e8:2e7"),
                        parse_calibration_parameter("restitution:0.05:0.8:0.3"),
                        parse_calibration_parameter("mu_s:0.1:0.6:0.35"),
                        parse_calibration_parameter("mu_k:0.1:0.6:0.25")};
    options.max_evaluations = 1;
  }
  options.work_directory = dir / "runs";
  const CalibrationResult fit = calibrate(model(), recordings, options);
  const double truth[] = {kStiffness, kRestitution, kMuS, kMuK};
  for (std::size_t i = 0; i < 4; ++i) {
    const ParameterEstimate& e = fit.estimates[i];
    std::printf("%-12s true %.4g fitted %.4g se %.3g [%.4g, %.4g]\n", e.parameter.name.c_str(), truth[i], e.value,
                e.standard_error, e.lower95, e.upper95);
  }
  std::printf("objective %.4g -> %.4g, %d residuals, %d evaluations\n", fit.objective_start, fit.objective,
              fit.residual_count, fit.evaluations);
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
