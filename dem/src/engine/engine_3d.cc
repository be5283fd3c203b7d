// The 3D engine factory; the force loops it picks from are compiled in engine_3d_part*.cc.
#include "engine/engine_impl.h"

namespace bouncecal::dem::scene {

template std::unique_ptr<EngineBase<3>> MakeEngine<3>(const EngineSettings&, std::vector<Wall<3>>,
                                                      const ContactLawConfig&, const PhysicsSpec&);

}  // namespace bouncecal::dem::scene
