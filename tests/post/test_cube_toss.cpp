// The real cube tosses as recordings: channels agree with the tracked pose,
// the base face is the one the cube rests on, the initial state in the
// nominal reproduces the first tracked sample and parses as a scene, and
// the README's angular-velocity frame is checked against the quaternions.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include "calibration.h"
#include "cube_toss.h"
#include "freestand/input_error.h"
#include "freestand/scene.h"
#include "temp_dir.h"

namespace freestand {
namespace {

const std::string kTosses =
    std::string(FREESTAND_SHARED_DATA) + "/experiments/cube_toss/cube_tosses_0-299.csv.gz";

class CubeToss : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { tosses_ = new auto(read_cube_tosses(kTosses)); }
  static void TearDownTestSuite() { delete tosses_; }
  static const std::vector<CubeTossSample>& toss(int id) { return tosses_->at(id); }
  static const std::map<int, std::vector<CubeTossSample>>& all() { return *tosses_; }

 private:
  static std::map<int, std::vector<CubeTossSample>>* tosses_;
};
std::map<int, std::vector<CubeTossSample>>* CubeToss::tosses_ = nullptr;

Eigen::Quaterniond pose_orientation(const Recording& r, std::size_t k) {
  return {r.find("cube.qw")->values[k], r.find("cube.qx")->values[k], r.find("cube.qy")->values[k],
          r.find("cube.qz")->values[k]};
}

TEST_F(CubeToss, ReadsAllTosses) {
  EXPECT_EQ(all().size(), 300u);
  EXPECT_EQ(all().begin()->first, 0);
  EXPECT_EQ(all().rbegin()->first, 299);
  EXPECT_EQ(toss(0).size(), 121u);  // toss_summary_0-299.csv: n_samples
}

TEST_F(CubeToss, TimeIsSampleIndexOver148Hz) {
  const Recording r = cube_toss_recording(0, toss(0));
  ASSERT_EQ(r.time.size(), toss(0).size());
  for (std::size_t k = 0; k < r.time.size(); ++k) EXPECT_DOUBLE_EQ(r.time[k], k / 148.0);
}

TEST_F(CubeToss, BodyFrameIsTrackedFrameTurnedByACubeSymmetry) {
  const Recording r = cube_toss_recording(0, toss(0));
  for (std::size_t k = 0; k < toss(0).size(); ++k) {
    // R_tracked^T R_new must be a signed permutation (a rotation of the cube onto itself).
    const Eigen::Matrix3d s = toss(0)[k].orientation.toRotationMatrix().transpose() *
                              pose_orientation(r, k).toRotationMatrix();
    EXPECT_NEAR(s.cwiseAbs().maxCoeff(), 1.0, 1e-9);
    EXPECT_NEAR(s.cwiseAbs().sum(), 3.0, 1e-9);
    // The centre is unchanged by relabelling; uplift is its height change.
    EXPECT_EQ(r.find("cube.z")->values[k], toss(0)[k].centre.z());
    EXPECT_NEAR(r.body_channel("cube", "uplift")[k], toss(0)[k].centre.z() - toss(0)[0].centre.z(), 1e-15);
  }
}

TEST_F(CubeToss, ChannelsFollowTheQuaternion) {
  const Recording r = cube_toss_recording(0, toss(0));
  const double half = 0.1048 / 2;
  for (std::size_t k = 0; k < r.time.size(); ++k) {
    const Eigen::Matrix3d R = pose_orientation(r, k).toRotationMatrix();
    EXPECT_NEAR(r.body_channel("cube", "rock_x")[k], std::atan2(R(0, 2), R(2, 2)), 1e-12);
    EXPECT_NEAR(r.body_channel("cube", "rock_y")[k], std::atan2(R(1, 2), R(2, 2)), 1e-12);
    // slide: the base-face centre (centre - R (0, 0, edge/2)) moved horizontally.
    const Eigen::Vector3d base = toss(0)[k].centre - R.col(2) * half;
    const Eigen::Vector3d base0 = toss(0)[0].centre - pose_orientation(r, 0).toRotationMatrix().col(2) * half;
    EXPECT_NEAR(r.body_channel("cube", "slide_x")[k], base.x() - base0.x(), 1e-12);
    EXPECT_NEAR(r.body_channel("cube", "slide_y")[k], base.y() - base0.y(), 1e-12);
  }
  EXPECT_EQ(r.body_channel("cube", "twist")[0], 0.0);
}

TEST_F(CubeToss, EveryTossEndsRestingOnItsBase) {
  // A cube resting on a face has its base axis vertical: a tilt of 0.05 rad
  // would lift an edge by 5 mm, which a resting cube cannot hold. The last
  // sample is at rest (toss_summary: final speed < ~1 cm/s).
  double worst_rock = 0;
  std::vector<double> table_heights;  // final centre height minus half an edge
  for (const auto& [id, samples] : all()) {
    const Recording r = cube_toss_recording(id, samples);
    worst_rock = std::max({worst_rock, std::fabs(r.body_channel("cube", "rock_x").back()),
                           std::fabs(r.body_channel("cube", "rock_y").back())});
    table_heights.push_back(samples.back().centre.z() - 0.1048 / 2);
  }
  EXPECT_LT(worst_rock, 0.05);
  // The nominal's table height (README: "about 1 mm below z = 0", so to the
  // nearest mm) agrees with the median resting height to 0.5 mm.
  std::nth_element(table_heights.begin(), table_heights.begin() + 150, table_heights.end());
  const double median = table_heights[150];
  EXPECT_NEAR(median, cube_toss_recording(0, toss(0)).nominal["table_height"].get<double>(), 0.0005);
  RecordProperty("worst_final_rock_rad", std::to_string(worst_rock));
  RecordProperty("median_table_height_m", std::to_string(median));
}

TEST_F(CubeToss, InitialStateRoundTripsThroughTheScene) {
  const Recording r = cube_toss_recording(0, toss(0));
  const Scene scene = parse_scene(r.nominal, "toss 0");
  ASSERT_EQ(scene.bodies.size(), 1u);
  const BodySpec& cube = scene.bodies[0];
  const CubeTossSample& first = toss(0)[0];
  // Base-face centre + R (0, 0, edge/2) is the tracked centre.
  const CubeFlightState flight = cube_flight_state(toss(0));
  ASSERT_GT(flight.samples, 2);
  // Base-face centre + R (0, 0, edge/2) is the fitted centre, within tracking noise of the first sample.
  EXPECT_LT((cube.position + cube.orientation * Eigen::Vector3d(0, 0, 0.0524) - flight.centre).norm(), 1e-12);
  EXPECT_LT((flight.centre - first.centre).norm(), 1e-3);
  EXPECT_LT((cube.com - Eigen::Vector3d(0, 0, 0.0524)).norm(), 1e-15);
  // The same rotation as the fitted one, in the relabelled body frame (a cube symmetry away).
  const Eigen::Matrix3d s = flight.orientation.toRotationMatrix().transpose() * cube.orientation.toRotationMatrix();
  EXPECT_NEAR(s.cwiseAbs().sum(), 3.0, 1e-9);
  EXPECT_LT(cube.orientation.angularDistance(pose_orientation(r, 0)), 0.01);
  EXPECT_LT((cube.velocity - flight.velocity).norm(), 1e-15);
  EXPECT_LT((cube.omega - flight.omega).norm(), 1e-15);
  EXPECT_NEAR(cube.mass, 0.37, 1e-15);
  EXPECT_NEAR(cube.inertia(1, 1), 0.00081, 1e-15);
  ASSERT_NE(find_interface(scene, "table", "cube"), nullptr);
  EXPECT_EQ(find_interface(scene, "table", "cube")->contact.mu_s, 0.15);
}

TEST_F(CubeToss, AngularVelocityIsInBodyAxes) {
  // In free flight (the first samples, before the first impact) the world
  // angular velocity is log(R1 R0^T) / h. The README's body-axes omega,
  // turned to world axes, must match it; read as world axes it must not.
  // The authors' velocities are smoothed estimates: 10 % of |omega|.
  const CubeTossSample& s0 = toss(0)[0];
  const CubeTossSample& s1 = toss(0)[1];
  const Eigen::AngleAxisd step(s1.orientation * s0.orientation.conjugate());
  const Eigen::Vector3d finite_difference = step.axis() * step.angle() * 148.0;
  const Eigen::Vector3d world = s0.orientation * s0.omega_body;
  EXPECT_LT((world - finite_difference).norm(), 0.1 * world.norm());
  EXPECT_GT((s0.omega_body - finite_difference).norm(), 0.3 * world.norm());
}

TEST_F(CubeToss, ConvertsToReadableRecordings) {
  test::TempDir dir;
  const std::vector<std::string> stems = convert_cube_tosses(kTosses, dir / "out", 3, 4);
  ASSERT_EQ(stems.size(), 2u);
  EXPECT_EQ(std::filesystem::path(stems[0]).filename(), "cube_toss_003");
  const Recording r = read_recording(stems[1]);
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  EXPECT_EQ(r.time.size(), toss(4).size());
  EXPECT_EQ(r.body_names(), std::vector<std::string>{"cube"});
  EXPECT_NO_THROW(read_scene_file(stems[1] + ".nominal.json"));
  try {
    convert_cube_tosses(kTosses, dir / "out", 299, 300);
    FAIL() << "toss 300 is not in the file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no toss 300"), std::string::npos) << e.what();
  }
}

// Ballistic samples of a cube (edge 0.1048 m) thrown from x0 with v0, turning
// at a constant world omega from q0, at 148 Hz while every corner is more than
// `clearance` above the table at z = -0.001; then `resting` samples lying
// still elsewhere on the table (contact: must not enter the fit).
std::vector<CubeTossSample> thrown_cube(const Eigen::Vector3d& x0, const Eigen::Vector3d& v0,
                                        const Eigen::Quaterniond& q0, const Eigen::Vector3d& omega,
                                        double clearance, int resting) {
  std::vector<CubeTossSample> out;
  const double g = 9.81, half = 0.1048 / 2;
  for (int k = 0;; ++k) {
    const double t = k / 148.0;
    CubeTossSample s;
    s.k = k;
    s.centre = x0 + v0 * t - Eigen::Vector3d(0, 0, g * t * t / 2);
    s.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(omega.norm() * t, omega.normalized())) * q0;
    if (s.centre.z() - half * s.orientation.toRotationMatrix().row(2).cwiseAbs().sum() <= -0.001 + clearance) break;
    s.velocity = v0 - Eigen::Vector3d(0, 0, g * t);
    s.omega_body = s.orientation.conjugate() * omega;
    out.push_back(s);
  }
  for (int i = 0; i < resting; ++i) {
    CubeTossSample s;
    s.k = static_cast<int>(out.size());
    s.centre = {0.4, -0.3, -0.001 + half};
    s.orientation = Eigen::Quaterniond::Identity();
    s.velocity = s.omega_body = Eigen::Vector3d::Zero();
    out.push_back(s);
  }
  return out;
}

const Eigen::Vector3d kX0(0.1, 0.25, 0.15), kV0(1.1, -0.4, -0.2), kOmega(3.0, -4.0, 1.0);
const Eigen::Quaterniond kQ0 = Eigen::Quaterniond(0.3, -0.8, 0.4, 0.2).normalized();

TEST(CubeTossFlight, RecoversAnExactBallisticToss) {
  const std::vector<CubeTossSample> samples = thrown_cube(kX0, kV0, kQ0, kOmega, 0.002, 30);
  const int flying = static_cast<int>(samples.size()) - 30;
  ASSERT_GE(flying, 10);
  const CubeFlightState f = cube_flight_state(samples);
  EXPECT_EQ(f.samples, flying);  // the resting samples (in contact) are not fitted
  // Exact data: only rounding (the rotation fit iterates to an offset of 1e-12 rad).
  EXPECT_LT((f.centre - kX0).norm(), 1e-12);
  EXPECT_LT((f.velocity - kV0).norm(), 1e-10);
  EXPECT_LT(f.orientation.angularDistance(kQ0), 1e-10);
  EXPECT_LT((f.omega - kOmega).norm(), 1e-9);
}

TEST(CubeTossFlight, NoisyTossWithinTheLeastSquaresError) {
  std::vector<CubeTossSample> samples = thrown_cube(kX0, kV0, kQ0, kOmega, 0.002, 0);
  const double sigma_x = 1e-4, sigma_r = 1e-3;  // m, rad per component: the tracking noise (docs/validation.md)
  std::mt19937 random(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (CubeTossSample& s : samples) {
    s.centre += sigma_x * Eigen::Vector3d(normal(random), normal(random), normal(random));
    const Eigen::Vector3d r = sigma_r * Eigen::Vector3d(normal(random), normal(random), normal(random));
    s.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(r.norm(), r.normalized())) * s.orientation;
  }
  // A least-squares line through n samples h apart from t = 0: slope error
  // sigma / (h sqrt(n (n^2 - 1) / 12)), intercept error sigma sqrt((4n - 2) / (n (n + 1))).
  // Per component; 4.5 of those on the norm of three (chi-square 20.25 with 3 dof: P = 2e-4).
  const CubeFlightState f = cube_flight_state(samples);
  const double n = f.samples, spread = std::sqrt(n * (n * n - 1) / 12) / 148.0;
  const double intercept = std::sqrt((4 * n - 2) / (n * (n + 1)));
  ASSERT_EQ(f.samples, static_cast<int>(samples.size()));
  EXPECT_LT((f.velocity - kV0).norm(), 4.5 * sigma_x / spread);
  EXPECT_LT((f.centre - kX0).norm(), 4.5 * sigma_x * intercept);
  EXPECT_LT((f.omega - kOmega).norm(), 4.5 * sigma_r / spread);
  EXPECT_LT(f.orientation.angularDistance(kQ0), 4.5 * sigma_r * intercept);
  // For comparison, a backward difference of two samples (the data set's
  // estimate) errs by sqrt(2) sigma / h per component: 21 mm/s and 0.21 rad/s.
  RecordProperty("velocity_error_m_s", std::to_string((f.velocity - kV0).norm()));
  RecordProperty("omega_error_rad_s", std::to_string((f.omega - kOmega).norm()));
}

TEST(CubeTossFlight, TossStartingOnTheTableKeepsTheFirstSample) {
  const std::vector<CubeTossSample> samples = thrown_cube(kX0, kV0, kQ0, kOmega, 0.002, 3);
  const std::vector<CubeTossSample> resting(samples.end() - 3, samples.end());
  const CubeFlightState f = cube_flight_state(resting);
  EXPECT_EQ(f.samples, 0);
  EXPECT_EQ(f.centre, resting[0].centre);
  EXPECT_EQ(f.velocity, resting[0].velocity);
}

// On the real tosses the fitted state, flown ballistically, must follow the
// tracked flight more closely than the data set's first-sample velocities do
// (those lag by half a sample and carry the noise of two samples).
TEST_F(CubeToss, FlightFitFollowsTheTrackedFlight) {
  double fitted = 0, first_sample = 0;
  int count = 0;
  for (const auto& [id, samples] : all()) {
    const CubeFlightState f = cube_flight_state(samples);
    const CubeFlightState given{samples[0].centre, samples[0].velocity, samples[0].orientation,
                                samples[0].orientation * samples[0].omega_body, 0};
    for (int k = 0; k < f.samples; ++k) {
      const double t = samples[k].k / 148.0;
      auto error = [&](const CubeFlightState& s) {
        return (s.centre + s.velocity * t - Eigen::Vector3d(0, 0, 9.81 * t * t / 2) - samples[k].centre).squaredNorm();
      };
      fitted += error(f), first_sample += error(given), ++count;
    }
  }
  const double rms_fitted = std::sqrt(fitted / count), rms_first = std::sqrt(first_sample / count);
  RecordProperty("flight_rms_fitted_mm", std::to_string(1e3 * rms_fitted));
  RecordProperty("flight_rms_first_sample_mm", std::to_string(1e3 * rms_first));
  EXPECT_LT(rms_fitted, 0.5 * rms_first);
  EXPECT_LT(rms_fitted, 1e-3);  // tracking noise is about 0.1 mm; the fit must not be off by a corner's mm
}

// The calibrated prediction must simulate a toss as the fit did: the fitted
// friction and table height replace the nominal's (0.15, -1 mm), which the
// recording's scenario otherwise takes over the calibrated model's `contact`.
TEST_F(CubeToss, CalibratedPredictionUsesTheFittedFrictionAndTableHeight) {
  const Recording r = cube_toss_recording(0, toss(0));
  const nlohmann::json model = {{"contact", {{"layout", "vertices"}, {"mu", 0.2}}}};
  const std::vector<ParameterEstimate> fitted = {{parse_calibration_parameter("mu"), 0.18},
                                                 {parse_calibration_parameter("table_height"), -0.0008},
                                                 {parse_calibration_parameter("restitution"), 0.05}};
  const nlohmann::json plain = recording_scenario(model, r, "table.csv");
  EXPECT_EQ(plain["interfaces"][0]["mu"].get<double>(), 0.15);  // why calibrated_scenario exists
  const nlohmann::json document = calibrated_scenario(model, fitted, r, "table.csv");
  EXPECT_EQ(document["interfaces"][0]["mu"].get<double>(), 0.18);
  EXPECT_EQ(document["interfaces"][0]["restitution"].get<double>(), 0.05);
  EXPECT_EQ(document["table_height"].get<double>(), -0.0008);
  EXPECT_EQ(document["bodies"], r.nominal["bodies"]);
  EXPECT_EQ(calibrated_scenario(model, {}, r, "table.csv"), plain);
}

TEST(CubeTossInput, MalformedFilesNameTheLine) {
  test::TempDir dir;
  EXPECT_THROW(read_cube_tosses(dir / "absent.csv.gz"), InputError);
  // gzopen reads uncompressed files transparently: plain text stands in for a gzip file.
  const std::string header =
      "toss,k,t_s,qw,qx,qy,qz,x_m,y_m,z_m,wx_body_rad_s,wy_body_rad_s,wz_body_rad_s,vx_m_s,vy_m_s,vz_m_s\n";
  const std::string row0 = "0,0,0.000000,1,0,0,0,0,0,0.0512,0,0,0,0,0,0\n";
  try {
    read_cube_tosses(dir.write("bad.csv", header + row0 + "0,1,0.5,1,0,0,0,0,0,0.0512,0,0,0,0,0,0\n"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.csv:3: t_s = 0.5 is not k / 148"), std::string::npos) << e.what();
  }
  try {
    read_cube_tosses(dir.write("q.csv", header + "0,0,0,0.5,0,0,0,0,0,0.0512,0,0,0,0,0,0\n"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("q.csv:2: the quaternion"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_cube_tosses(dir.write("cols.csv", "toss,k\n0,0\n")), InputError);
}

}  // namespace
}  // namespace freestand
