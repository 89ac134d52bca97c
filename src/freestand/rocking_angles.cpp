#include "freestand/rocking_angles.h"

#include <cmath>

namespace freestand {

Eigen::Vector2d rocking_angles(const Eigen::Vector3d& e3) {
  return {std::atan2(e3.x(), e3.z()), std::atan2(e3.y(), e3.z())};
}

double heading(const Eigen::Vector3d& e1) { return std::atan2(e1.y(), e1.x()); }

Eigen::Vector3d base_centre(const BodyPose& pose, const BodyFrameGeometry& geometry) {
  return pose.com - pose.orientation * geometry.com;
}

Eigen::Vector3d top_centre(const BodyPose& pose, const BodyFrameGeometry& geometry) {
  return base_centre(pose, geometry) + pose.orientation * Eigen::Vector3d(0, 0, geometry.height);
}

ModeChannels ModeChannelTracker::update(const BodyPose& pose, const BodyFrameGeometry& geometry,
                                        const Eigen::Vector3d& support) {
  const Eigen::Matrix3d rotation = pose.orientation.toRotationMatrix();
  const Eigen::Vector2d slide = (base_centre(pose, geometry) - support).head<2>();
  const double h = heading(rotation.col(0));
  if (!started_) {
    started_ = true;
    slide0_ = slide;
    uplift0_ = pose.com.z();
    heading0_ = h;
    unwrapped_heading_ = h;
  }
  // Unwrap: the heading moves by less than pi between calls, so the jump
  // across +-pi is the branch cut, not motion.
  unwrapped_heading_ += std::remainder(h - unwrapped_heading_, 2 * M_PI);

  const Eigen::Vector2d rock = rocking_angles(rotation.col(2));
  ModeChannels channels;
  channels.rock_x = rock.x();
  channels.rock_y = rock.y();
  channels.twist = unwrapped_heading_ - heading0_;
  channels.slide_x = slide.x() - slide0_.x();
  channels.slide_y = slide.y() - slide0_.y();
  channels.uplift = pose.com.z() - uplift0_;
  return channels;
}

}  // namespace freestand
