#ifndef BOUNCECAL_VERSION_H_
#define BOUNCECAL_VERSION_H_

#include <string_view>

namespace bouncecal {

// The toolkit version, written into material cards and exported decks for provenance.
std::string_view Version();

}  // namespace bouncecal

#endif  // BOUNCECAL_VERSION_H_
