// The real cube tosses as recordings: channels agree with the tracked pose,
// the base face is the one the cube rests on, the initial state in the
// nominal reproduces the first tracked sample and parses as a scene, and
// the README's angular-velocity frame is checked against the quaternions.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

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
  EXPECT_LT((cube.position + cube.orientation * Eigen::Vector3d(0, 0, 0.0524) - first.centre).norm(), 1e-12);
  EXPECT_LT((cube.com - Eigen::Vector3d(0, 0, 0.0524)).norm(), 1e-15);
  EXPECT_TRUE(cube.orientation.isApprox(pose_orientation(r, 0), 1e-12));
  EXPECT_LT((cube.velocity - first.velocity).norm(), 1e-15);
  EXPECT_LT((cube.omega - first.orientation * first.omega_body).norm(), 1e-12);
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
