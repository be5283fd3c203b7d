#ifndef BOUNCECAL_EXPORT_EXPORT_MATERIAL_H_
#define BOUNCECAL_EXPORT_EXPORT_MATERIAL_H_

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "bouncecal/dem/contact_law.h"

namespace bouncecal::calibrate {

// What an export needs from a material card ("format": "bouncecal-material/1"): the contact law,
// the ball it was calibrated with, and the card's implied restitution when it states one.
//
// This reads only the "format", "contact_law", "ball", "implied" and "fit.drop_height_m" keys, so
// it accepts any card the calibration writes; it stands in for calibrate's ReadMaterialCard until
// both land on main, and can then be replaced by a conversion from MaterialCard.
struct ExportMaterial {
  dem::ContactLawConfig law;
  double diameter_m = 0.01;
  double mass_kg = 0;
  std::optional<double> implied_restitution;
  // The drop height the card was fitted at ("fit": {"drop_height_m"}), when it states one: the
  // natural height for the check deck.
  std::optional<double> drop_height_m;
  std::string source = "(in memory)";  // the card's path, for deck headers
};

// `context` (the card's path) prefixes every error. Throws InputError for a wrong format, a
// missing/malformed "contact_law" or "ball" key (naming the key) or a law parameter out of its
// range (dem::ContactLawConfigFromJson): every problem of the card is a bad input file.
ExportMaterial ExportMaterialFromJson(const nlohmann::json& card, std::string_view context);

// Throws InputError when the file is missing or is not JSON, then as ExportMaterialFromJson.
ExportMaterial ReadExportMaterial(const std::filesystem::path& card_path);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_EXPORT_EXPORT_MATERIAL_H_
