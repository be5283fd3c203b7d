// The engine factories of a build configured with BOUNCECAL_PACKING_ENGINE=OFF
// (dem/CMakeLists.txt): the force loops, 28 % of a cold build's CPU, are not compiled, so a
// packing stops here with what to do, after its scene was read and checked.
#include "bouncecal/error.h"
#include "engine/engine.h"

namespace bouncecal::dem::scene {

template <int Dim>
std::unique_ptr<EngineBase<Dim>> MakeEngine(const EngineSettings&, std::vector<Wall<Dim>>,
                                            const ContactLawConfig&, const PhysicsSpec&) {
  throw ConfigError(
      "this bouncecal was built without the packing engine (CMake option "
      "BOUNCECAL_PACKING_ENGINE=OFF, as the README's first command builds it to calibrate "
      "sooner); build it with scripts/build.sh, or scripts/run_tests.sh, to run packings");
}

template std::unique_ptr<EngineBase<2>> MakeEngine<2>(const EngineSettings&, std::vector<Wall<2>>,
                                                      const ContactLawConfig&, const PhysicsSpec&);
template std::unique_ptr<EngineBase<3>> MakeEngine<3>(const EngineSettings&, std::vector<Wall<3>>,
                                                      const ContactLawConfig&, const PhysicsSpec&);

}  // namespace bouncecal::dem::scene
