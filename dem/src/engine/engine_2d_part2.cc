// The 2D force loops of the contact laws in part 2 (engine_impl.h, kEngineParts).
#include "engine/engine_impl.h"

namespace bouncecal::dem::scene {

template std::unique_ptr<EngineBase<2>> MakeEnginePart<2, 2>(const EngineSettings&,
                                                             std::vector<Wall<2>>,
                                                             const ContactLaw&, const PhysicsSpec&);

}  // namespace bouncecal::dem::scene
