#include "vtk_series.h"

#include "atomic_file.h"

#include <fmt/format.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkFieldData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkXMLPolyDataWriter.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "freestand/body_channels.h"
#include "freestand/input_error.h"

namespace freestand {
namespace {

namespace fs = std::filesystem;

// Table slab around the bodies' footprint: margin on each side and thickness,
// as fractions of the bodies' largest extent (a picture scale, not physics).
constexpr double kTableMargin = 0.25;
constexpr double kTableThickness = 0.05;

// The file is built in memory and written in one go: VTK's file output makes
// ~220 small writes and seeks per file, which dominated `freestand post`
// (docs/benchmarks.md).
void write_polydata(vtkPolyData* data, const std::string& path) {
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(data);
  writer->WriteToOutputStringOn();
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();  // raw binary: doubles round-trip exactly
  writer->SetCompressorTypeToZLib();
  writer->SetHeaderTypeToUInt64();
  if (writer->Write() != 1 || writer->GetErrorCode() != vtkErrorCode::NoError)
    throw InputError(fmt::format("{}: cannot write ({})", path,
                                 vtkErrorCode::GetStringFromErrorCode(writer->GetErrorCode())));
  write_file_atomically(path, writer->GetOutputString());
}


vtkNew<vtkDoubleArray> make_array(const char* name, int components) {
  vtkNew<vtkDoubleArray> array;
  array->SetName(name);
  array->SetNumberOfComponents(components);
  return array;
}

vtkNew<vtkIntArray> make_int_array(const char* name) {
  vtkNew<vtkIntArray> array;
  array->SetName(name);
  return array;
}

// Field data every file carries: its time (VTK's TimeValue convention) and
// the body names that *_name_index arrays point into.
void add_field_data(vtkPolyData* data, double time, const std::vector<SeriesBody>& bodies) {
  auto time_value = make_array("TimeValue", 1);
  time_value->InsertNextValue(time);
  data->GetFieldData()->AddArray(time_value);
  vtkNew<vtkStringArray> names;
  names->SetName("body_names");
  for (const auto& body : bodies) names->InsertNextValue(body.name);
  data->GetFieldData()->AddArray(names);
}

// Polygons of faces with outward unit normals as cell normals.
struct Polygons {
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> cells;
  vtkNew<vtkDoubleArray> normals = make_array("Normals", 3);

  Polygons() { points->SetDataTypeToDouble(); }

  // Appends the faces of `shape` moved by x -> rotation x + offset; returns
  // how many faces were added.
  int append(const ConvexShape& shape, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& offset) {
    const vtkIdType first = points->GetNumberOfPoints();
    for (const Eigen::Vector3d& v : shape.vertices()) {
      const Eigen::Vector3d x = rotation * v + offset;
      points->InsertNextPoint(x.data());
    }
    for (const ShapeFace& face : shape.faces()) {
      cells->InsertNextCell(static_cast<vtkIdType>(face.loop.size()));
      for (int k : face.loop) cells->InsertCellPoint(first + k);
      const Eigen::Vector3d n = rotation * face.normal;
      normals->InsertNextTuple(n.data());
    }
    return static_cast<int>(shape.faces().size());
  }

  vtkNew<vtkPolyData> polydata() const {
    vtkNew<vtkPolyData> data;
    data->SetPoints(points);
    data->SetPolys(cells);
    data->GetCellData()->SetNormals(normals);
    return data;
  }
};

// Body frame -> world; quaternions are accepted to 1e-6 of unit length (check()).
Eigen::Matrix3d rotation_of(const BodyPose& pose) { return pose.orientation.normalized().toRotationMatrix(); }

// x_world = com_world + R (x_body - com_body).
Eigen::Vector3d body_offset(const SeriesBody& body, const BodyPose& pose) {
  return pose.com - rotation_of(pose) * body.com;
}

vtkNew<vtkPolyData> bodies_polydata(const std::vector<SeriesBody>& bodies, const SeriesFrame& frame) {
  Polygons polygons;
  auto body_id = make_int_array("body_id");
  auto name_index = make_int_array("body_name_index");
  auto piece = make_int_array("piece");
  auto velocity = make_array("velocity", 3);
  auto omega = make_array("angular_velocity", 3);
  std::vector<vtkNew<vtkDoubleArray>> channels;
  for (const std::string& name : channel_names()) channels.push_back(make_array(name.c_str(), 1));

  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const BodyState& state = frame.bodies[b];
    const Eigen::Matrix3d rotation = rotation_of(state.pose);
    const Eigen::Vector3d offset = body_offset(bodies[b], state.pose);
    const std::vector<double> values = channel_values(state.channels);
    const auto& pieces = bodies[b].geometry.pieces();
    for (std::size_t p = 0; p < pieces.size(); ++p) {
      const int faces = polygons.append(pieces[p], rotation, offset);
      for (int f = 0; f < faces; ++f) {
        body_id->InsertNextValue(static_cast<int>(b) + 1);
        name_index->InsertNextValue(static_cast<int>(b));
        piece->InsertNextValue(static_cast<int>(p));
        velocity->InsertNextTuple(state.velocity.data());
        omega->InsertNextTuple(state.omega.data());
        for (std::size_t c = 0; c < values.size(); ++c) channels[c]->InsertNextValue(values[c]);
      }
    }
  }
  auto data = polygons.polydata();
  vtkCellData* cell = data->GetCellData();
  cell->AddArray(body_id);
  cell->AddArray(name_index);
  cell->AddArray(piece);
  for (auto& channel : channels) cell->AddArray(channel);
  cell->AddArray(velocity);
  cell->AddArray(omega);
  cell->SetActiveScalars("rock_x");
  add_field_data(data, frame.time, bodies);
  return data;
}

vtkNew<vtkPolyData> table_polydata(const Eigen::Vector3d& half_extents, const Eigen::Vector3d& top_centre,
                                   const SeriesFrame& frame, const std::vector<SeriesBody>& bodies) {
  Polygons polygons;
  // ConvexShape::box spans z in [0, 2c]: lower it so that its top is the table top.
  const Eigen::Vector3d offset =
      top_centre - Eigen::Vector3d(0, 0, 2 * half_extents.z()) + frame.table_displacement;
  const int faces = polygons.append(ConvexShape::box(half_extents), Eigen::Matrix3d::Identity(), offset);
  auto displacement = make_array("displacement", 3);
  for (int f = 0; f < faces; ++f) displacement->InsertNextTuple(frame.table_displacement.data());
  auto data = polygons.polydata();
  data->GetCellData()->AddArray(displacement);
  add_field_data(data, frame.time, bodies);
  return data;
}

vtkNew<vtkPolyData> contacts_polydata(const SeriesFrame& frame, const std::vector<SeriesBody>& bodies) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> vertices;
  auto force = make_array("force", 3);
  auto body = make_int_array("body_name_index");
  auto other = make_int_array("other_name_index");
  for (const ContactVector& c : frame.contacts) {
    vertices->InsertNextCell(1);
    vertices->InsertCellPoint(points->InsertNextPoint(c.point.data()));
    force->InsertNextTuple(c.force.data());
    body->InsertNextValue(c.body);
    other->InsertNextValue(c.other);
  }
  vtkNew<vtkPolyData> data;
  data->SetPoints(points);
  data->SetVerts(vertices);
  vtkPointData* point = data->GetPointData();
  point->AddArray(force);
  point->SetActiveVectors("force");
  point->AddArray(body);
  point->AddArray(other);
  add_field_data(data, frame.time, bodies);
  return data;
}

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

}  // namespace

VtkSeriesWriter::VtkSeriesWriter(std::string directory, std::vector<SeriesBody> bodies,
                                 VtkSeriesOptions options)
    : directory_(std::move(directory)), bodies_(std::move(bodies)), options_(options) {
  if (bodies_.empty()) throw InputError(fmt::format("{}: no bodies to write", directory_));
  for (const SeriesBody& body : bodies_)
    if (body.geometry.pieces().empty())
      throw InputError(fmt::format("{}: body '{}' has no faces", directory_, body.name));
  std::error_code error;
  fs::create_directories(directory_, error);
  if (error) throw InputError(fmt::format("{}: cannot create directory: {}", directory_, error.message()));
}

void VtkSeriesWriter::check(const SeriesFrame& frame) const {
  const std::string where = fmt::format("{}: frame at t = {}", directory_, frame.time);
  if (!std::isfinite(frame.time) || (!times_.empty() && frame.time <= times_.back()))
    throw InputError(fmt::format("{}: time must be finite and increase (previous frame t = {})", where,
                                 times_.empty() ? 0.0 : times_.back()));
  if (frame.bodies.size() != bodies_.size())
    throw InputError(fmt::format("{}: {} body states for {} bodies", where, frame.bodies.size(), bodies_.size()));
  if (!finite(frame.table_displacement)) throw InputError(where + ": non-finite table displacement");
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const BodyState& s = frame.bodies[b];
    if (!finite(s.pose.com) || !s.pose.orientation.coeffs().allFinite() ||
        std::abs(s.pose.orientation.norm() - 1.0) > 1e-6)
      throw InputError(fmt::format("{}: body '{}': non-finite position or non-unit quaternion", where,
                                   bodies_[b].name));
  }
  for (const ContactVector& c : frame.contacts) {
    const int n = static_cast<int>(bodies_.size());
    if (c.body < 0 || c.body >= n || c.other < -2 || c.other >= n)
      throw InputError(fmt::format("{}: contact between unknown bodies {} and {}", where, c.body, c.other));
    if (!finite(c.point) || !finite(c.force)) throw InputError(where + ": non-finite contact point or force");
  }
}

void VtkSeriesWriter::size_table(const SeriesFrame& frame) {
  Eigen::AlignedBox3d box;
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const BodyPose& pose = frame.bodies[b].pose;
    const Eigen::Matrix3d rotation = rotation_of(pose);
    const Eigen::Vector3d offset = body_offset(bodies_[b], pose);
    for (const ConvexShape& piece : bodies_[b].geometry.pieces())
      for (const Eigen::Vector3d& v : piece.vertices()) box.extend(rotation * v + offset);
  }
  const double size = box.sizes().maxCoeff();
  const Eigen::Vector3d centre = box.center() - frame.table_displacement;
  table_half_extents_ = Eigen::Vector3d(0.5 * box.sizes().x() + kTableMargin * size,
                                        0.5 * box.sizes().y() + kTableMargin * size,
                                        0.5 * kTableThickness * size);
  table_centre_ = Eigen::Vector3d(centre.x(), centre.y(), options_.table_top_z);
}

std::string VtkSeriesWriter::frame_path(const std::string& kind, int index) const {
  return (fs::path(directory_) / fmt::format("{}_{:06d}.vtp", kind, index)).string();
}

void VtkSeriesWriter::write_frame(const SeriesFrame& frame) {
  check(frame);
  if (times_.empty()) size_table(frame);
  const int index = frames_written();
  write_polydata(bodies_polydata(bodies_, frame), frame_path("bodies", index));
  write_polydata(table_polydata(table_half_extents_, table_centre_, frame, bodies_), frame_path("table", index));
  if (options_.contacts) write_polydata(contacts_polydata(frame, bodies_), frame_path("contacts", index));
  times_.push_back(frame.time);
}

std::string VtkSeriesWriter::finish() {
  std::vector<std::string> kinds = {"bodies", "table"};
  if (options_.contacts) kinds.push_back("contacts");
  for (const std::string& kind : kinds) {
    std::string text =
        "<?xml version=\"1.0\"?>\n"
        "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        "  <Collection>\n";
    for (int i = 0; i < frames_written(); ++i)
      text += fmt::format("    <DataSet timestep=\"{}\" part=\"0\" file=\"{}\"/>\n", times_[i],
                          fs::path(frame_path(kind, i)).filename().string());
    text += "  </Collection>\n</VTKFile>\n";
    write_file_atomically((fs::path(directory_) / (kind + ".pvd")).string(), text);
  }
  return (fs::path(directory_) / "bodies.pvd").string();
}

std::vector<Eigen::Vector3d> differentiate_positions(const std::vector<double>& time,
                                                     const std::vector<Eigen::Vector3d>& positions) {
  const std::size_t n = time.size();
  std::vector<Eigen::Vector3d> rate(n, Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
  if (n < 2) return rate;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t lo = i == 0 ? 0 : i - 1, hi = i + 1 == n ? i : i + 1;
    rate[i] = (positions[hi] - positions[lo]) / (time[hi] - time[lo]);
  }
  return rate;
}

std::vector<Eigen::Vector3d> differentiate_orientations(
    const std::vector<double>& time, const std::vector<Eigen::Quaterniond>& orientations) {
  const std::size_t n = time.size();
  std::vector<Eigen::Vector3d> rate(n, Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
  if (n < 2) return rate;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t lo = i == 0 ? 0 : i - 1, hi = i + 1 == n ? i : i + 1;
    // Rotation from lo to hi in the world frame; AngleAxis takes the short way (angle <= pi).
    const Eigen::AngleAxisd turn(orientations[hi] * orientations[lo].conjugate());
    rate[i] = turn.angle() * turn.axis() / (time[hi] - time[lo]);
  }
  return rate;
}

namespace {

// `values` must have one entry per sample, or be empty when `optional`.
void check_length(const std::vector<double>& values, std::size_t samples, const std::string& where,
                  const std::string& name, bool optional) {
  if (values.size() == samples || (optional && values.empty())) return;
  throw InputError(fmt::format("{}: {} has {} samples, time has {}", where, name, values.size(), samples));
}

// Per-sample states of one body, velocities differentiated when not given.
std::vector<BodyState> body_states(const std::vector<double>& time, const BodyHistory& h,
                                   const std::string& where) {
  const std::size_t n = time.size();
  const std::vector<std::pair<const std::vector<double>*, const char*>> required = {
      {&h.x, "x"}, {&h.y, "y"}, {&h.z, "z"}, {&h.qw, "qw"}, {&h.qx, "qx"}, {&h.qy, "qy"}, {&h.qz, "qz"}};
  for (const auto& [values, name] : required) check_length(*values, n, where, name, false);
  for (std::size_t c = 0; c < h.channels.size(); ++c)
    check_length(h.channels[c], n, where, channel_names()[c], false);
  const std::vector<std::pair<const std::vector<double>*, const char*>> optional = {
      {&h.vx, "vx"}, {&h.vy, "vy"}, {&h.vz, "vz"}, {&h.wx, "wx"}, {&h.wy, "wy"}, {&h.wz, "wz"}};
  for (const auto& [values, name] : optional) check_length(*values, n, where, name, true);

  std::vector<BodyState> states(n);
  std::vector<Eigen::Vector3d> com(n);
  std::vector<Eigen::Quaterniond> orientation(n);
  for (std::size_t i = 0; i < n; ++i) {
    com[i] = {h.x[i], h.y[i], h.z[i]};
    orientation[i] = Eigen::Quaterniond(h.qw[i], h.qx[i], h.qy[i], h.qz[i]);
  }
  const auto velocity = h.vx.empty() ? differentiate_positions(time, com) : std::vector<Eigen::Vector3d>();
  const auto omega = h.wx.empty() ? differentiate_orientations(time, orientation) : std::vector<Eigen::Vector3d>();
  for (std::size_t i = 0; i < n; ++i) {
    BodyState& s = states[i];
    s.pose = {com[i], orientation[i]};
    s.velocity = h.vx.empty() ? velocity[i] : Eigen::Vector3d(h.vx[i], h.vy[i], h.vz[i]);
    s.omega = h.wx.empty() ? omega[i] : Eigen::Vector3d(h.wx[i], h.wy[i], h.wz[i]);
    s.channels = {h.channels[0][i], h.channels[1][i], h.channels[2][i],
                  h.channels[3][i], h.channels[4][i], h.channels[5][i]};
  }
  return states;
}

}  // namespace

std::string write_vtk_series(const std::string& directory, const std::vector<SeriesBody>& bodies,
                             const SeriesHistory& history, VtkSeriesOptions options) {
  const std::size_t n = history.time.size();
  if (n == 0) throw InputError(fmt::format("{}: empty history", directory));
  if (options.stride < 1) throw InputError(fmt::format("{}: stride {} < 1", directory, options.stride));
  if (history.bodies.size() != bodies.size())
    throw InputError(fmt::format("{}: {} body histories for {} bodies", directory, history.bodies.size(),
                                 bodies.size()));
  for (const auto& [values, name] : {std::pair{&history.table_dx, "table dx"},
                                     std::pair{&history.table_dy, "table dy"},
                                     std::pair{&history.table_dz, "table dz"}})
    check_length(*values, n, directory, name, true);
  if (!history.contacts.empty() && history.contacts.size() != n)
    throw InputError(fmt::format("{}: contacts given for {} samples, time has {}", directory,
                                 history.contacts.size(), n));

  std::vector<std::vector<BodyState>> states;
  for (std::size_t b = 0; b < bodies.size(); ++b)
    states.push_back(body_states(history.time, history.bodies[b],
                                 fmt::format("{}: body '{}'", directory, bodies[b].name)));

  options.contacts = options.contacts || !history.contacts.empty();
  VtkSeriesWriter writer(directory, bodies, options);
  const auto component = [](const std::vector<double>& v, std::size_t i) { return v.empty() ? 0.0 : v[i]; };
  std::vector<std::size_t> samples;
  for (std::size_t i = 0; i < n; i += options.stride) samples.push_back(i);
  if (samples.back() != n - 1) samples.push_back(n - 1);  // the end of the run, even off the stride
  for (std::size_t k : samples) {
    SeriesFrame frame;
    frame.time = history.time[k];
    frame.table_displacement = {component(history.table_dx, k), component(history.table_dy, k),
                                component(history.table_dz, k)};
    for (const auto& body : states) frame.bodies.push_back(body[k]);
    if (!history.contacts.empty()) frame.contacts = history.contacts[k];
    writer.write_frame(frame);
  }
  return writer.finish();
}

}  // namespace freestand
