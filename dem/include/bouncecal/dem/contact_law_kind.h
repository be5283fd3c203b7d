#ifndef BOUNCECAL_DEM_CONTACT_LAW_KIND_H_
#define BOUNCECAL_DEM_CONTACT_LAW_KIND_H_

#include <array>
#include <string>
#include <string_view>

namespace bouncecal::dem {

// The normal contact laws a user picks by name (CLI --law, material cards, scene files).
enum class ContactLawKind {
  kWaltonBraun,         // linear elastic + hysteretic damping, the paper's law (default)
  kWaltonBraunPlastic,  // Walton & Braun 1986: loading k1, unloading k2 from the maximum overlap
  kLinearDashpot,       // Cundall & Strack 1979 spring-dashpot, damping 2*gamma*sqrt(m k)
  kHertz,               // Hertz elastic, F proportional to overlap^(3/2)
  kHertzViscoelastic,   // Hertz + Tsuji 1992 damping proportional to overlap^(1/4) * rate
};

inline constexpr std::array<ContactLawKind, 5> kAllContactLawKinds = {
    ContactLawKind::kWaltonBraun, ContactLawKind::kWaltonBraunPlastic,
    ContactLawKind::kLinearDashpot, ContactLawKind::kHertz, ContactLawKind::kHertzViscoelastic};

std::string_view ToString(ContactLawKind kind);
// Throws ConfigError naming the unknown value and listing the valid names.
ContactLawKind ContactLawKindFromString(std::string_view name);
// "walton-braun, walton-braun-plastic, ..." for help texts and error messages.
std::string ContactLawNames();

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_CONTACT_LAW_KIND_H_
