#ifndef BOUNCECAL_APPS_DROP_CLI_OPTIONS_H_
#define BOUNCECAL_APPS_DROP_CLI_OPTIONS_H_

#include <CLI/CLI.hpp>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "bouncecal/calibrate/material_card.h"
#include "bouncecal/dem/contact_law.h"
#include "bouncecal/dem/drop.h"

namespace bouncecal::apps {

// The ball, the law and the drop set-up shared by simulate drop, calibrate, report, sweep and
// compare, so each quantity has one spelling (its SI unit in the name) on every command. Simulate,
// sweep and compare simulate the paper's set-up unless told otherwise (1 cm steel, 7800 kg/m^3,
// h0 = 0.2 m); calibrate describes an experiment and assumes none of it (Geometry::kAsGiven).
struct DropCliOptions {
  enum class Geometry {
    kPaperDefaults,  // absent ball and height are the paper's
    kAsGiven,        // absent means not given; a ball must be complete (size and mass)
  };
  // What Add registers besides the ball, the law parameters and the drop set-up.
  struct Features {
    bool law = true;        // --law
    bool material = false;  // --material CARD: the card's law and ball
    bool gamma = false;     // --gamma VALUE: the law's damping parameter
  };
  std::string ball_preset;  // --ball NAME
  std::optional<double> diameter_m;
  std::optional<double> density_kg_per_m3;
  std::optional<double> mass_kg;
  std::optional<std::string> law;           // unset: walton-braun, or the card's
  std::filesystem::path material;           // --material: a material card
  std::optional<double> gamma;              // --gamma (simulate drop)
  std::optional<double> stiffness_n_per_m;  // unset: the law's (or the card's) value
  std::optional<double> modulus_pa;         // unset: the law's (or the card's) value
  // Sets the law's elastic parameter instead (calibrate::WithContactDuration), for Ball() at the
  // release speed sqrt(2 g DropHeightM()).
  std::optional<double> contact_duration_s;
  std::vector<std::string> parameters;  // NAME=VALUE
  std::optional<double> drop_height_m;
  // Geometry::kAsGiven: --drop-height-m as given, once for every recording or once per recording
  // (calibrate resolves it; one value also sets drop_height_m).
  std::vector<double> drop_heights_m;
  double gravity_mps2 = 9.81;
  std::string integrator = "verlet";
  std::optional<double> time_step_s;
  std::optional<double> steps_per_contact;
  bool fixed_step_grid = false;
  bool drag = false;     // --drag
  bool no_drag = false;  // --no-drag (commands with --material): off whatever the card says
  double drag_coefficient = 0.47;
  double air_density_kg_per_m3 = 1.204;

  // Registers the options on `command` (and the old spellings as hidden aliases); `geometry`
  // decides the help texts and what absence means.
  void Add(CLI::App& command, Features features, Geometry geometry = Geometry::kPaperDefaults);
  void Add(CLI::App& command, Geometry geometry = Geometry::kPaperDefaults) {
    Add(command, Features{}, geometry);
  }
  // Reads --material (InputError naming the card); call once before Law(), Ball(), DropHeightM().
  void ReadMaterial();
  const std::optional<calibrate::MaterialCard>& card() const { return card_; }
  // The ball the command line describes (--ball, --diameter-m with --density-kg-per-m3 or
  // --mass-kg, or the card of --material), or nothing when no ball option was given. ConfigError
  // for a value out of range or an incomplete ball under kAsGiven (a size without a mass or the
  // reverse).
  std::optional<dem::Ball> GivenBall() const;
  // GivenBall() completed with the paper's ball (kPaperDefaults).
  dem::Ball Ball() const;
  // --drop-height-m, else the height the card was fitted at, else the paper's 0.2 m
  // (kPaperDefaults).
  double DropHeightM() const;
  // The law (--law or the card's) with --gamma, --stiffness-n-per-m, --modulus-pa, --param and
  // --contact-duration-s applied and validated (ConfigError otherwise). Unvalidated for
  // --compare-laws, where each law takes the --param values it has.
  dem::ContactLawConfig Law(bool validate = true) const;
  // The law named by --law (or the card's), without parameters applied.
  dem::ContactLawKind LawKind() const;
  dem::Integrator Integrator() const;
  // --drag on, --no-drag off, else the card's setting, else off.
  dem::AirDrag Drag() const;
  // Where DropHeightM() and Drag() come from: "command line", "card" or "default".
  std::string_view DropHeightSource() const;
  std::string_view DragSource() const;
  // The drop set-up every option above describes, in one place so no subcommand can leave one
  // out (sweep once ignored --drag): ball (Ball()), DropHeightM(), gravity, drag, integrator,
  // time step or steps per contact, step grid, and Law(validate_law). Under kAsGiven an absent
  // ball or height comes out as the reference one; calibrate records what was given beside it.
  dem::DropOptions DropSetUp(bool validate_law = true) const;

 private:
  Geometry geometry_ = Geometry::kPaperDefaults;
  std::optional<calibrate::MaterialCard> card_;
};

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_DROP_CLI_OPTIONS_H_
