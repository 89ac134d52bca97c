#ifndef FREESTAND_SCENE_CONTACT_LAWS_H
#define FREESTAND_SCENE_CONTACT_LAWS_H

// The contact law of every pair of surfaces of a scene that can touch, as fix
// rigid/convex applies them: a stated interface's law between its two
// surfaces, the defaults' law everywhere else (the sides of a statue and its
// pedestal, neighbours in a wall, a toppled drum on the table). The fix and
// the freestand tool (a scenario's critical time step) build them here, so
// both see the same laws.

#include <utility>
#include <vector>

#include "freestand/contact_law.h"
#include "freestand/scene.h"

namespace freestand {

class SceneContactLaws {
 public:
  // Every interface's tangential damping ratio is the defaults' (or, for
  // "normal", its own normal one: the tangential force of an impact then
  // rises and decays with the normal force instead of lagging behind it).
  // Names are looked up once (a 1000-block wall has some 2000 interfaces).
  // Throws InputError for a law that cannot be built.
  SceneContactLaws(const Scene& scene, const SceneDefaults& defaults);

  const ContactLaw& table(int body) const { return laws_[table_[body]]; }  // body on the table
  const ContactLaw& between(int body_a, int body_b) const;                  // two bodies, either order

 private:
  std::vector<ContactLaw> laws_;                            // per stated interface, the defaults' last
  std::vector<int> table_;                                  // per body: index in laws_ of its table contact
  std::vector<std::vector<std::pair<int, int>>> partners_;  // per body: (other body, index in laws_),
                                                            //   stated interfaces only
};

}  // namespace freestand

#endif
