#ifndef BOUNCECAL_DEM_CONTACT_LAW_KIND_H_
#define BOUNCECAL_DEM_CONTACT_LAW_KIND_H_

#include <string>
#include <string_view>

namespace bouncecal::dem {

// The normal contact law a user picks by name (CLI --law, material cards, scene files): the law's
// position in the ContactLaw variant (contact_laws.h), whose laws give their own names. The named
// values are the first laws' positions, kept for the code and tests that name those laws (a
// static_assert in contact_laws.h keeps them in step); a law added later is named
// kKindOf<Law>, and kAllContactLawKinds lists them all.
enum class ContactLawKind : unsigned char {
  kWaltonBraun,         // linear elastic + hysteretic damping, the paper's law (default)
  kWaltonBraunPlastic,  // Walton & Braun 1986: loading k1, unloading k2 from the maximum overlap
  kLinearDashpot,       // Cundall & Strack 1979 spring-dashpot, damping 2*gamma*sqrt(m k)
  kHertz,               // Hertz elastic, F proportional to overlap^(3/2)
  kHertzViscoelastic,   // Hertz + Brilliantov 1996 damping proportional to overlap^(1/2) * rate
};

std::string_view ToString(ContactLawKind kind);
// Throws ConfigError naming the unknown value and listing the valid names.
ContactLawKind ContactLawKindFromString(std::string_view name);
// "walton-braun, walton-braun-plastic, ..." for help texts and error messages.
std::string ContactLawNames();

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_CONTACT_LAW_KIND_H_
