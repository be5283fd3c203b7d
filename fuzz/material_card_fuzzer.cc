// Fuzzes the material-card readers (calibrate's MaterialCardFromJson, export's
// ExportMaterialFromJson) and through them the contact-law JSON parser: any text must become a
// card or a one-line InputError/ConfigError; any other exception or a crash is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>

#include "bouncecal/calibrate/material_card.h"
#include "bouncecal/error.h"
#include "bouncecal/export/export_material.h"

namespace {

void CheckOneLine(const bouncecal::Error& error) {
  if (std::string(error.what()).find('\n') != std::string::npos) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto card = nlohmann::json::parse(data, data + size, nullptr, /*allow_exceptions=*/false);
  if (card.is_discarded()) return 0;
  try {
    bouncecal::calibrate::MaterialCardFromJson(card, "fuzz.json");
  } catch (const bouncecal::InputError& error) {
    CheckOneLine(error);
  } catch (const bouncecal::ConfigError& error) {
    CheckOneLine(error);
  }
  try {
    bouncecal::calibrate::ExportMaterialFromJson(card, "fuzz.json");
  } catch (const bouncecal::InputError& error) {
    CheckOneLine(error);
  } catch (const bouncecal::ConfigError& error) {
    CheckOneLine(error);
  }
  return 0;
}
