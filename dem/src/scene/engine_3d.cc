// The 3D force loops: one instantiation per contact law and physics combination. Split by
// dimension so the two halves compile in parallel.
#include "scene/engine_impl.h"

namespace bouncecal::dem::scene {

template std::unique_ptr<EngineBase<3>> MakeEngine<3>(const EngineSettings&, std::vector<Wall<3>>,
                                                      const ContactLawConfig&, const PhysicsSpec&);

}  // namespace bouncecal::dem::scene
