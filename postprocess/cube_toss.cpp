#include "cube_toss.h"

#include <fmt/format.h>
#include <zlib.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <limits>

#include "csv_cells.h"
#include "freestand/body_channels.h"
#include "freestand/input_error.h"

namespace freestand {
namespace {

using nlohmann::json;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

const std::vector<std::string> kColumns = {
    "toss", "k", "t_s", "qw", "qx", "qy", "qz", "x_m", "y_m", "z_m",
    "wx_body_rad_s", "wy_body_rad_s", "wz_body_rad_s", "vx_m_s", "vy_m_s", "vz_m_s"};

// Pose extension columns (docs/recordings.md), in this order.
const std::vector<std::string> kPoseColumns = {"x", "y", "z", "qw", "qx", "qy", "qz"};

// Lines of a gzip file, '\n' removed.
class GzLines {
 public:
  explicit GzLines(const std::string& path) : path_(path), file_(gzopen(path.c_str(), "rb")) {
    if (!file_) throw InputError(fmt::format("{}: cannot open file", path));
  }
  ~GzLines() { gzclose(file_); }
  GzLines(const GzLines&) = delete;
  GzLines& operator=(const GzLines&) = delete;

  bool next(std::string& line) {
    line.clear();
    std::array<char, 4096> buffer;
    while (gzgets(file_, buffer.data(), buffer.size())) {
      line += buffer.data();
      if (!line.empty() && line.back() == '\n') break;
    }
    int status = Z_OK;
    const char* message = gzerror(file_, &status);
    if (status != Z_OK && status != Z_STREAM_END)
      throw InputError(fmt::format("{}: corrupt gzip data: {}", path_, message));
    if (line.empty()) return false;
    while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
    ++number_;
    return true;
  }
  int number() const { return number_; }

 private:
  std::string path_;  // for messages
  gzFile file_;       // open file
  int number_ = 0;    // 1-based number of the last line read
};

CubeTossSample parse_sample(const std::vector<double>& v) {
  CubeTossSample s;
  s.k = static_cast<int>(v[1]);
  s.orientation = Eigen::Quaterniond(v[3], v[4], v[5], v[6]);
  s.centre = {v[7], v[8], v[9]};
  s.omega_body = {v[10], v[11], v[12]};
  s.velocity = {v[13], v[14], v[15]};
  return s;
}

// The 24 rotations of a cube onto itself (signed permutation matrices of
// determinant +1), identity first.
std::vector<Eigen::Matrix3d> cube_symmetries() {
  std::vector<Eigen::Matrix3d> out;
  const std::array<std::array<int, 3>, 6> permutations = {
      {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  for (const auto& p : permutations)
    for (int signs = 0; signs < 8; ++signs) {
      Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
      for (int i = 0; i < 3; ++i) m(i, p[i]) = (signs >> i & 1) ? -1.0 : 1.0;
      if (m.determinant() > 0) out.push_back(m);
    }
  return out;
}

// The symmetry S (tracked body frame -> new body frame) whose z axis points
// most nearly up in the final pose: the face the cube comes to rest on
// becomes the base. Of the four candidates, the smallest turn (identity if
// the tracked base is already down).
Eigen::Quaterniond base_relabelling(const Eigen::Quaterniond& final_orientation) {
  const Eigen::Matrix3d r = final_orientation.toRotationMatrix();
  Eigen::Matrix3d best = Eigen::Matrix3d::Identity();
  double best_up = -2, best_trace = -2;
  for (const Eigen::Matrix3d& s : cube_symmetries()) {
    const double up = (r * s).col(2).z();
    const bool higher = up > best_up + 1e-9;
    if (higher || (up > best_up - 1e-9 && s.trace() > best_trace)) {
      best = s;
      best_up = up;
      best_trace = s.trace();
    }
  }
  return Eigen::Quaterniond(best);
}

json vector_json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// Height of the lowest corner of a cube of edge `edge` in pose (centre, q).
double lowest_corner(const Eigen::Vector3d& centre, const Eigen::Quaterniond& q, double edge) {
  // The lowest corner of a centred cube lies (edge / 2) sum_i |R_zi| below its centre.
  return centre.z() - edge / 2 * q.toRotationMatrix().row(2).cwiseAbs().sum();
}

// Least-squares line y = a + b t through rows of `values` (one column per
// component): row 0 the intercepts a, row 1 the slopes b.
Eigen::Matrix<double, 2, 3> fit_lines(const Eigen::VectorXd& t, const Eigen::MatrixX3d& values) {
  Eigen::MatrixX2d design(t.size(), 2);
  design.col(0).setOnes();
  design.col(1) = t;
  return design.colPivHouseholderQr().solve(values);
}

// Rotation vector of q (angle times axis, angle in [0, pi]) and back.
Eigen::Vector3d rotation_vector(const Eigen::Quaterniond& q) {
  const Eigen::AngleAxisd a(q);
  return a.angle() * a.axis();
}
Eigen::Quaterniond rotation(const Eigen::Vector3d& r) {
  const double angle = r.norm();
  return angle > 0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, r / angle)) : Eigen::Quaterniond::Identity();
}

json cube_nominal(int id, const std::vector<CubeTossSample>& samples, const CubeTossModel& m,
                  const Eigen::Quaterniond& relabel) {
  const CubeFlightState flight = cube_flight_state(samples, m);
  Eigen::Quaterniond q0 = flight.orientation * relabel;
  if (q0.w() < 0) q0.coeffs() *= -1;
  const double half = m.edge / 2;
  const Eigen::Vector3d base = flight.centre - q0 * Eigen::Vector3d(0, 0, half);
  const double i = m.inertia;
  json cube = {{"name", "cube"},
               {"shape", "box"},
               {"half_extents", {half, half, half}},
               {"mass", m.mass},
               {"com", {0.0, 0.0, half}},
               {"inertia", {{i, 0.0, 0.0}, {0.0, i, 0.0}, {0.0, 0.0, i}}},
               {"supported_by", "table"},
               {"position", vector_json(base)},
               {"orientation", {q0.w(), q0.x(), q0.y(), q0.z()}},
               {"velocity", vector_json(flight.velocity)},
               {"omega", vector_json(flight.omega)}};
  json columns = json::object();
  for (const char* c : {"x", "y", "z"})
    columns[std::string("cube.") + c] = fmt::format("cube centre {}, world frame (m)", c);
  for (const char* c : {"qw", "qx", "qy", "qz"})
    columns[std::string("cube.") + c] = fmt::format("orientation body -> world, {} component (scalar first)", c);
  return {{"bodies", {cube}},
          {"interfaces", {{{"lower", "table"}, {"upper", "cube"}, {"mu", m.mu}}}},
          {"sampling_hz", m.sampling_hz},
          {"duration", samples.back().k / m.sampling_hz},
          {"table_height", m.table_height},
          {"ground_motion", "none: the table is fixed"},
          {"columns", columns},
          {"source", fmt::format("DAIR Lab cube toss {} (Pfrommer, Halm, Posa, CoRL 2020; "
                                 "DAIRLab/dair_pll assets/contactnets_cube, commit 523d372d). "
                                 "Body frame = tracked frame turned by the cube symmetry "
                                 "[w, x, y, z] = [{:.6g}, {:.6g}, {:.6g}, {:.6g}] so that the "
                                 "face it rests on at the end is the base. Initial state: {}",
                                 id, relabel.w(), relabel.x(), relabel.y(), relabel.z(),
                                 flight.samples > 0
                                     ? fmt::format("least-squares free flight through samples 0-{}",
                                                   flight.samples - 1)
                                     : std::string("the first sample (fewer than 2 in free flight)"))}};
}

}  // namespace

std::map<int, std::vector<CubeTossSample>> read_cube_tosses(const std::string& gz_path) {
  GzLines lines(gz_path);
  std::string text;
  if (!lines.next(text)) throw InputError(fmt::format("{}: empty file", gz_path));
  std::vector<std::string> header;
  for (std::string_view cell : split_cells(text)) header.emplace_back(cell);
  if (header != kColumns)
    throw InputError(fmt::format("{}:1: expected the columns {}", gz_path, fmt::join(kColumns, ",")));
  std::map<int, std::vector<CubeTossSample>> tosses;
  std::vector<double> values(kColumns.size());
  while (lines.next(text)) {
    const std::string where = fmt::format("{}:{}", gz_path, lines.number());
    const std::vector<std::string_view> cells = split_cells(text);
    if (cells.size() != kColumns.size())
      throw InputError(fmt::format("{}: {} cells, expected {}", where, cells.size(), kColumns.size()));
    for (std::size_t c = 0; c < cells.size(); ++c) {
      values[c] = cell_value(cells[c], where, c + 1, kColumns[c]);
      if (std::isnan(values[c]))
        throw InputError(fmt::format("{}: column {} ('{}') is empty", where, c + 1, kColumns[c]));
    }
    const CubeTossSample sample = parse_sample(values);
    std::vector<CubeTossSample>& toss = tosses[static_cast<int>(values[0])];
    // t_s is k / 148 printed to 6 decimals: within 5e-7 s of it.
    if (std::fabs(values[2] - sample.k / CubeTossModel{}.sampling_hz) > 1e-6)
      throw InputError(fmt::format("{}: t_s = {} is not k / 148 (k = {})", where, values[2], sample.k));
    // 7 significant digits per component keep the norm within ~1e-6 of 1.
    if (std::fabs(sample.orientation.norm() - 1) > 1e-4)
      throw InputError(fmt::format("{}: the quaternion is not of unit length", where));
    if (!toss.empty() && sample.k <= toss.back().k)
      throw InputError(fmt::format("{}: k = {} does not increase", where, sample.k));
    toss.push_back(sample);
    toss.back().orientation.normalize();
  }
  return tosses;
}

CubeFlightState cube_flight_state(const std::vector<CubeTossSample>& samples, const CubeTossModel& model,
                                  double gravity) {
  if (samples.empty()) throw InputError("cube toss: no samples");
  std::size_t n = 0;
  while (n < samples.size() &&
         lowest_corner(samples[n].centre, samples[n].orientation, model.edge) > model.table_height + model.flight_clearance)
    ++n;
  const CubeTossSample& first = samples.front();
  if (n < 2) return {first.centre, first.velocity, first.orientation, first.orientation * first.omega_body, 0};
  Eigen::VectorXd t(n);
  Eigen::MatrixX3d centres(n, 3), turns(n, 3);
  for (std::size_t k = 0; k < n; ++k) {
    t[k] = (samples[k].k - first.k) / model.sampling_hz;
    centres.row(k) = samples[k].centre + Eigen::Vector3d(0, 0, gravity * t[k] * t[k] / 2);
  }
  const Eigen::Matrix<double, 2, 3> flight = fit_lines(t, centres);
  // R_k = exp(omega t_k) R0: rotation vectors of R_k relative to a reference
  // lie on a line when the reference is R0. Gauss-Newton from the first
  // sample: the line's intercept is the reference's offset from R0 (to first
  // order), so turn the reference by it until it vanishes.
  Eigen::Quaterniond reference = first.orientation;
  Eigen::Matrix<double, 2, 3> spin;
  // The offset shrinks by the ratio of the neglected second-order terms
  // (|omega t| |offset| / 2, well below 1): 1e-12 rad within a few steps.
  for (int iteration = 0; iteration < 20; ++iteration) {
    for (std::size_t k = 0; k < n; ++k)
      turns.row(k) = rotation_vector(samples[k].orientation * reference.conjugate());
    spin = fit_lines(t, turns);
    const Eigen::Vector3d offset = spin.row(0).transpose();
    reference = (rotation(offset) * reference).normalized();
    if (offset.norm() < 1e-12) break;
  }
  return {flight.row(0).transpose(), flight.row(1).transpose(), reference, spin.row(1).transpose(),
          static_cast<int>(n)};
}

Recording cube_toss_recording(int id, const std::vector<CubeTossSample>& samples,
                              const CubeTossModel& model) {
  if (samples.empty()) throw InputError(fmt::format("cube toss {}: no samples", id));
  const Eigen::Quaterniond relabel = base_relabelling(samples.back().orientation);
  if (samples.front().k != 0) throw InputError(fmt::format("cube toss {}: does not start at k = 0", id));
  const std::size_t n = static_cast<std::size_t>(samples.back().k) + 1;  // missing k stay NaN
  Recording r;
  r.time.resize(n);
  for (std::size_t k = 0; k < n; ++k) r.time[k] = k / model.sampling_hz;
  for (const std::string& c : channel_names()) r.channels.push_back({"cube." + c, std::vector<double>(n, kNaN)});
  for (const std::string& c : kPoseColumns) r.channels.push_back({"cube." + c, std::vector<double>(n, kNaN)});

  const double half = model.edge / 2;
  BodyChannels channels({ChannelBody{"cube", 0, BodyFrameGeometry{{0, 0, half}, model.edge}, -1,
                                     Eigen::Quaterniond::Identity(), true}});
  Eigen::Quaterniond q0 = samples.front().orientation * relabel;
  if (q0.w() < 0) q0.coeffs() *= -1;  // first sample: scalar part >= 0
  Eigen::Quaterniond previous = q0;
  for (const CubeTossSample& s : samples) {
    Eigen::Quaterniond q = s.orientation * relabel;
    if (q.dot(previous) < 0) q.coeffs() *= -1;  // continuous sign: q and -q are one rotation
    previous = q;
    const std::vector<double> modes =
        channel_values(channels.update({BodyPose{s.centre, q}}, {1}, Eigen::Vector3d::Zero())[0]);
    const std::vector<double> pose = {s.centre.x(), s.centre.y(), s.centre.z(), q.w(), q.x(), q.y(), q.z()};
    for (std::size_t c = 0; c < modes.size(); ++c) r.channels[c].values[s.k] = modes[c];
    for (std::size_t c = 0; c < pose.size(); ++c) r.channels[modes.size() + c].values[s.k] = pose[c];
  }
  r.nominal = cube_nominal(id, samples, model, relabel);
  return r;
}

std::vector<std::string> convert_cube_tosses(const std::string& gz_path, const std::string& out_dir,
                                             int first, int last) {
  if (first > last)
    throw InputError(fmt::format("cube tosses: first ({}) is after last ({})", first, last));
  const std::map<int, std::vector<CubeTossSample>> tosses = read_cube_tosses(gz_path);
  for (int id = first; id <= last; ++id)
    if (!tosses.count(id))
      throw InputError(fmt::format("{}: no toss {} (the file holds {}-{})", gz_path, id,
                                   tosses.begin()->first, tosses.rbegin()->first));
  std::error_code error;
  std::filesystem::create_directories(out_dir, error);
  if (error) throw InputError(fmt::format("{}: cannot create directory: {}", out_dir, error.message()));
  std::vector<std::string> stems;
  for (int id = first; id <= last; ++id) {
    stems.push_back((std::filesystem::path(out_dir) / fmt::format("cube_toss_{:03d}", id)).string());
    write_recording(stems.back(), cube_toss_recording(id, tosses.at(id)));
  }
  return stems;
}

}  // namespace freestand
