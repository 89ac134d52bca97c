#include "freestand/scene.h"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "freestand/input_error.h"

namespace freestand {
namespace {

using nlohmann::json;

const json& field(const json& j, const std::string& key, const std::string& where) {
  if (!j.contains(key)) fail(where, fmt::format("'{}' is missing", key));
  return j.at(key);
}

double number(const json& j, const std::string& key, const std::string& where) {
  const json& v = field(j, key, where);
  if (!v.is_number() || !std::isfinite(v.get<double>()))
    fail(where, fmt::format("'{}' must be a finite number", key));
  return v.get<double>();
}

double positive(const json& j, const std::string& key, const std::string& where) {
  const double v = number(j, key, where);
  if (v <= 0) fail(where, fmt::format("'{}' must be > 0, got {}", key, v));
  return v;
}

Eigen::Vector3d vector3(const json& j, const std::string& key, const std::string& where) {
  const json& v = field(j, key, where);
  if (!v.is_array() || v.size() != 3) fail(where, fmt::format("'{}' must be [x, y, z]", key));
  Eigen::Vector3d out;
  for (int i = 0; i < 3; ++i) {
    if (!v[i].is_number()) fail(where, fmt::format("'{}' must hold numbers", key));
    out[i] = v[i].get<double>();
  }
  if (!out.allFinite()) fail(where, fmt::format("'{}' must be finite", key));
  return out;
}

Eigen::Vector3d vector3_or(const json& j, const std::string& key, const std::string& where,
                           const Eigen::Vector3d& fallback) {
  return j.contains(key) ? vector3(j, key, where) : fallback;
}

Eigen::Matrix3d matrix3(const json& j, const std::string& key, const std::string& where) {
  const json& m = j.at(key);
  if (!m.is_array() || m.size() != 3) fail(where, fmt::format("'{}' must be a 3x3 matrix", key));
  Eigen::Matrix3d out;
  for (int r = 0; r < 3; ++r) {
    if (!m[r].is_array() || m[r].size() != 3)
      fail(where, fmt::format("'{}' must be a 3x3 matrix", key));
    for (int c = 0; c < 3; ++c) out(r, c) = m[r][c].get<double>();
  }
  if (!out.allFinite() || !out.isApprox(out.transpose(), 1e-9))
    fail(where, fmt::format("'{}' must be finite and symmetric", key));
  return out;
}

// One convex shape: box, prism or convex (hull of vertices).
ConvexShape parse_convex(const json& j, const std::string& shape, const std::string& where) {
  if (shape == "box") {
    const Eigen::Vector3d h = vector3(j, "half_extents", where);
    if ((h.array() <= 0).any()) fail(where, "'half_extents' must be > 0");
    return ConvexShape::box(h);
  }
  if (shape == "prism") {
    const double sides = number(j, "sides", where);
    if (sides != std::floor(sides)) fail(where, "'sides' must be an integer");
    if (sides < 3) fail(where, fmt::format("'sides' must be >= 3, got {}", sides));
    return ConvexShape::prism(positive(j, "radius", where), static_cast<int>(sides),
                              positive(j, "height", where));
  }
  if (shape == "convex") {
    const json& vertices = field(j, "vertices", where);
    if (!vertices.is_array()) fail(where, "'vertices' must be a list of [x, y, z]");
    std::vector<Eigen::Vector3d> points;
    for (const json& p : vertices) {
      if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() ||
          !p[2].is_number())
        fail(where, "'vertices' must be a list of [x, y, z]");
      points.emplace_back(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
    }
    return ConvexShape::hull(points, where);
  }
  fail(where, fmt::format("unknown shape '{}' (box, prism, convex{})", shape,
                          where.find(": piece ") == std::string::npos ? ", clump" : ""));
}

std::string shape_name(const json& j, const std::string& where) {
  if (!j.contains("shape")) fail(where, "'shape' is missing");
  if (!j.at("shape").is_string()) fail(where, "'shape' must be a string");
  return j.at("shape").get<std::string>();
}

// A unit quaternion [w, x, y, z] (normalised when within 1e-6 of unit length).
Eigen::Quaterniond quaternion(const json& j, const std::string& key, const std::string& where) {
  const json& q = j.at(key);
  if (!q.is_array() || q.size() != 4 || !q[0].is_number() || !q[1].is_number() ||
      !q[2].is_number() || !q[3].is_number())
    fail(where, fmt::format("'{}' must be a quaternion [w, x, y, z]", key));
  Eigen::Quaterniond out(q[0].get<double>(), q[1].get<double>(), q[2].get<double>(),
                         q[3].get<double>());
  if (!out.coeffs().allFinite() || std::fabs(out.norm() - 1.0) > 1e-6)
    fail(where, fmt::format("'{}' must be a unit quaternion", key));
  return out.normalized();
}

// A body's geometry: one convex shape, or a clump of pieces placed in the
// body frame by "offset" and "orientation" (piece frame -> body frame).
Clump parse_shape(const json& body, const std::string& where) {
  const std::string shape = shape_name(body, where);
  if (shape != "clump") return Clump(parse_convex(body, shape, where));
  if (!body.contains("pieces")) fail(where, "clump: 'pieces' is missing");
  const json& pieces = body.at("pieces");
  if (!pieces.is_array() || pieces.empty())
    fail(where, "clump: 'pieces' must be a non-empty list of shapes");
  std::vector<ClumpPiece> list;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const json& p = pieces[i];
    std::string piece_where = fmt::format("{}: piece {}", where, i);
    if (!p.is_object()) fail(piece_where, "must be an object with 'shape'");
    const std::string piece_shape = shape_name(p, piece_where);
    piece_where += fmt::format(" ({})", piece_shape);
    if (piece_shape == "clump") fail(piece_where, "a clump piece cannot itself be a clump");
    for (const char* key : {"mass", "density", "com", "inertia", "position", "velocity", "omega",
                            "nodes", "base", "supported_by", "name"})
      if (p.contains(key))
        fail(piece_where, fmt::format("'{}' belongs to the body, not to a piece", key));
    ClumpPiece piece{parse_convex(p, piece_shape, piece_where)};
    if (p.contains("offset")) piece.offset = vector3(p, "offset", piece_where);
    if (p.contains("orientation")) piece.orientation = quaternion(p, "orientation", piece_where);
    list.push_back(piece);
  }
  return Clump(list, where + ": clump");
}

// "nodes": {"spacing": H | "per_edge": N, "layout": L, "refine": "all" | "bearing"}.
NodeOptions parse_nodes(const json& body, const Clump& geometry, const NodeOptions& fallback,
                        const std::string& where) {
  if (!body.contains("nodes")) return fallback;
  const json& n = body.at("nodes");
  if (!n.is_object()) fail(where, "nodes: must be an object with 'per_edge' or 'spacing', 'layout', 'refine'");
  for (const auto& [key, value] : n.items())
    if (key != "spacing" && key != "per_edge" && key != "layout" && key != "refine")
      fail(where, fmt::format("nodes: unknown key '{}' (spacing, per_edge, layout, refine)", key));
  NodeOptions options = fallback;
  if (n.contains("spacing")) options.spacing = positive(n, "spacing", where);
  if (n.contains("per_edge")) options.per_edge = static_cast<int>(positive(n, "per_edge", where));
  if (n.contains("layout")) {
    const std::string layout = n.at("layout").get<std::string>();
    if (layout == "surface") options.layout = NodeLayout::kSurface;
    else if (layout == "boundary") options.layout = NodeLayout::kBoundary;
    else if (layout == "vertices") options.layout = NodeLayout::kVertices;
    else fail(where, fmt::format("nodes: unknown layout '{}' (surface, boundary, vertices)", layout));
  }
  if (n.contains("refine")) {
    const std::string refine = n.at("refine").is_string() ? n.at("refine").get<std::string>() : "";
    if (refine == "bearing") options.refined = geometry.bearing_faces();
    else if (refine == "all") options.refined.clear();
    else fail(where, fmt::format("nodes: refine must be \"all\" or \"bearing\", got {}", n.at("refine").dump()));
  }
  return options;
}

// "base": {"edge_inset": D, "corner_gaps": [{"corner": [X, Y], "gap": G}, ...]},
// checked against the body's base.
BaseShape parse_base(const json& body, const Clump& geometry, const std::string& where) {
  BaseShape base;
  if (!body.contains("base")) return base;
  const json& b = body.at("base");
  const std::string here = where + ": base";
  if (!b.is_object()) fail(here, "must be an object with 'edge_inset' and/or 'corner_gaps'");
  for (const auto& [key, value] : b.items())
    if (key != "edge_inset" && key != "corner_gaps")
      fail(here, fmt::format("unknown key '{}' (edge_inset, corner_gaps)", key));
  if (b.contains("edge_inset")) base.edge_inset = number(b, "edge_inset", here);
  if (b.contains("corner_gaps")) {
    const json& gaps = b.at("corner_gaps");
    if (!gaps.is_array()) fail(here, "'corner_gaps' must be a list of {\"corner\": [x, y], \"gap\": m}");
    for (std::size_t i = 0; i < gaps.size(); ++i) {
      const std::string gap_where = fmt::format("{}: corner_gaps[{}]", here, i);
      const json& corner = field(gaps[i], "corner", gap_where);
      if (!corner.is_array() || corner.size() != 2 || !corner[0].is_number() || !corner[1].is_number())
        fail(gap_where, "'corner' must be a direction [x, y] in the body frame");
      base.corner_gaps.push_back({Eigen::Vector2d(corner[0].get<double>(), corner[1].get<double>()),
                                  number(gaps[i], "gap", gap_where)});
    }
  }
  try {
    BaseMap{geometry, base};
  } catch (const InputError& e) {
    fail(where, e.what());
  }
  return base;
}

// Mass, COM and inertia: as stated, the rest from geometry at uniform density.
void fill_mass(const json& j, BodySpec& body, const SceneDefaults& defaults,
               const std::string& where) {
  const double volume = body.geometry.volume();
  double density = defaults.density;
  if (j.contains("mass")) {
    body.mass = positive(j, "mass", where);
    density = body.mass / volume;
  } else if (j.contains("density")) {
    density = positive(j, "density", where);
    body.mass = density * volume;
  } else {
    body.mass = density * volume;
    body.notes.push_back(fmt::format("{}: no mass or density given: density {} kg/m^3", where, density));
  }
  const MassProperties geometric = body.geometry.mass_properties(density);
  body.com = vector3_or(j, "com", where, geometric.com);
  body.inertia = j.contains("inertia") ? matrix3(j, "inertia", where) : geometric.inertia;
  if (j.contains("com") && !j.contains("inertia"))
    // Geometric inertia moved to the stated COM (parallel-axis theorem).
    body.inertia -= body.mass * ((body.com - geometric.com).squaredNorm() * Eigen::Matrix3d::Identity() -
                                 (body.com - geometric.com) * (body.com - geometric.com).transpose());
}

BodySpec parse_body(const json& j, const SceneDefaults& defaults, const std::string& source,
                    std::size_t index) {
  const std::string name = j.value("name", fmt::format("body{}", index + 1));
  const std::string where = fmt::format("{}: body '{}'", source, name);
  if (name == "table") fail(where, "the name 'table' is reserved for the shake table");
  BodySpec body(name, parse_shape(j, where));
  fill_mass(j, body, defaults, where);
  body.height = body.geometry.bounding_box().max().z();
  body.supported_by = j.value("supported_by", std::string("table"));
  body.velocity = vector3_or(j, "velocity", where, Eigen::Vector3d::Zero());
  body.omega = vector3_or(j, "omega", where, Eigen::Vector3d::Zero());
  body.orientation = Eigen::Quaterniond::Identity();
  if (j.contains("orientation")) {
    body.orientation = quaternion(j, "orientation", where);
  }
  body.position = vector3_or(j, "position", where, Eigen::Vector3d::Constant(NAN));
  body.nodes = parse_nodes(j, body.geometry, defaults.nodes, where);
  body.nodes.base = parse_base(j, body.geometry, where);
  return body;
}

// Bodies without a position stand upright, centred on what supports them.
void place_bodies(Scene& scene, const std::string& source) {
  std::set<std::string> placed;
  for (std::size_t pass = 0; pass <= scene.bodies.size(); ++pass) {
    for (BodySpec& body : scene.bodies) {
      if (placed.count(body.name)) continue;
      if (body.position.allFinite()) { placed.insert(body.name); continue; }
      if (body.supported_by == "table") {
        body.position = Eigen::Vector3d::Zero();
        placed.insert(body.name);
        continue;
      }
      for (const BodySpec& below : scene.bodies) {
        if (below.name != body.supported_by || !placed.count(below.name)) continue;
        body.position = below.position + below.orientation * Eigen::Vector3d(0, 0, below.height);
        placed.insert(body.name);
      }
    }
  }
  for (const BodySpec& body : scene.bodies)
    if (!placed.count(body.name))
      fail(source, fmt::format("body '{}' is supported_by '{}', which is neither 'table' nor a "
                               "body, or the supports form a cycle", body.name, body.supported_by));
}

InterfaceSpec parse_interface(const json& j, const SceneDefaults& defaults, const std::string& where) {
  InterfaceSpec spec;
  spec.lower = j.at("lower").get<std::string>();
  spec.upper = j.at("upper").get<std::string>();
  ContactParams& c = spec.contact;
  if (j.contains("mu")) c.mu_s = c.mu_k = number(j, "mu", where);
  if (j.contains("mu_s")) c.mu_s = number(j, "mu_s", where);
  if (j.contains("mu_k")) c.mu_k = number(j, "mu_k", where);
  if (std::isnan(c.mu_s) && !std::isnan(c.mu_k)) c.mu_s = c.mu_k;
  if (std::isnan(c.mu_k) && !std::isnan(c.mu_s)) c.mu_k = c.mu_s;
  if (std::isnan(c.mu_s)) {
    c.mu_s = c.mu_k = defaults.mu;
    spec.notes.push_back(fmt::format("{}: no friction stated: mu = {}", where, defaults.mu));
  }
  if (j.contains("friction_decay")) c.friction_decay = number(j, "friction_decay", where);
  if (j.contains("restitution")) c.restitution = number(j, "restitution", where);
  else {
    c.restitution = defaults.restitution;
    spec.notes.push_back(fmt::format("{}: no restitution stated: {}", where, defaults.restitution));
  }
  return spec;
}

// Per-area stiffness: the stated total stiffness over the upper body's base area.
void fill_stiffness(Scene& scene, InterfaceSpec& spec, const json* stated,
                    const SceneDefaults& defaults, const std::string& where) {
  const BodySpec* upper = nullptr;
  for (const BodySpec& b : scene.bodies) if (b.name == spec.upper) upper = &b;
  if (!upper) fail(where, fmt::format("unknown body '{}'", spec.upper));
  double base_area = 0;
  for (const FaceRef& f : upper->geometry.base_faces())
    base_area += upper->geometry.pieces()[f.piece].faces()[f.face].area;
  if (stated && stated->contains("contact_stiffness")) {
    spec.contact.stiffness_per_area = positive(*stated, "contact_stiffness", where) / base_area;
  } else {
    spec.contact.stiffness_per_area = defaults.stiffness_per_area;
    spec.notes.push_back(fmt::format("{}: no contact_stiffness stated: {:.3g} N/m^3 per area "
                                     "({:.3g} N/m over the base)", where,
                                     defaults.stiffness_per_area,
                                     defaults.stiffness_per_area * base_area));
  }
  // Normal law: linear, or Hertz with the reference overlap at which its
  // pressure equals the linear law's; by default the upper body's resting
  // overlap under its own weight, so both laws rest at the same overlap.
  const std::string law = stated ? stated->value("law", defaults.law) : defaults.law;
  if (law == "hertz") {
    spec.contact.law = NormalLaw::kHertz;
    spec.contact.hertz_reference_overlap =
        stated && stated->contains("hertz_reference_overlap")
            ? positive(*stated, "hertz_reference_overlap", where)
            : upper->mass * scene.gravity / (spec.contact.stiffness_per_area * base_area);
  } else if (law != "linear") {
    fail(where, fmt::format("unknown law '{}' (linear, hertz)", law));
  }
}

}  // namespace

Scene parse_scene(const json& document, const std::string& source, const SceneDefaults& defaults) {
  try {
    Scene scene;
    if (document.contains("gravity")) scene.gravity = positive(document, "gravity", source);
    const json& bodies = document.at("bodies");
    for (std::size_t i = 0; i < bodies.size(); ++i)
      scene.bodies.push_back(parse_body(bodies[i], defaults, source, i));
    std::set<std::string> names;
    for (const BodySpec& b : scene.bodies)
      if (!names.insert(b.name).second) fail(source, fmt::format("body name '{}' used twice", b.name));
    place_bodies(scene, source);
    // Every body touches what supports it: that interface is stated or defaulted.
    for (const BodySpec& b : scene.bodies) {
      const json* stated = nullptr;
      if (document.contains("interfaces"))
        for (const json& i : document.at("interfaces"))
          if (i.value("lower", "") == b.supported_by && i.value("upper", "") == b.name) stated = &i;
      const std::string where = fmt::format("{}: interface {}/{}", source, b.supported_by, b.name);
      json empty = {{"lower", b.supported_by}, {"upper", b.name}};
      InterfaceSpec spec = parse_interface(stated ? *stated : empty, defaults, where);
      fill_stiffness(scene, spec, stated, defaults, where);
      ContactLaw{spec.contact};  // validates, naming the field
      scene.interfaces.push_back(spec);
    }
    return scene;
  } catch (const json::exception& e) {
    throw InputError(fmt::format("{}: {}", source, e.what()));
  }
}

Scene read_scene_file(const std::string& path, const SceneDefaults& defaults) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot open file", path));
  json document;
  try {
    in >> document;
  } catch (const json::parse_error& e) {
    throw InputError(fmt::format("{}: not valid JSON: {}", path, e.what()));
  }
  return parse_scene(document, path, defaults);
}

bool set_scene_default(SceneDefaults& defaults, const std::string& key, const std::string& value) {
  const auto number = [&] {
    std::size_t end = 0;
    double x = std::nan("");
    try {
      x = std::stod(value, &end);
    } catch (const std::exception&) {
    }
    if (end != value.size() || !std::isfinite(x)) fail(key, fmt::format("expects a number, got '{}'", value));
    return x;
  };
  if (key == "stiffness") defaults.stiffness_per_area = number();
  else if (key == "restitution") defaults.restitution = number();
  else if (key == "mu") defaults.mu = number();
  else if (key == "spacing") defaults.nodes.spacing = number();
  else if (key == "law") {
    if (value != "linear" && value != "hertz") fail(key, "must be linear or hertz");
    defaults.law = value;
  } else if (key == "layout") {
    if (value == "surface") defaults.nodes.layout = NodeLayout::kSurface;
    else if (value == "boundary") defaults.nodes.layout = NodeLayout::kBoundary;
    else if (value == "vertices") defaults.nodes.layout = NodeLayout::kVertices;
    else fail(key, "must be surface, boundary or vertices");
  } else if (key == "tangential_damping") {
    defaults.tangential_damping = value == "normal" ? -1.0 : number();
    if (value != "normal" && defaults.tangential_damping < 0) fail(key, "must be >= 0 or 'normal'");
  } else {
    return false;
  }
  return true;
}

const InterfaceSpec* find_interface(const Scene& scene, const std::string& lower,
                                    const std::string& upper) {
  for (const InterfaceSpec& i : scene.interfaces)
    if (i.lower == lower && i.upper == upper) return &i;
  return nullptr;
}

}  // namespace freestand
