#ifndef FREESTAND_SCENE_H
#define FREESTAND_SCENE_H

// Bodies and interfaces in the vocabulary of a recording's nominal.json
// (../shared/recording-format.md), plus what a simulation needs beyond it
// (initial pose and velocity, contact nodes). Read by fix rigid/convex and
// by the freestand tool.

#include <nlohmann/json_fwd.hpp>

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "freestand/contact_law.h"
#include "freestand/contact_nodes.h"
#include "freestand/shape_clump.h"

namespace freestand {

// One rigid body. Body frame: origin at the centre of the base face, z up.
struct BodySpec {
  BodySpec(std::string name_, Clump geometry_) : name(std::move(name_)), geometry(std::move(geometry_)) {}

  std::string name;                 // unique; "table" is reserved
  Clump geometry;                   // convex piece(s), body frame
  double mass = 0.0;                // kg
  Eigen::Vector3d com;              // centre of mass, body frame (m)
  Eigen::Matrix3d inertia;          // about the COM, body frame (kg m^2)
  double height = 0.0;              // z of the top-face centre, body frame (m)
  std::string supported_by;         // "table" or the name of the body below
  Eigen::Vector3d position;         // initial base-centre position, world (m)
  Eigen::Quaterniond orientation;   // initial body frame -> world
  Eigen::Vector3d velocity;         // initial velocity of the COM, world (m/s)
  Eigen::Vector3d omega;            // initial angular velocity, world (rad/s)
  NodeOptions nodes;                // contact-node grid on the body's faces
  std::vector<std::string> notes;   // defaults applied, for the log
};

// What is stated about the contact between two surfaces.
struct InterfaceSpec {
  std::string lower;                       // "table" or a body name
  std::string upper;                       // a body name
  ContactParams contact;                   // per-area stiffness, damping, friction
  std::vector<std::string> notes;          // defaults applied, for the log
};

struct Scene {
  std::vector<BodySpec> bodies;            // in file order; body i has body number i + 1
  std::vector<InterfaceSpec> interfaces;   // one per touching pair that was stated or defaulted
  double gravity = 9.81;                   // m/s^2
};

// Defaults for what a scene leaves out (documented in docs/fix_rigid_convex.md).
struct SceneDefaults {
  double density = 2700.0;                 // kg/m^3 (marble), when neither mass nor density is given
  double stiffness_per_area = 1e10;        // N/m^3 (stone on stone: E ~ 5e10 Pa over ~5 m)
  double restitution = 0.05;               // flat face-on impact (docs/benchmarks.md: time to accuracy)
  double mu = 0.6;                         // friction when none is stated
  std::string law = "linear";              // normal law when none is stated: "linear" or "hertz"
  NodeOptions nodes;                       // contact nodes when a body states none
  double tangential_damping = -1.0;        // zeta_t of every law; < 0 ("normal"): each law's own zeta
};

// Sets the default named by one of fix rigid/convex's keywords (`stiffness`, `restitution`,
// `mu`, `law`, `spacing`, `layout`, `tangential_damping`; docs/fix_rigid_convex.md) from its
// text, as the input script or a scenario's `contact` block gives it. Returns false for any
// other key; throws InputError naming the keyword for a bad value.
bool set_scene_default(SceneDefaults& defaults, const std::string& key, const std::string& value);

// Parses a scene; `source` names it in error messages (file name).
// Throws InputError naming the field that is missing, wrong or contradictory.
Scene parse_scene(const nlohmann::json& document, const std::string& source,
                  const SceneDefaults& defaults = {});
Scene read_scene_file(const std::string& path, const SceneDefaults& defaults = {});

// The interface between `lower` and `upper`, or null.
const InterfaceSpec* find_interface(const Scene& scene, const std::string& lower,
                                    const std::string& upper);

}  // namespace freestand

#endif
