#ifndef BOUNCECAL_DEM_CONTACT_LAWS_H_
#define BOUNCECAL_DEM_CONTACT_LAWS_H_

#include <variant>

#include "bouncecal/dem/contact_law.h"
#include "bouncecal/dem/laws/hertz.h"
#include "bouncecal/dem/laws/hertz_viscoelastic.h"
#include "bouncecal/dem/laws/linear_dashpot.h"
#include "bouncecal/dem/laws/walton_braun.h"
#include "bouncecal/dem/laws/walton_braun_plastic.h"

namespace bouncecal::dem {

// Every normal contact law. Adding a law: its header (with kKind, Params, FromConfig, Specs and
// NormalForce), its ContactLawKind value, and one line here. ParameterSpecs and MakeContactLaw
// find it through kKind; drivers dispatch once per run with std::visit and then run a loop
// specialised for that law.
using ContactLaw =
    std::variant<WaltonBraun, WaltonBraunPlastic, LinearDashpot, Hertz, HertzViscoelastic>;

// Validates the configuration (ContactLawConfig::Validate plus the law's cross-parameter rules)
// and builds the law. Throws ConfigError naming the bad parameter and its valid range.
ContactLaw MakeContactLaw(const ContactLawConfig& config);

// The kind of a constructed law.
ContactLawKind KindOf(const ContactLaw& law);

// True when the law has a closed-form sphere-on-plane impact (SolveImpactExactly), so the exact
// event-driven drop path applies.
template <typename Law>
concept HasExactImpact = requires(const Law& law) {
  { law.SolveImpactExactly(1.0, 1.0, 1.0) } -> std::same_as<ExactImpact>;
};
bool SupportsExactImpacts(const ContactLaw& law);

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_CONTACT_LAWS_H_
