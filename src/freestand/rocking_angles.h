#ifndef FREESTAND_ROCKING_ANGLES_H
#define FREESTAND_ROCKING_ANGLES_H

// The mode channels of ../shared/recording-format.md, computed from a body's
// pose: rock_x, rock_y, twist, slide_x, slide_y, uplift. These are what users
// read and what recordings contain, so the definitions here are exactly the
// format's, in world coordinates.

#include <Eigen/Geometry>

namespace freestand {

// A rigid body's pose in the world frame.
struct BodyPose {
  Eigen::Vector3d com;             // centre of mass, world frame (m)
  Eigen::Quaterniond orientation;  // rotation from the body's own frame to the world
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // of the centre of mass, world (m/s)
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();     // angular velocity, world (rad/s)
};

// What the channels need to know of a body's shape, in its own frame
// (origin at the centre of the base face, z up).
struct BodyFrameGeometry {
  Eigen::Vector3d com{0, 0, 0};  // centre of mass (m)
  double height = 0.0;           // z of the top face centre (m); used by bodies stacked on this one
};

// The six channels, each minus its initial value except the angles.
struct ModeChannels {
  double rock_x = 0;   // atan2(e3.x, e3.z): lean toward +x in the x-z plane (rad)
  double rock_y = 0;   // atan2(e3.y, e3.z) (rad)
  double twist = 0;    // unwrapped heading of e1 in the x-y plane minus its initial value (rad)
  double slide_x = 0;  // base-centre displacement relative to the support, minus initial (m)
  double slide_y = 0;  // (m)
  double uplift = 0;   // vertical centre-of-mass displacement minus initial (m)
};

// rock_x and rock_y of a body whose own vertical axis is e3 (world frame).
Eigen::Vector2d rocking_angles(const Eigen::Vector3d& e3);

// Heading atan2(e1.y, e1.x) of the body's x axis e1 (world frame), in (-pi, pi].
double heading(const Eigen::Vector3d& e1);

// Centre of the base face in the world frame.
Eigen::Vector3d base_centre(const BodyPose& pose, const BodyFrameGeometry& geometry);

// Centre of the top face in the world frame: where a stacked body is measured from.
Eigen::Vector3d top_centre(const BodyPose& pose, const BodyFrameGeometry& geometry);

// Follows one body through time: keeps the initial values and unwraps twist.
// Call update() at increasing times; the first call fixes the reference.
class ModeChannelTracker {
 public:
  // support: the world point the body slides relative to (the table's
  // displacement for the bottom body, top_centre() of the body below).
  ModeChannels update(const BodyPose& pose, const BodyFrameGeometry& geometry,
                      const Eigen::Vector3d& support);
  bool started() const { return started_; }

 private:
  bool started_ = false;              // false until the first update()
  Eigen::Vector2d slide0_{0, 0};      // initial base-centre offset from the support
  double uplift0_ = 0;                // initial centre-of-mass height
  double heading0_ = 0;               // initial heading of e1
  double unwrapped_heading_ = 0;      // heading of e1 continued across +-pi
};

}  // namespace freestand

#endif
