#ifndef FREESTAND_SCENE_TIME_STEP_H
#define FREESTAND_SCENE_TIME_STEP_H

// The critical time step of a whole scene at rest (contact_time_step.h for one
// contact): every body standing on its base-face nodes on what supports it (the
// table or the body below), linearised at the overlap under its own weight.
// fix rigid/convex refuses a larger step; the freestand tool keeps the steps
// of a scenario's variants (a stiffer or more damped contact) below it.

#include "freestand/scene.h"
#include "freestand/scene_contact_laws.h"

namespace freestand {

struct SceneTimeStep {
  double critical = 0.0;            // smallest over the bodies' resting contacts (s); 0: no body has a base
  double recommended = 0.0;         // smallest critical x recommended_time_step_fraction (s)
  const ContactLaw* law = nullptr;  // the contact giving `critical` (points into the laws), or null
};

SceneTimeStep resting_time_step(const Scene& scene, const SceneContactLaws& laws);

}  // namespace freestand

#endif
