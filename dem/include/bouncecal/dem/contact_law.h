#ifndef BOUNCECAL_DEM_CONTACT_LAW_H_
#define BOUNCECAL_DEM_CONTACT_LAW_H_

#include <functional>
#include <map>
#include <span>
#include <string>
#include <string_view>

#include "bouncecal/dem/contact_law_kind.h"

namespace bouncecal::dem {

// What a parameter does to an impact, which decides whether a fit of drops varies it.
enum class ParameterRole {
  kElastic,      // sets the stiffness, hence the contact duration: held fixed unless asked for
  kDissipative,  // sets the energy loss a drop measures: fitted by default
  kOptIn,        // switches an extra effect on (its default switches it off): fitted only if asked
};

// Whether the law's energy loss, through this parameter, depends on the ball (its size and mass,
// by way of the impact speed): then a fit needs the real ball, not a reference one.
enum class BallDependence {
  kNone,
  kAlways,    // the law has a scale of its own (a modulus, a time, a yield pressure)
  kWhenUsed,  // only when the parameter is non-zero or fitted (Luding's flow overlap)
};

// The range a fit searches by default, which may be narrower than the valid range (gamma_n stops
// at 0.98: at 1 the ball never leaves the plane and the drop spends its whole time budget).
struct FitRange {
  double lower = 0;
  double upper = 1;
  bool log_scale = false;
  // When named, lower and upper are multiples of that parameter's value (the plastic law's
  // unloading stiffness searches [k1, 1e4 k1]).
  std::string_view relative_to = {};
};

// A described parameter of a contact law. The descriptions make material cards, CLI options,
// fitting bounds and export generic: nothing outside a law's own file lists its parameters.
struct ParameterSpec {
  std::string_view name;  // snake_case with unit suffix: "stiffness_n_per_m", "gamma_n"
  std::string_view unit;  // "N/m", "1", "Pa", "s"
  double min_value;       // valid closed range [min_value, max_value]
  double max_value;       // may be +infinity
  double default_value;
  std::string_view description;
  ParameterRole role = ParameterRole::kElastic;
  FitRange fit = {};
  BallDependence ball_dependence = BallDependence::kNone;
  // A shorter option name front ends offer for it ("gamma" is the command line's --gamma), shared
  // by the laws whose parameter means the same thing; empty for none.
  std::string_view alias = {};
};

// The parameters of a law, in a fixed order (the law's own Specs()).
std::span<const ParameterSpec> ParameterSpecs(ContactLawKind kind);

// Throws ConfigError unless value is finite and inside [spec.min_value, spec.max_value]. The
// one-line message names `context` (e.g. "walton-braun"), the parameter, the value and the range.
void CheckParameterValue(const ParameterSpec& spec, double value, std::string_view context);

// A law picked by name with its parameters; absent parameters take their defaults.
struct ContactLawConfig {
  ContactLawKind kind = ContactLawKind::kWaltonBraun;
  std::map<std::string, double, std::less<>> parameters;

  // The value if set, else the default. Throws ConfigError if `name` is not a parameter of kind.
  double Get(std::string_view name) const;
  // Throws ConfigError for an unknown name, a non-finite value or one outside [min, max], naming
  // the parameter and its valid range. Cross-parameter rules are checked by the law's
  // constructor (MakeContactLaw), e.g. the plastic law's unloading >= loading stiffness.
  void Validate() const;
};

// What a normal-force evaluator sees. For a sphere on a plane m_eff = m and R_eff = R; for two
// spheres m_eff = m1 m2 / (m1 + m2) and R_eff = R1 R2 / (R1 + R2).
struct NormalContact {
  double overlap_m = 0;         // xi_n >= 0
  double overlap_rate_mps = 0;  // d xi_n / dt, > 0 while loading (approaching)
  double effective_mass_kg = 0;
  double effective_radius_m = 0;
};

// Per-contact memory for laws that need it (walton-braun-plastic keeps the maximum overlap).
// Reset it (value-initialise) when a contact ends.
struct NormalHistory {
  double max_overlap_m = 0;
};

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_CONTACT_LAW_H_
