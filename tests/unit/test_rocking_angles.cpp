// Mode channels against closed-form rotations: the definitions of
// ../shared/recording-format.md applied to poses whose angles are known.

#include <gtest/gtest.h>

#include <cmath>

#include "freestand/body_channels.h"
#include "freestand/input_error.h"
#include "freestand/rocking_angles.h"

using freestand::BodyPose;
using Eigen::AngleAxisd;
using Eigen::Quaterniond;
using Eigen::Vector3d;

namespace {
// Round-off on a handful of trigonometric evaluations: 1e-12 is far below any
// physically meaningful angle (sensor noise is ~5e-4 rad) yet catches any
// wrong sign, axis or convention.
constexpr double kTol = 1e-12;
}  // namespace

TEST(RockingAngles, TiltAboutYIsRockX) {
  // Rotating by +theta about +y tips e3 toward +x: a lean toward +x.
  const double theta = 0.123;
  const Vector3d e3 = Quaterniond(AngleAxisd(theta, Vector3d::UnitY())) * Vector3d::UnitZ();
  EXPECT_NEAR(freestand::rocking_angles(e3).x(), theta, kTol);
  EXPECT_NEAR(freestand::rocking_angles(e3).y(), 0.0, kTol);
}

TEST(RockingAngles, TiltAboutXIsNegativeRockY) {
  // +phi about +x tips e3 toward -y.
  const double phi = 0.2;
  const Vector3d e3 = Quaterniond(AngleAxisd(phi, Vector3d::UnitX())) * Vector3d::UnitZ();
  EXPECT_NEAR(freestand::rocking_angles(e3).y(), -phi, kTol);
  EXPECT_NEAR(freestand::rocking_angles(e3).x(), 0.0, kTol);
}

TEST(ModeChannelTracker, TwistUnwrapsAcrossPi) {
  freestand::ModeChannelTracker tracker;
  freestand::BodyFrameGeometry geometry;
  double last = 0;
  // Two and a half turns in steps of 0.3 rad: twist must grow monotonically
  // past +-pi, where atan2 jumps by 2 pi.
  for (int k = 0; k <= 52; ++k) {
    const double angle = 0.3 * k;
    BodyPose pose{Vector3d::Zero(), Quaterniond(AngleAxisd(angle, Vector3d::UnitZ()))};
    last = tracker.update(pose, geometry, Vector3d::Zero()).twist;
    ASSERT_NEAR(last, angle, 1e-9) << "step " << k;
  }
}

TEST(ModeChannelTracker, SlideIsBaseCentreRelativeToSupport) {
  // A body of COM height 0.5 tilted by theta about its +x base edge at
  // x = 0.1: the base centre moves by (0.1 (1 - cos), -, 0.1 sin) when the
  // body pivots; here we only translate and check table-relative sliding.
  freestand::ModeChannelTracker tracker;
  freestand::BodyFrameGeometry geometry;
  geometry.com = Vector3d(0, 0, 0.5);
  BodyPose pose{Vector3d(1, 2, 0.5), Quaterniond::Identity()};
  tracker.update(pose, geometry, Vector3d(0.3, 0, 0));
  pose.com += Vector3d(0.05, -0.02, 0.001);
  const auto c = tracker.update(pose, geometry, Vector3d(0.31, 0.01, 0));
  EXPECT_NEAR(c.slide_x, 0.05 - 0.01, kTol);
  EXPECT_NEAR(c.slide_y, -0.02 - 0.01, kTol);
  EXPECT_NEAR(c.uplift, 0.001, kTol);
}

TEST(ModeChannelTracker, PureRockingAboutEdgeMovesBaseCentre) {
  // Rocking by theta about the base edge x = b, y-axis: the base centre
  // rotates about the pivot, so slide_x = b (1 - cos theta) exactly and the
  // COM rises by R cos(alpha - theta) - h.
  const double b = 0.125, h = 0.5, theta = 0.1;
  freestand::BodyFrameGeometry geometry;
  geometry.com = Vector3d(0, 0, h);
  const Vector3d pivot(b, 0, 0);
  freestand::ModeChannelTracker tracker;
  tracker.update({Vector3d(0, 0, h), Quaterniond::Identity()}, geometry, Vector3d::Zero());
  const Quaterniond q(AngleAxisd(theta, Vector3d::UnitY()));
  const Vector3d com = pivot + q * (Vector3d(0, 0, h) - pivot);
  const auto c = tracker.update({com, q}, geometry, Vector3d::Zero());
  const double R = std::hypot(b, h), alpha = std::atan2(b, h);
  EXPECT_NEAR(c.rock_x, theta, kTol);
  EXPECT_NEAR(c.slide_x, b * (1 - std::cos(theta)), kTol);
  EXPECT_NEAR(c.uplift, R * std::cos(alpha - theta) - h, kTol);
}

TEST(BodyChannels, IntegratorFrameDoesNotLeakIntoAngles) {
  // An integrator reporting principal axes rotated by 90 deg about z (as a
  // square-section block's degenerate inertia allows) must give the same
  // channels as one reporting the body's own axes.
  freestand::ChannelBody body;
  body.name = "block";
  body.geometry.com = Vector3d(0, 0, 0.5);
  body.geometry.height = 1.0;
  freestand::BodyChannels channels({body});
  const Quaterniond principal(AngleAxisd(M_PI / 2, Vector3d::UnitZ()));
  std::vector<char> present{1};
  channels.update({{Vector3d(0, 0, 0.5), principal}}, present, Vector3d::Zero());
  const Quaterniond tilt(AngleAxisd(0.05, Vector3d::UnitY()));
  const auto c = channels.update({{Vector3d(0, 0, 0.5), tilt * principal}}, present,
                                 Vector3d::Zero());
  EXPECT_NEAR(c[0].rock_x, 0.05, kTol);
  EXPECT_NEAR(c[0].rock_y, 0.0, kTol);
  EXPECT_NEAR(c[0].twist, 0.0, kTol);
}

TEST(BodyChannels, StackedBodySlidesRelativeToTopFaceOfBodyBelow) {
  freestand::ChannelBody pedestal, statue;
  pedestal.name = "pedestal";
  pedestal.index = 0;
  pedestal.geometry = {Vector3d(0, 0, 0.5), 1.0};
  statue.name = "statue";
  statue.index = 1;
  statue.geometry = {Vector3d(0, 0, 0.8), 1.6};
  statue.support = 0;
  freestand::BodyChannels channels({pedestal, statue});
  std::vector<char> present{1, 1};
  channels.update({{Vector3d(0, 0, 0.5), Quaterniond::Identity()},
                   {Vector3d(0, 0, 1.8), Quaterniond::Identity()}},
                  present, Vector3d::Zero());
  // Both move together by 0.2 in x with the table: no sliding anywhere.
  const auto c = channels.update({{Vector3d(0.2, 0, 0.5), Quaterniond::Identity()},
                                  {Vector3d(0.2, 0, 1.8), Quaterniond::Identity()}},
                                 present, Vector3d(0.2, 0, 0));
  EXPECT_NEAR(c[0].slide_x, 0.0, kTol);
  EXPECT_NEAR(c[1].slide_x, 0.0, kTol);
}

TEST(BodyChannels, RejectsCyclicSupport) {
  freestand::ChannelBody a, b;
  a.name = "a";
  b.name = "b";
  a.support = 1;
  b.support = 0;
  EXPECT_THROW(freestand::BodyChannels({a, b}), freestand::InputError);
}
