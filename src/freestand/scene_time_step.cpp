#include "freestand/scene_time_step.h"

#include <algorithm>
#include <limits>
#include <string>
#include <unordered_map>

#include "freestand/contact_nodes.h"
#include "freestand/contact_time_step.h"
#include "freestand/rigid_body.h"

namespace freestand {
namespace {

// The modes of `upper` on its base-face nodes against the table (lower == nullptr) or `lower`.
ContactModes resting_modes(const BodySpec& upper, const BodySpec* lower, const ContactLaw& law, double gravity) {
  NodeOptions base = upper.nodes;
  base.faces = upper.geometry.base_faces();
  std::vector<Eigen::Vector3d> offsets;
  std::vector<double> areas;
  double area = 0.0;
  for (const ContactNode& node : make_contact_nodes(upper.geometry, base)) {
    offsets.push_back(node.position - upper.com);
    areas.push_back(node.area);
    area += node.area;
  }
  if (offsets.empty()) return {};
  const PreparedMassProperties mass({upper.mass, upper.inertia}, upper.name);
  const ContactBody a{mass.mass(), mass.inertia(), Eigen::Vector3d::Zero()};
  // Linearised at the overlap under the body's own weight (Hertz stiffens with
  // overlap; the linear law does not care).
  const double overlap = law.overlap_under_load(area, upper.mass * gravity);
  if (!lower) return resting_critical_time_step(law, offsets, areas, Eigen::Vector3d::UnitZ(), overlap, a);
  const PreparedMassProperties below({lower->mass, lower->inertia}, lower->name);
  const Eigen::Vector3d offset =
      (lower->position + lower->orientation * lower->com) - (upper.position + upper.orientation * upper.com);
  const ContactBody b{below.mass(), below.inertia(), offset};
  return resting_critical_time_step(law, offsets, areas, Eigen::Vector3d::UnitZ(), overlap, a, &b);
}

}  // namespace

SceneTimeStep resting_time_step(const Scene& scene, const SceneContactLaws& laws) {
  std::unordered_map<std::string, int> index_of;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) index_of.emplace(scene.bodies[b].name, static_cast<int>(b));
  double critical = std::numeric_limits<double>::infinity(), recommended = critical;
  const ContactLaw* limiting = nullptr;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const auto found = index_of.find(scene.bodies[b].supported_by);
    const int lower = found == index_of.end() ? -1 : found->second;
    const ContactLaw& law = lower < 0 ? laws.table(static_cast<int>(b)) : laws.between(static_cast<int>(b), lower);
    const ContactModes modes =
        resting_modes(scene.bodies[b], lower < 0 ? nullptr : &scene.bodies[lower], law, scene.gravity);
    if (!(modes.time_step > 0)) continue;
    if (modes.time_step < critical) limiting = &law;
    critical = std::min(critical, modes.time_step);
    recommended = std::min(recommended, modes.time_step * recommended_time_step_fraction(law));
  }
  if (!limiting) return {};
  return {critical, recommended, limiting};
}

}  // namespace freestand
