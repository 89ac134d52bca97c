// Rotational table axes (roll, pitch) of freestand::ShakeTable: the angle is
// the exactly integrated angular acceleration, the orientation is
// R_y(pitch) R_x(roll), and the angular velocity and acceleration it reports
// are the time derivatives of that orientation (checked by finite
// differences, independent of the formulas in shake_table.cpp).

#include <gtest/gtest.h>

#include <cmath>

#include "freestand/input_error.h"
#include "freestand/shake_table.h"

namespace {

freestand::ShakeTable table(const std::vector<std::string>& args) {
  return freestand::ShakeTable(freestand::parse_shake_table_args(args));
}

// omega from R' R^T = [omega]x, by central differences of the orientation.
Eigen::Vector3d omega_by_differences(const freestand::ShakeTable& t, double time, double h) {
  const Eigen::Matrix3d dR = (t.at(time + h).orientation.toRotationMatrix() -
                              t.at(time - h).orientation.toRotationMatrix()) / (2 * h);
  const Eigen::Matrix3d W = dR * t.at(time).orientation.toRotationMatrix().transpose();
  return Eigen::Vector3d(W(2, 1), W(0, 2), W(1, 0));
}

}  // namespace

TEST(TableRotation, OneSinePitchEndsAtRestAtItsClosedFormAngle) {
  // One period of A sin(2 pi f t): the angle ends at A / (2 pi f^2) at rest
  // (docs/ground-motion.md), here 0.2 / (2 pi) = 0.0318 rad.
  const auto t = table({"pitch", "onesine", "amplitude", "0.2", "rad/s^2", "frequency", "1"});
  EXPECT_TRUE(t.rotates());
  const freestand::TableState end = t.at(1.5);
  const double angle = 0.2 / (2 * M_PI);
  EXPECT_NEAR(end.pitch, angle, 1e-14);
  EXPECT_EQ(end.roll, 0.0);
  EXPECT_NEAR(end.angular_velocity.norm(), 0.0, 1e-14);
  const Eigen::Vector3d normal = end.orientation * Eigen::Vector3d::UnitZ();
  // A positive pitch turns +x down: the table normal leans toward +x.
  EXPECT_NEAR(normal.x(), std::sin(angle), 1e-14);
  EXPECT_NEAR(normal.z(), std::cos(angle), 1e-14);
  EXPECT_EQ(end.displacement, Eigen::Vector3d::Zero());
}

TEST(TableRotation, AngularVelocityAndAccelerationAreTheOrientationsDerivatives) {
  // Roll and pitch at once, at different frequencies, large angles (about
  // 0.5 rad and more) so that the composition matters. Central differences with
  // h = 1e-5 s: truncation h^2 |omega'''| / 6 ~ 1e-9 rad/s, round-off
  // 1e-16 / h ~ 1e-11; tolerance 1e-7.
  const auto t = table({"roll", "sine", "amplitude", "20", "rad/s^2", "frequency", "1.1", "pitch", "sine",
                        "amplitude", "15", "rad/s^2", "frequency", "0.9"});
  const double h = 1e-5;
  for (double time : {0.71, 1.37, 2.9}) {
    const freestand::TableState s = t.at(time);
    EXPECT_GT(std::fabs(s.roll) + std::fabs(s.pitch), 0.2);
    const Eigen::Vector3d omega = omega_by_differences(t, time, h);
    EXPECT_NEAR((s.angular_velocity - omega).norm(), 0.0, 1e-7) << "t = " << time;
    const Eigen::Vector3d alpha = (t.at(time + h).angular_velocity - t.at(time - h).angular_velocity) / (2 * h);
    EXPECT_NEAR((s.angular_acceleration - alpha).norm(), 0.0, 1e-6) << "t = " << time;
  }
}

TEST(TableRotation, TranslationOnlyTableDoesNotRotate) {
  const auto t = table({"x", "sine", "amplitude", "0.3", "g", "frequency", "2"});
  EXPECT_FALSE(t.rotates());
  const freestand::TableState s = t.at(0.3);
  EXPECT_EQ(s.orientation.coeffs(), Eigen::Quaterniond::Identity().coeffs());
  EXPECT_EQ(s.angular_velocity, Eigen::Vector3d::Zero());
}

TEST(TableRotation, AngularAndLinearUnitsAreNotMixed) {
  using freestand::InputError;
  using freestand::parse_shake_table_args;
  EXPECT_THROW(parse_shake_table_args({"pitch", "sine", "amplitude", "0.2", "g", "frequency", "1"}), InputError);
  EXPECT_THROW(parse_shake_table_args({"x", "sine", "amplitude", "0.2", "rad/s^2", "frequency", "1"}), InputError);
  EXPECT_THROW(parse_shake_table_args({"roll", "record", "r.txt", "units", "g"}), InputError);
  EXPECT_THROW(parse_shake_table_args({"y", "record", "r.txt", "units", "rad/s^2"}), InputError);
  try {
    parse_shake_table_args({"pitch", "sine", "amplitude", "0.2", "m/s^2", "frequency", "1"});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'amplitude' unit must be rad/s^2"), std::string::npos) << e.what();
  }
}
