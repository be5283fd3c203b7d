#ifndef BOUNCECAL_DEM_CONTACT_LAWS_H_
#define BOUNCECAL_DEM_CONTACT_LAWS_H_

#include <array>
#include <concepts>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>

#include "bouncecal/dem/contact_law.h"
#include "bouncecal/dem/laws/hertz.h"
#include "bouncecal/dem/laws/hertz_viscoelastic.h"
#include "bouncecal/dem/laws/law_common.h"
#include "bouncecal/dem/laws/linear_dashpot.h"
#include "bouncecal/dem/laws/thornton.h"
#include "bouncecal/dem/laws/walton_braun.h"
#include "bouncecal/dem/laws/walton_braun_plastic.h"

namespace bouncecal::dem {

// Every normal contact law. Adding a law: its header and source in laws/ (a class that is a
// NormalContactLaw, below) and one entry here; its kind (its position here), its name, its
// parameters and its place in every command, card and fit follow from the law. Drivers dispatch
// once per run with std::visit and then run a loop specialised for that law. Appending keeps the
// kinds of the laws before it (they order help texts and break ties between laws).
using ContactLaw = std::variant<WaltonBraun, WaltonBraunPlastic, LinearDashpot, Hertz,
                                HertzViscoelastic, Thornton>;

// The members a law must have, one concept each so that CheckContactLaw can name the missing one.
// They are what the drivers use (the drop, the packing engine, the fitter, the exporter, cards).
namespace law_members {

template <typename Law>
concept Name = requires {
  { Law::kName } -> std::convertible_to<std::string_view>;
};
template <typename Law>
concept History = requires {
  { Law::kNeedsHistory } -> std::convertible_to<bool>;
};
template <typename Law>
concept Parameters = requires(const ContactLawConfig& config, const Law& law) {
  typename Law::Params;
  { Law::FromConfig(config) } -> std::same_as<typename Law::Params>;
  { Law::Specs() } -> std::same_as<std::span<const ParameterSpec>>;
  { law.params() } -> std::same_as<const typename Law::Params&>;
}
&&std::constructible_from<Law, const typename Law::Params&>;
template <typename Law>
concept Force = requires(const Law& law, const NormalContact& contact, NormalHistory& history) {
  { law.NormalForce(contact, history) } -> std::same_as<double>;
};
template <typename Law>
concept ClosedForms = requires(const Law& law, double value) {
  { law.ClosedFormRestitution(value, value, value) } -> std::same_as<std::optional<double>>;
  { law.ClosedFormContactDuration(value, value, value) } -> std::same_as<std::optional<double>>;
};
template <typename Law>
concept StableStep = requires(const Law& law, double value) {
  { law.MaxStableTimeStepS(value, value, value, value) } -> std::same_as<double>;
};
template <typename Law>
concept Energy = requires(const Law& law, const NormalContact& contact,
                          const NormalHistory& history) {
  { law.ReturnableEnergyJ(contact, history) } -> std::same_as<double>;
};

}  // namespace law_members

template <typename Law>
concept NormalContactLaw = law_members::Name<Law> && law_members::History<Law> &&
    law_members::Parameters<Law> && law_members::Force<Law> && law_members::ClosedForms<Law> &&
    law_members::StableStep<Law> && law_members::Energy<Law>;

// Optional: a closed-form sphere-on-plane impact (SolveImpactExactly), so the exact event-driven
// drop path applies.
template <typename Law>
concept HasExactImpact = requires(const Law& law) {
  { law.SolveImpactExactly(1.0, 1.0, 1.0) } -> std::same_as<ExactImpact>;
};
// Optional: how LAMMPS/LIGGGHTS can run the law (EngineForm); without it EngineMatchAtSpeed.
template <typename Law>
concept HasEngineForm = requires(const Law& law) {
  { law.ExportForm() } -> std::same_as<EngineForm>;
};

// One static_assert per member: a law that lacks one stops the build here, the message naming
// the member and the instantiation (CheckContactLaw<bouncecal::dem::NAME>) naming the law, before
// any std::visit over the variant reports it as a template error.
template <typename Law>
consteval bool CheckContactLaw() {
  static_assert(law_members::Name<Law>,
                "a contact law needs `static constexpr std::string_view kName`, the name users "
                "type (the law option, material cards, scene files)");
  static_assert(law_members::History<Law>,
                "a contact law needs `static constexpr bool kNeedsHistory` (true if NormalForce "
                "reads or writes NormalHistory)");
  static_assert(law_members::Parameters<Law>,
                "a contact law needs `struct Params`, a constructor from it, `const Params& "
                "params() const`, `static Params FromConfig(const ContactLawConfig&)` and "
                "`static std::span<const ParameterSpec> Specs()`");
  static_assert(law_members::Force<Law>,
                "a contact law needs `double NormalForce(const NormalContact&, NormalHistory&) "
                "const`");
  static_assert(law_members::ClosedForms<Law>,
                "a contact law needs `std::optional<double> ClosedFormRestitution(m_eff, R_eff, "
                "v) const` and `ClosedFormContactDuration(m_eff, R_eff, v) const` (nullopt where "
                "there is none)");
  static_assert(law_members::StableStep<Law>,
                "a contact law needs `double MaxStableTimeStepS(m_eff, R_eff, v, g) const`");
  static_assert(law_members::Energy<Law>,
                "a contact law needs `double ReturnableEnergyJ(const NormalContact&, const "
                "NormalHistory&) const`");
  return true;
}

namespace law_list {

template <typename... Laws>
consteval bool CheckAll(std::type_identity<std::variant<Laws...>>) {
  return (CheckContactLaw<Laws>() && ...);
}
template <typename Law, typename... Laws>
consteval std::size_t IndexOf(std::type_identity<std::variant<Laws...>>) {
  constexpr std::array<bool, sizeof...(Laws)> matches = {std::is_same_v<Law, Laws>...};
  for (std::size_t i = 0; i < matches.size(); ++i) {
    if (matches[i]) return i;
  }
  return matches.size();
}
template <typename... Laws>
consteval std::array<std::string_view, sizeof...(Laws)> Names(
    std::type_identity<std::variant<Laws...>>) {
  return {Laws::kName...};
}

}  // namespace law_list

static_assert(law_list::CheckAll(std::type_identity<ContactLaw>{}));

// A law's kind is its position in ContactLaw.
template <typename Law>
inline constexpr ContactLawKind kKindOf =
    static_cast<ContactLawKind>(law_list::IndexOf<Law>(std::type_identity<ContactLaw>{}));

inline constexpr auto kAllContactLawKinds = [] {
  std::array<ContactLawKind, std::variant_size_v<ContactLaw>> kinds{};
  for (std::size_t i = 0; i < kinds.size(); ++i) kinds[i] = static_cast<ContactLawKind>(i);
  return kinds;
}();

// Each law's kName, by kind.
inline constexpr auto kContactLawNames = law_list::Names(std::type_identity<ContactLaw>{});

static_assert(
    [] {
      for (std::size_t i = 0; i < kContactLawNames.size(); ++i) {
        for (std::size_t j = 0; j < i; ++j) {
          if (kContactLawNames[i] == kContactLawNames[j]) return false;
        }
      }
      return true;
    }(),
    "two contact laws have the same kName");
static_assert(kKindOf<WaltonBraun> == ContactLawKind::kWaltonBraun &&
                  kKindOf<WaltonBraunPlastic> == ContactLawKind::kWaltonBraunPlastic &&
                  kKindOf<LinearDashpot> == ContactLawKind::kLinearDashpot &&
                  kKindOf<Hertz> == ContactLawKind::kHertz &&
                  kKindOf<HertzViscoelastic> == ContactLawKind::kHertzViscoelastic,
              "the named ContactLawKind values must stay these laws' positions in ContactLaw");

// Validates the configuration (ContactLawConfig::Validate plus the law's cross-parameter rules)
// and builds the law. Throws ConfigError naming the bad parameter and its valid range.
ContactLaw MakeContactLaw(const ContactLawConfig& config);

// The kind of a constructed law.
ContactLawKind KindOf(const ContactLaw& law);

bool SupportsExactImpacts(const ContactLaw& law);
// "walton-braun, walton-braun-plastic, linear-dashpot": the laws with an exact impact.
std::string ExactImpactLawNames();

// How LAMMPS/LIGGGHTS can run the law: its ExportForm(), or EngineMatchAtSpeed without one.
EngineForm ExportFormOf(const ContactLaw& law);

// The law's gravity-free closed forms of one impact at impact_speed_mps (ClosedFormRestitution,
// ClosedFormContactDuration), or nothing where the law has none.
std::optional<double> ClosedFormRestitutionOf(const ContactLaw& law, double effective_mass_kg,
                                              double effective_radius_m, double impact_speed_mps);
std::optional<double> ClosedFormContactDurationOf(const ContactLaw& law, double effective_mass_kg,
                                                  double effective_radius_m,
                                                  double impact_speed_mps);

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_CONTACT_LAWS_H_
