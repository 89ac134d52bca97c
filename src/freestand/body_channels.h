#ifndef FREESTAND_BODY_CHANNELS_H
#define FREESTAND_BODY_CHANNELS_H

// Mode channels of a set of bodies, single or stacked: each body slides
// relative to what supports it (the table, or the top face of the body
// below), as ../shared/recording-format.md defines.

#include <optional>
#include <string>
#include <vector>

#include "freestand/rocking_angles.h"

namespace freestand {

// One body as the user describes it to the channel extraction.
struct ChannelBody {
  std::string name;                  // body name in outputs (/bodies/<name>/...)
  int index = 0;                     // index into the pose list given to update()
  BodyFrameGeometry geometry;        // COM and top-face height in the body's own frame
  int support = -1;                  // index into the ChannelBody list of the body below; -1: the table
  Eigen::Quaterniond initial_frame = Eigen::Quaterniond::Identity();  // body's own frame at the
                                     // first update, relative to the world
  bool source_frame_is_own = false;  // the integrator reports the body's own frame (no offset)
};

// The channel names, in the order of ModeChannels' fields.
const std::vector<std::string>& channel_names();
// ModeChannels as an array in channel_names() order.
std::vector<double> channel_values(const ModeChannels& channels);

// Where the shake table is (world frame). It turns about its reference
// point, at `pivot` at rest and moved by `displacement` (fix shaketable).
struct TablePose {
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // table frame -> world
  Eigen::Vector3d pivot = Eigen::Vector3d::Zero();
};

class BodyChannels {
 public:
  // Throws InputError for an unknown or cyclic support.
  explicit BodyChannels(std::vector<ChannelBody> bodies);

  // Channels of every body, in the order given to the constructor.
  // source_poses: poses as the integrator reports them (its own body-fixed
  // frame, e.g. principal axes); present: which exist yet. A body's own
  // frame is tied to the integrator's frame at its first update, so the
  // integrator's choice of axes does not leak into the angles.
  // table: where the table is. A body on the table slides relative to the
  // table's material point that was under its base centre at its first
  // update (with a table that does not turn: the table's displacement).
  std::vector<ModeChannels> update(const std::vector<BodyPose>& source_poses,
                                   const std::vector<char>& present, const TablePose& table);
  std::vector<ModeChannels> update(const std::vector<BodyPose>& source_poses,
                                   const std::vector<char>& present,
                                   const Eigen::Vector3d& table_displacement) {
    return update(source_poses, present, TablePose{table_displacement});
  }

  const std::vector<ChannelBody>& bodies() const { return bodies_; }
  // Poses in each body's own frame from the last update(), body order, and
  // whether each body existed then.
  const std::vector<BodyPose>& own_poses() const { return own_; }
  const std::vector<char>& known() const { return known_; }

 private:
  std::vector<ChannelBody> bodies_;                    // as given, validated
  std::vector<std::optional<Eigen::Quaterniond>> frame_offset_;  // source frame -> own frame, once known
  std::vector<ModeChannelTracker> trackers_;           // one per body
  // The table point a bottom body slides relative to: its offset from the
  // table's reference point and the table's inverse orientation, at the
  // body's first update.
  struct TableAnchor {
    Eigen::Vector3d offset;
    Eigen::Quaterniond initial_inverse;
  };
  std::vector<std::optional<TableAnchor>> table_anchor_;  // one per body, once known
  Eigen::Vector3d table_point(std::size_t body, const TablePose& table);
  std::vector<BodyPose> own_;                          // last poses, own frame
  std::vector<char> known_;                            // body existed at the last update
};

}  // namespace freestand

#endif
