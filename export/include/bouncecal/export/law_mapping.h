#ifndef BOUNCECAL_EXPORT_LAW_MAPPING_H_
#define BOUNCECAL_EXPORT_LAW_MAPPING_H_

#include <string>
#include <vector>

#include "bouncecal/dem/contact_law.h"
#include "bouncecal/export/engine.h"
#include "bouncecal/export/spring_dashpot.h"

namespace bouncecal::calibrate {

// How a material card's contact law is expressed with the linear spring-dashpot that both target
// engines offer (LAMMPS gran/hooke/history + fix wall/gran, LIGGGHTS hooke/stiffness).
//
// Wall and pair contacts get separate coefficients because the engines scale the damping by the
// contact's effective mass: a sphere on a wall has m_eff = m, two equal spheres m/2, and one
// gamma_n cannot give both the right restitution (the LAMMPS user trap of docs/physics.md
// section 4).
struct LawMapping {
  std::string source_law;          // the card's law name, e.g. "walton-braun"
  std::string source_description;  // name and parameters, for deck headers
  bool exact = false;              // the engine integrates the card's law itself
  SpringDashpot wall;              // sphere on a plane: m_eff = m
  SpringDashpot pair;              // two equal spheres: m_eff = m / 2
  // The card's law, closed form, gravity neglected.
  double restitution = 0;
  double wall_contact_duration_s = 0;
  double pair_contact_duration_s = 0;
  // Sentences for the deck header and the command's output: what was matched, what differs.
  std::vector<std::string> notes;
};

// The paper's hysteretic law (Walton & Braun 1986 style, docs/physics.md section 2): loading
// stiffness (1+gamma_n) k, unloading (1-gamma_n) k, so e = sqrt((1-gamma_n)/(1+gamma_n)) and
// t_c = (pi/2) sqrt(m_eff/k) (1/sqrt(1+gamma_n) + 1/sqrt(1-gamma_n)), both independent of the
// impact speed. Neither engine has it (LIGGGHTS' hooke/hysteresis is Luding's variant, whose e
// depends on the impact speed), so it maps to the spring-dashpot with equal e and equal t_c, for
// wall contacts (m_eff = m) and for equal-sphere pairs (m_eff = m/2) separately; the notes say what
// still differs. Throws ConfigError for k <= 0, gamma_n outside [0, 1) or mass <= 0.
LawMapping MapWaltonBraun(double stiffness_n_per_m, double gamma_n, double ball_mass_kg,
                          Engine engine);

// The Cundall-Strack spring-dashpot with damping coefficient 2 zeta sqrt(m_eff k): the engines'
// own law, so the mapping is exact (gamma_n = 2 zeta sqrt(k / m_eff) per contact kind). Throws
// ConfigError for k <= 0, zeta outside [0, 1) (zeta >= 1 never rebounds) or mass <= 0.
LawMapping MapLinearDashpot(double stiffness_n_per_m, double damping_ratio, double ball_mass_kg,
                            Engine engine);

// Any law of the card, for an engine, as the law's dem::EngineForm says: the engines' own
// spring-dashpot exactly (linear-dashpot), linear hysteresis by MapWaltonBraun, and every other
// law with closed-form restitution and contact duration (dem ClosedForm*) by the spring-dashpot
// with equal e and t_c at the reference impact speed, for wall (m, R) and pair (m/2, R/2)
// contacts; the notes say whether the card's law depends on the impact speed and by how much e
// changes over a factor of 4 in speed. Throws ConfigError, in one line naming the law, its reason
// and the laws that can be exported, for a law that states it has no engine form
// (dem::NoEngineForm) or lacks those closed forms, and for bad parameters.
LawMapping MapContactLaw(const dem::ContactLawConfig& law, double ball_mass_kg,
                         double ball_radius_m, double reference_impact_speed_mps, Engine engine);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_EXPORT_LAW_MAPPING_H_
