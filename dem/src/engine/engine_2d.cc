// The 2D engine factory; the force loops it picks from are compiled in engine_2d_part*.cc.
#include "engine/engine_impl.h"

namespace bouncecal::dem::scene {

template std::unique_ptr<EngineBase<2>> MakeEngine<2>(const EngineSettings&, std::vector<Wall<2>>,
                                                      const ContactLawConfig&, const PhysicsSpec&);

}  // namespace bouncecal::dem::scene
