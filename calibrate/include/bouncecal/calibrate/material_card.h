#ifndef BOUNCECAL_CALIBRATE_MATERIAL_CARD_H_
#define BOUNCECAL_CALIBRATE_MATERIAL_CARD_H_

#include <ctime>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bouncecal/calibrate/fit.h"
#include "bouncecal/dem/contact_law.h"
#include "bouncecal/dem/drop.h"

namespace bouncecal::calibrate {

inline constexpr std::string_view kMaterialCardFormat = "bouncecal-material/1";

// A recording a card was fitted to, identified by name and content (FileContentHash).
struct RecordingReference {
  std::string file;
  std::string content_hash;  // "fnv1a64:<16 hex digits>"
  // The release height its drops were fitted with; unset when unknown.
  std::optional<double> drop_height_m;
  // The energy losses its eta-bar averaged under mean-energy-loss (the fewest of its sequences):
  // fit.first_n, or fewer where it gave fewer (FitOptions::first_n_given); unset under the other
  // objectives and in older cards.
  std::optional<int> first_n;
};

// What the card's confidence intervals include (uncertainty.h), and how many distinct
// measurements they rest on.
struct UncertaintyRecord {
  std::string model;                    // one sentence
  int recordings = 0;                   // distinct recording files (by content hash)
  int sequences = 0;                    // distinct bounce sequences fitted
  int duplicates = 0;                   // sequences dropped as repeats of another
  int impacts_used = 0;                 // impacts whose energy loss the fit used
  double per_impact_scatter = 0;        // sd of eta_k beyond timing noise
  double between_recording_sd = 0;      // sd of a recording's eta beyond its impacts' scatter
  std::optional<double> effective_dof;  // of the first parameter's interval; null: known variances
};

// How the card's parameters were obtained.
struct FitRecord {
  std::string objective;
  int first_n = 3;
  double residual = 0;  // chi-square
  int data_points = 0;
  int evaluations = 0;
  std::string stop_reason;
  // The drop height given; unset: unknown, and the drops started from the first measured bounce
  // apex ("release": "first-bounce-apex" in the JSON, else "drop-height").
  std::optional<double> drop_height_m;
  // The recordings had heights of their own (recordings[].drop_height_m), not one for all:
  // "release": "per-recording", drop_height_m null.
  bool heights_per_recording = false;
  std::string integrator;
  std::optional<double> time_step_s;
  // Unset: the drop engine's default (dem::DropOptions::steps_per_contact) at the time of the fit.
  std::optional<double> steps_per_contact;
  bool fixed_step_grid = false;
  bool drag = false;
  std::map<std::string, std::pair<double, double>, std::less<>> confidence_interval;
  double confidence_level = 0.95;
  std::string uncertainty_method;  // = uncertainty.model, kept for older readers
  UncertaintyRecord uncertainty;
  std::optional<double> energy_loss_mean_measured;  // eta-bar, first N impacts
  std::optional<double> gamma_n_formula;            // eta-bar / (2 - eta-bar), walton-braun
};

// The calibrated material (JSON, "format": "bouncecal-material/1"; dem_interfaces.md):
// {"format", "contact_law": {"law", "parameters"}, "parameter_units": {name: unit},
//  "ball": {"diameter_m", "density_kg_per_m3" (mass / volume), "mass_kg"[, "preset"]}, "implied":
//  {"restitution", "energy_loss", "contact_duration_s", "contact_speed_mps"}, "fit": {...,
//  "drop_height_m" (null: unknown), "release", "uncertainty": {...}}, "recordings": [{"file",
//  "content_hash"}] (distinct files), "tool_version", "created_utc"}. Scenes that need only the law
//  read "contact_law" with
// dem::ContactLawConfigFromJson. Keys added since the first cards ("preset", "release",
// "uncertainty", "contact_duration_s", "contact_speed_mps") are optional when read.
struct MaterialCard {
  dem::ContactLawConfig law;
  dem::Ball ball;
  std::string ball_preset;         // the preset the ball came from, or empty
  double implied_restitution = 0;  // first impact from the drop height
  double implied_energy_loss = 0;
  // The law's closed-form contact duration for the card's ball at implied_contact_speed_mps
  // (FitSummary::contact_duration_s): what its stiffness means, and what sets the DEM step of
  // scenes built on the card. Unset where the law has no closed form (or an older card).
  std::optional<double> implied_contact_duration_s;
  std::optional<double> implied_contact_speed_mps;
  FitRecord fit;
  std::vector<RecordingReference> recordings;
  std::string tool_version;
  std::string created_utc;  // ISO 8601, e.g. 2026-11-21T18:20:00Z
};

// The card of a fit; hashes each recording file (InputError if one cannot be read; a file given
// twice is listed once) and stamps the tool version and `created_at` (seconds since 1970-01-01
// UTC). The caller chooses the time so a build can pin it (SOURCE_DATE_EPOCH) and the card
// becomes reproducible. Throws ConfigError when the ball was not given: a card states the ball its
// damping belongs to (exported damping coefficients scale with its mass).
MaterialCard MakeMaterialCard(const FitSummary& summary, const FitOptions& options,
                              const std::vector<std::filesystem::path>& recordings,
                              std::time_t created_at);

// The ConfigError MakeMaterialCard would throw for these options, so a command can refuse before
// a long fit rather than after it.
void CheckCardOptions(const FitOptions& options);

nlohmann::json ToJson(const MaterialCard& card);
// Throws InputError naming `context` and the key for a wrong format or a malformed field,
// including the law's (checked by dem::ContactLawConfigFromJson).
MaterialCard MaterialCardFromJson(const nlohmann::json& object, std::string_view context);

// Written atomically (AtomicFile): OutputError when the file cannot be written.
void WriteMaterialCard(const std::filesystem::path& path, const MaterialCard& card);
// InputError when the file is missing, not JSON or not a material card.
MaterialCard ReadMaterialCard(const std::filesystem::path& path);

// `seconds_since_epoch` as ISO 8601 UTC with a Z suffix, e.g. 2026-11-21T18:20:00Z.
std::string UtcTimestamp(std::time_t seconds_since_epoch);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_MATERIAL_CARD_H_
