#ifndef BOUNCECAL_EXPORT_SCENE_PACKING_H_
#define BOUNCECAL_EXPORT_SCENE_PACKING_H_

#include "bouncecal/dem/scene.h"
#include "bouncecal/export/packing_deck.h"

namespace bouncecal::calibrate {

// The engine-neutral packing spec of a bouncecal scene (docs/scenes.md). 3D: shifted so that the
// container's floor centre is the origin, particles poured. 2D (a box): the particles the scene
// starts from (its random placement or its start file, as `bouncecal pack --duration 0` places
// them) become the deck's start.data, in the scene's coordinates. Throws ConfigError, naming the
// scene file and the key, for what the exported decks cannot express: more than one species, van
// der Waals attraction, Cundall local damping, the first-contact stop, a plane container, a 2D
// pour or a 3D start file.
PackingDeckSpec PackingDeckSpecFromScene(const dem::Scene& scene);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_EXPORT_SCENE_PACKING_H_
