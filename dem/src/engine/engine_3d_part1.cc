// The 3D force loops of the contact laws in part 1 (engine_impl.h, kEngineParts).
#include "engine/engine_impl.h"

namespace bouncecal::dem::scene {

template std::unique_ptr<EngineBase<3>> MakeEnginePart<3, 1>(const EngineSettings&,
                                                             std::vector<Wall<3>>,
                                                             const ContactLaw&, const PhysicsSpec&);

}  // namespace bouncecal::dem::scene
