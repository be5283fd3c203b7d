#ifndef BOUNCECAL_CALIBRATE_CONTACT_STIFFNESS_H_
#define BOUNCECAL_CALIBRATE_CONTACT_STIFFNESS_H_

#include <optional>
#include <string>
#include <string_view>

#include "bouncecal/dem/contact_law.h"
#include "bouncecal/dem/drop.h"

namespace bouncecal::calibrate {

// A drop constrains the damping, not the stiffness: k_n (or E*) sets only how long a contact
// lasts, and with it the DEM time step of the drops and of every packing run built on the card.
// So the stiffness is chosen to match the ball's contact duration, and the card states both.

// The law's elastic parameter (the one --stiffness-n-per-m or --modulus-pa sets):
// "stiffness_n_per_m" for the linear laws, "effective_modulus_pa" for the Hertz ones.
std::string_view ElasticParameterName(dem::ContactLawKind kind);

// The law's gravity-free closed-form contact duration for the ball on a rigid plane at
// `impact_speed_mps` (dem::ClosedFormContactDurationOf), or nothing where the law has none.
// walton-braun: t_c = (pi/2) sqrt(m/k_n) (1/sqrt(1 + gamma_n) + 1/sqrt(1 - gamma_n));
// linear-dashpot: t_c = pi / sqrt(k/m - (zeta omega)^2) = pi / (omega sqrt(1 - zeta^2));
// Hertz: t_c = 2.868 (m^2 / (E*^2 R v))^(1/5) (docs/physics.md: 2 I xi_max / v).
std::optional<double> ContactDurationS(const dem::ContactLawConfig& law, const dem::Ball& ball,
                                       double impact_speed_mps);

// The law with its elastic parameter set so that ContactDurationS equals `contact_duration_s`,
// the other parameters as they are. The inverse of the closed form: for the linear laws
//   walton-braun:   k_n = m (pi/2)^2 (1/sqrt(1 + gamma_n) + 1/sqrt(1 - gamma_n))^2 / t_c^2,
//   linear-dashpot: k   = m pi^2 / ((1 - zeta^2) t_c^2),
// for the Hertz laws E* = 2.868^(5/2) m / (sqrt(R v) t_c^(5/2)) (elastic part), found by
// iterating on the closed form so a law's damping term is included. ConfigError naming the law
// when it has no closed-form duration, and naming the value when the parameter it needs lies
// outside the law's range.
dem::ContactLawConfig WithContactDuration(dem::ContactLawConfig law, const dem::Ball& ball,
                                          double impact_speed_mps, double contact_duration_s);

// One line when a named ball's contact duration is known (BallPreset::contact_duration_s) and the
// law's, with its elastic parameter left at the default, is off by more than a factor 3; it names
// both durations, the stiffness and what to give instead. Empty otherwise.
std::string ContactDurationWarning(const dem::ContactLawConfig& law, const dem::Ball& ball,
                                   std::string_view ball_preset, double impact_speed_mps);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_CONTACT_STIFFNESS_H_
