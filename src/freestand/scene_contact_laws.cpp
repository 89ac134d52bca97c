#include "freestand/scene_contact_laws.h"

#include <string>
#include <unordered_map>

namespace freestand {

SceneContactLaws::SceneContactLaws(const Scene& scene, const SceneDefaults& defaults) {
  const auto with_tangential_damping = [&](ContactParams params) {
    params.tangential_damping_ratio =
        defaults.tangential_damping >= 0.0 ? defaults.tangential_damping : ContactLaw(params).damping_ratio();
    return ContactLaw(params);
  };
  for (const InterfaceSpec& interface : scene.interfaces) laws_.push_back(with_tangential_damping(interface.contact));
  ContactParams fallback;
  fallback.stiffness_per_area = defaults.stiffness_per_area;
  fallback.restitution = defaults.restitution;
  fallback.mu_s = fallback.mu_k = defaults.mu;
  laws_.push_back(with_tangential_damping(fallback));

  const int defaults_law = static_cast<int>(laws_.size()) - 1;
  table_.assign(scene.bodies.size(), defaults_law);
  partners_.resize(scene.bodies.size());
  std::unordered_map<std::string, int> index_of;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) index_of.emplace(scene.bodies[b].name, static_cast<int>(b));
  const auto body = [&](const std::string& name) {
    const auto found = index_of.find(name);
    return found == index_of.end() ? -1 : found->second;
  };
  // In the scene's order: a later table interface of a body overrides an earlier one.
  for (std::size_t k = 0; k < scene.interfaces.size(); ++k) {
    const InterfaceSpec& interface = scene.interfaces[k];
    const int lower = body(interface.lower), upper = body(interface.upper), law = static_cast<int>(k);
    if (upper >= 0 && interface.lower == "table") table_[upper] = law;
    if (lower < 0 || upper < 0) continue;
    partners_[lower].emplace_back(upper, law);
    if (upper != lower) partners_[upper].emplace_back(lower, law);
  }
}

// Called per contact pair and step: a scan of the few stated partners of one body.
const ContactLaw& SceneContactLaws::between(int body_a, int body_b) const {
  for (const auto& [partner, law] : partners_[body_a])
    if (partner == body_b) return laws_[law];
  return laws_.back();
}

}  // namespace freestand
