#ifndef FREESTAND_POST_VTK_SERIES_H
#define FREESTAND_POST_VTK_SERIES_H

// A ParaView time series of a simulation: the bodies' true faces, the shake
// table and optional contact forces, one VTK XML PolyData file (.vtp) per
// frame and kind, indexed by bodies.pvd, table.pvd and contacts.pvd.
// docs/paraview.md lists the files, arrays and units.
//
// Everything is in SI units in the world frame. Poses are given as in a
// results HDF5 (docs/fix_rockslide_hdf5.md): the centre of mass in the world
// and the rotation from the body's own frame (origin at the base-face centre,
// z up) to the world.

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "freestand/rocking_angles.h"
#include "freestand/shape_clump.h"

namespace freestand {

// A body as drawn.
struct SeriesBody {
  std::string name;
  Clump geometry;                                  // pieces in the body frame
  Eigen::Vector3d com = Eigen::Vector3d::Zero();   // centre of mass, body frame (m)
};

// One body at one instant.
struct BodyState {
  BodyPose pose;                                       // COM and orientation, world
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // COM velocity (m/s)
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();     // angular velocity (rad/s)
  ModeChannels channels;                               // rad, m
};

// A contact force drawn as a vector at its point of application.
struct ContactVector {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // world (m)
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  // on `body` (N)
  int body = 0;                                     // index into the SeriesBody list
  int other = -1;                                   // the other body's index; -1: the table; -2: other bodies (a resultant)
};

struct SeriesFrame {
  double time = 0.0;                                              // s
  Eigen::Vector3d table_displacement = Eigen::Vector3d::Zero();   // m
  std::vector<BodyState> bodies;                                  // one per SeriesBody, same order
  std::vector<ContactVector> contacts;
};

struct VtkSeriesOptions {
  double table_top_z = 0.0;     // height of the table top at rest (fix shaketable's `plane`, m)
  bool contacts = false;        // write contacts_*.vtp and contacts.pvd
  int stride = 1;               // write_vtk_series: every stride-th sample (the last one always)
};

// Writes frames as they come; the .pvd indices appear at finish(). Every file
// is written under a temporary name and renamed, so files already in the
// directory stay intact until replaced by complete ones.
class VtkSeriesWriter {
 public:
  // Creates `directory` if needed. Throws InputError for an empty body list
  // or a body without faces.
  VtkSeriesWriter(std::string directory, std::vector<SeriesBody> bodies,
                  VtkSeriesOptions options = {});

  // Writes bodies_NNNNNN.vtp, table_NNNNNN.vtp (and contacts_NNNNNN.vtp).
  // The table is sized on the first frame to the bodies' footprint and then
  // only moves. Throws InputError for a frame whose time does not increase,
  // a wrong number of bodies, a contact naming an unknown body or non-finite
  // values.
  void write_frame(const SeriesFrame& frame);

  // Writes the .pvd indices. Returns the path of bodies.pvd.
  std::string finish();

  int frames_written() const { return static_cast<int>(times_.size()); }

 private:
  void check(const SeriesFrame& frame) const;
  void size_table(const SeriesFrame& frame);
  std::string frame_path(const std::string& kind, int index) const;

  std::string directory_;
  std::vector<SeriesBody> bodies_;
  VtkSeriesOptions options_;
  std::vector<double> times_;
  Eigen::Vector3d table_half_extents_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d table_centre_ = Eigen::Vector3d::Zero();  // top-face centre at rest
};

// One body's time series, laid out as /bodies/<name>/ in a results HDF5.
struct BodyHistory {
  std::vector<double> x, y, z;           // COM, world (m)
  std::vector<double> qw, qx, qy, qz;    // body frame -> world
  std::array<std::vector<double>, 6> channels;  // in channel_names() order (rad, m)
  // Optional: empty means differentiated from the poses (central differences,
  // one-sided at the ends).
  std::vector<double> vx, vy, vz;        // COM velocity (m/s)
  std::vector<double> wx, wy, wz;        // angular velocity, world (rad/s)
};

struct SeriesHistory {
  std::vector<double> time;                           // s, strictly increasing
  std::vector<double> table_dx, table_dy, table_dz;   // m; empty: table at rest
  std::vector<BodyHistory> bodies;                    // one per SeriesBody, same order
  std::vector<std::vector<ContactVector>> contacts;    // per sample; empty: none
};

// Writes a whole history (every options.stride-th sample) and returns the path
// of bodies.pvd. Throws InputError naming the body and array whose length
// differs from time's.
std::string write_vtk_series(const std::string& directory, const std::vector<SeriesBody>& bodies,
                             const SeriesHistory& history, VtkSeriesOptions options = {});

// Velocities of samples `positions` at `time` by central differences
// (one-sided at the ends); on a uniform grid exact for quadratic motion
// except at the ends (off by a dt / 2).
std::vector<Eigen::Vector3d> differentiate_positions(const std::vector<double>& time,
                                                     const std::vector<Eigen::Vector3d>& positions);

// Angular velocities (world frame) of orientations sampled at `time`: the
// rotation vector of q[i+1] q[i-1]^-1 over t[i+1] - t[i-1] (one-sided at the
// ends); exact for rotation at constant angular velocity.
std::vector<Eigen::Vector3d> differentiate_orientations(
    const std::vector<double>& time, const std::vector<Eigen::Quaterniond>& orientations);

}  // namespace freestand

#endif
