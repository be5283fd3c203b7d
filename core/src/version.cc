#include "bouncecal/version.h"

namespace bouncecal {

std::string_view Version() { return BOUNCECAL_VERSION; }

}  // namespace bouncecal
