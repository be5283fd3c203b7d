#ifndef BOUNCECAL_CALIBRATE_EXPORT_SCENE_PACKING_H_
#define BOUNCECAL_CALIBRATE_EXPORT_SCENE_PACKING_H_

#include "bouncecal/calibrate/export/packing_deck.h"
#include "bouncecal/dem/scene.h"

namespace bouncecal::calibrate {

// The engine-neutral packing spec of a bouncecal scene (docs/scenes.md), shifted so that the
// container's floor centre is the origin. Throws ConfigError, naming the scene file and the key,
// for what the exported decks cannot express: 2D scenes, more than one species, van der Waals
// attraction, Cundall local damping, a plane container, insertion from a file.
PackingDeckSpec PackingDeckSpecFromScene(const dem::Scene& scene);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_EXPORT_SCENE_PACKING_H_
