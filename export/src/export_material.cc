#include "bouncecal/export/export_material.h"

#include <fmt/core.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include "bouncecal/calibrate/material_card.h"
#include "bouncecal/dem/contact_law_json.h"
#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

constexpr std::string_view kFormat = "bouncecal-material/1";

// A positive finite number at object[key], or nothing when the key is absent or null.
std::optional<double> OptionalPositive(const nlohmann::json& object, std::string_view key,
                                       std::string_view where, std::string_view unit) {
  const auto it = object.find(key);
  if (it == object.end() || it->is_null()) return std::nullopt;
  if (!it->is_number() || !std::isfinite(it->get<double>()) || !(it->get<double>() > 0)) {
    throw InputError(fmt::format("{}: \"{}\" must be a positive number of {}, got {}", where, key,
                                 unit, it->dump()));
  }
  return it->get<double>();
}

}  // namespace

ExportMaterial ExportMaterialFromJson(const nlohmann::json& card, std::string_view context) {
  if (!card.is_object()) {
    throw InputError(
        fmt::format("{}: a material card is a JSON object; this is {}", context, card.type_name()));
  }
  const auto format = card.find("format");
  if (format == card.end() || !format->is_string() || format->get<std::string>() != kFormat) {
    throw InputError(fmt::format(
        "{}: key \"format\" must be \"{}\", got {}; is this a bouncecal material card?", context,
        kFormat, format == card.end() ? std::string("nothing") : format->dump()));
  }
  // The calibration's own reader checks every key and type (unknown keys, non-finite numbers),
  // so a card that export accepts is one calibrate would accept too.
  MaterialCardFromJson(card, context);
  ExportMaterial material;
  material.source = std::string(context);

  const auto law = card.find("contact_law");
  if (law == card.end()) {
    throw InputError(fmt::format(
        "{}: missing key \"contact_law\" (e.g. {{\"law\": \"walton-braun\", \"parameters\": "
        "{{...}}}})",
        context));
  }
  material.law = dem::ContactLawConfigFromJson(*law, fmt::format("{}: contact_law", context));

  const auto ball = card.find("ball");
  if (ball == card.end() || !ball->is_object()) {
    throw InputError(fmt::format(
        "{}: missing or non-object key \"ball\" (needs diameter_m and density_kg_per_m3 or "
        "mass_kg)",
        context));
  }
  const std::string where = fmt::format("{}: ball", context);
  const auto diameter = OptionalPositive(*ball, "diameter_m", where, "metres");
  if (!diameter) throw InputError(fmt::format("{}: missing key \"diameter_m\"", where));
  material.diameter_m = *diameter;
  const auto density = OptionalPositive(*ball, "density_kg_per_m3", where, "kg/m^3");
  const auto mass = OptionalPositive(*ball, "mass_kg", where, "kilograms");
  if (mass) {
    material.mass_kg = *mass;  // an explicit mass overrides the density (dem::Ball convention)
  } else if (density) {
    material.mass_kg = *density * std::numbers::pi * std::pow(*diameter, 3) / 6;
  } else {
    throw InputError(
        fmt::format("{}: needs \"mass_kg\" or \"density_kg_per_m3\" to know the mass", where));
  }

  const auto implied = card.find("implied");
  if (implied != card.end() && implied->is_object()) {
    const auto e = implied->find("restitution");
    if (e != implied->end() && !e->is_null()) {
      if (!e->is_number() || !(e->get<double>() >= 0) || !(e->get<double>() <= 1)) {
        throw InputError(
            fmt::format("{}: implied: \"restitution\" must be a number in [0, 1], "
                        "got {}",
                        context, e->dump()));
      }
      material.implied_restitution = e->get<double>();
    }
  }
  const auto fit = card.find("fit");
  if (fit != card.end() && fit->is_object()) {
    material.drop_height_m =
        OptionalPositive(*fit, "drop_height_m", fmt::format("{}: fit", context), "metres");
  }
  return material;
}

ExportMaterial ReadExportMaterial(const std::filesystem::path& card_path) {
  std::ifstream file(card_path, std::ios::binary);
  if (!file) {
    throw InputError(card_path.string() +
                     ": cannot open the material card; check the path (bouncecal calibrate "
                     "writes one)");
  }
  nlohmann::json card;
  try {
    card = nlohmann::json::parse(file);
  } catch (const nlohmann::json::parse_error& error) {
    throw InputError(fmt::format("{}: not valid JSON (byte {}); is this a material card?",
                                 card_path.string(), error.byte));
  } catch (const nlohmann::json::exception& error) {
    // A number too large for a double (1e999) is out_of_range, not a parse_error.
    throw InputError(
        fmt::format("{}: not a usable JSON material card ({})", card_path.string(), error.what()));
  }
  return ExportMaterialFromJson(card, card_path.string());
}

}  // namespace bouncecal::calibrate
