// The 2D force loops: one instantiation per contact law and physics combination. Split by
// dimension so the two halves compile in parallel.
#include "scene/engine_impl.h"

namespace bouncecal::dem::scene {

template std::unique_ptr<EngineBase<2>> MakeEngine<2>(const EngineSettings&, std::vector<Wall<2>>,
                                                      const ContactLawConfig&, const PhysicsSpec&);

}  // namespace bouncecal::dem::scene
