#ifndef BOUNCECAL_EXPORT_SPRING_DASHPOT_H_
#define BOUNCECAL_EXPORT_SPRING_DASHPOT_H_

namespace bouncecal::calibrate {

// The linear spring-dashpot normal law in the convention both target engines use
// (LAMMPS pair gran/hooke/history and fix wall/gran hooke/history; LIGGGHTS model
// hooke/stiffness with absolute_damping off):
//
//   F_n = k xi_n + m_eff gamma_n dxi_n/dt,
//
// i.e. the damping coefficient is gamma_n times the contact's effective mass, so gamma_n has
// units 1/s. A contact lasts while xi_n > 0 (the damping force may turn attractive just before
// separation; neither engine limits it unless asked), and gravity during the contact is
// neglected. Then the motion is a damped oscillator with beta = gamma_n / 2 and
// omega_d = sqrt(k/m_eff - beta^2) (Cundall & Strack 1979; Schwager & Poeschel 2007 discuss the
// attractive tail), giving the closed forms below.
struct SpringDashpot {
  double stiffness_n_per_m = 0;
  double damping_rate_per_s = 0;  // gamma_n = damping coefficient / m_eff
  double effective_mass_kg = 0;   // m for a sphere on a wall, m/2 for two equal spheres
};

// e = exp(-beta t_c). Returns 0 for an over- or critically damped contact (no rebound).
double Restitution(const SpringDashpot& law);

// t_c = pi / omega_d. Returns +infinity for an over- or critically damped contact.
double ContactDurationS(const SpringDashpot& law);

// The spring-dashpot with the given restitution and contact duration for a contact of the given
// effective mass: beta = -ln e / t_c, omega_d = pi / t_c, k = m_eff (omega_d^2 + beta^2),
// gamma_n = 2 beta. Equal e and equal t_c is the honest way to stand a linear law in for a law
// the engine lacks (docs/physics.md section 4). Throws ConfigError unless 0 < e <= 1, t_c > 0 and
// m_eff > 0 (all finite).
SpringDashpot MatchRestitutionAndDuration(double restitution, double contact_duration_s,
                                          double effective_mass_kg);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_EXPORT_SPRING_DASHPOT_H_
