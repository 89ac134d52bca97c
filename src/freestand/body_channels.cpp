#include "freestand/body_channels.h"

#include <fmt/format.h>

#include "freestand/input_error.h"

namespace freestand {

const std::vector<std::string>& channel_names() {
  static const std::vector<std::string> names = {"rock_x",  "rock_y",  "twist",
                                                 "slide_x", "slide_y", "uplift"};
  return names;
}

std::vector<double> channel_values(const ModeChannels& c) {
  return {c.rock_x, c.rock_y, c.twist, c.slide_x, c.slide_y, c.uplift};
}

BodyChannels::BodyChannels(std::vector<ChannelBody> bodies)
    : bodies_(std::move(bodies)), frame_offset_(bodies_.size()), trackers_(bodies_.size()),
      table_anchor_(bodies_.size()) {
  const int n = static_cast<int>(bodies_.size());
  for (int i = 0; i < n; ++i) {
    // Walking down the supports must reach the table within n steps.
    int below = bodies_[i].support;
    for (int steps = 0; below >= 0; ++steps) {
      if (below >= n) throw InputError(fmt::format("body '{}': unknown support", bodies_[i].name));
      if (steps >= n)
        throw InputError(fmt::format("body '{}': supports form a cycle", bodies_[i].name));
      below = bodies_[below].support;
    }
  }
}

std::vector<ModeChannels> BodyChannels::update(const std::vector<BodyPose>& source_poses,
                                               const std::vector<char>& present,
                                               const TablePose& table) {
  const std::size_t n = bodies_.size();
  own_.assign(n, BodyPose{});
  known_.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const int k = bodies_[i].index;
    if (k < 0 || k >= static_cast<int>(source_poses.size()) || !present[k]) continue;
    const BodyPose& pose = source_poses[k];
    if (!frame_offset_[i])
      frame_offset_[i] = bodies_[i].source_frame_is_own
                             ? Eigen::Quaterniond::Identity()
                             : pose.orientation.conjugate() * bodies_[i].initial_frame;
    own_[i] = {pose.com, (pose.orientation * *frame_offset_[i]).normalized(), pose.velocity, pose.omega};
    known_[i] = 1;
  }
  std::vector<ModeChannels> channels(n);
  for (std::size_t i = 0; i < n; ++i) {
    const int below = bodies_[i].support;
    if (!known_[i] || (below >= 0 && !known_[below])) continue;
    const Eigen::Vector3d support =
        below < 0 ? table_point(i, table) : top_centre(own_[below], bodies_[below].geometry);
    channels[i] = trackers_[i].update(own_[i], bodies_[i].geometry, support);
  }
  return channels;
}

// d + (R R0^-1 - I) q0, q0 the base centre's initial offset from the table's
// reference point: the material point's displacement, written so that a
// table that does not turn (R = R0 = I, exactly) gives d bit for bit.
Eigen::Vector3d BodyChannels::table_point(std::size_t i, const TablePose& table) {
  if (!table_anchor_[i])
    table_anchor_[i] = TableAnchor{base_centre(own_[i], bodies_[i].geometry) - table.pivot - table.displacement,
                                   table.orientation.conjugate()};
  const Eigen::Matrix3d turn = (table.orientation * table_anchor_[i]->initial_inverse).toRotationMatrix() -
                               Eigen::Matrix3d::Identity();
  return table.displacement + turn * table_anchor_[i]->offset;
}

}  // namespace freestand
