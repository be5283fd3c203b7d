#include "bouncecal/calibrate/recording_manifest.h"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "bouncecal/error.h"
#include "bouncecal/option_error.h"
#include "csv_line.h"

namespace bouncecal::calibrate {
namespace {

constexpr const char* kColumns = "recording, drop_height_m, drop_height_uncertainty_m, ball";

// 'path', appended rather than "'" + ...: GCC 12 warns falsely (-Wrestrict) on that form.
std::string Quoted(const std::filesystem::path& path) {
  return std::string("'").append(path.string()).append("'");
}

std::optional<double> Length(const std::string& text, const std::string& where,
                             const std::string& column, bool allow_zero) {
  if (text.empty()) return std::nullopt;
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  const bool valid = used == text.size() && std::isfinite(value) &&
                     (allow_zero ? value >= 0 : value > 0) && value < 1e3;
  if (!valid) {
    throw InputError(where + ": " + column + " '" + text + "' is not a " +
                     (allow_zero ? "non-negative" : "positive") +
                     " number of metres below 1000; give it in m, or leave the cell empty");
  }
  return value;
}

void Finish(ManifestEntry& entry, const std::filesystem::path& manifest, const std::string& where) {
  if (entry.recording.empty()) {
    throw InputError(where + ": no recording; give the recording's path");
  }
  if (entry.recording.is_relative()) entry.recording = manifest.parent_path() / entry.recording;
  if (entry.drop_height_uncertainty_m && !entry.drop_height_m) {
    throw InputError(where +
                     ": drop_height_uncertainty_m without drop_height_m; give the height "
                     "or leave the uncertainty out");
  }
}

std::vector<ManifestEntry> ReadCsv(const std::filesystem::path& path, std::istream& stream) {
  std::vector<ManifestEntry> entries;
  std::vector<std::string> header;
  std::string line;
  for (int number = 1; std::getline(stream, line); ++number) {
    line = internal::TrimBlanks(line);
    if (line.empty() || line[0] == '#') continue;
    // Appended, not "'" + ...: GCC 12 warns falsely (-Wrestrict) on that form.
    const std::string where =
        std::string("'").append(path.string()).append("' line ").append(std::to_string(number));
    const auto fields = internal::SplitCsvLine(line);
    if (header.empty()) {
      header = fields;
      for (const auto& column : header) {
        if (column != "recording" && column != "drop_height_m" &&
            column != "drop_height_uncertainty_m" && column != "ball") {
          throw InputError(where + ": unknown column '" + column + "'; the columns are " +
                           kColumns);
        }
      }
      if (std::find(header.begin(), header.end(), "recording") == header.end()) {
        throw InputError(where +
                         ": the header has no recording column; the first line names "
                         "the columns: " +
                         kColumns);
      }
      continue;
    }
    if (fields.size() > header.size()) {
      throw InputError(where + ": " + std::to_string(fields.size()) + " fields under a header of " +
                       std::to_string(header.size()) + "; quote a path that holds a comma");
    }
    ManifestEntry entry;
    for (std::size_t i = 0; i < fields.size(); ++i) {
      const auto& column = header[i];
      if (column == "recording") entry.recording = fields[i];
      if (column == "drop_height_m") entry.drop_height_m = Length(fields[i], where, column, false);
      if (column == "drop_height_uncertainty_m")
        entry.drop_height_uncertainty_m = Length(fields[i], where, column, true);
      if (column == "ball") entry.ball = fields[i];
    }
    Finish(entry, path, where);
    entries.push_back(std::move(entry));
  }
  return entries;
}

std::vector<ManifestEntry> ReadJson(const std::filesystem::path& path, std::istream& stream) {
  nlohmann::json document;
  try {
    document = nlohmann::json::parse(stream);
  } catch (const nlohmann::json::exception& error) {
    throw InputError(Quoted(path) + ": not valid JSON (" + error.what() + ")");
  }
  const nlohmann::json* list = &document;
  if (document.is_object() && document.contains("recordings")) list = &document["recordings"];
  if (!list->is_array()) {
    throw InputError(Quoted(path) + ": expected an array of recordings or {\"recordings\": [...]}");
  }
  std::vector<ManifestEntry> entries;
  for (std::size_t i = 0; i < list->size(); ++i) {
    const auto& item = (*list)[i];
    const std::string where = std::string("'")
                                  .append(path.string())
                                  .append("' recordings[")
                                  .append(std::to_string(i))
                                  .append("]");
    if (!item.is_object()) throw InputError(where + ": expected an object with " + kColumns);
    ManifestEntry entry;
    for (const auto& [key, value] : item.items()) {
      const bool text = value.is_string();
      const bool number = value.is_number();
      if (key == "recording" && text) {
        entry.recording = value.get<std::string>();
      } else if (key == "ball" && text) {
        entry.ball = value.get<std::string>();
      } else if ((key == "drop_height_m" || key == "drop_height_uncertainty_m") &&
                 (number || value.is_null())) {
        const std::string shown = number ? value.dump() : std::string();
        auto length = Length(shown, where, key, key != "drop_height_m");
        (key == "drop_height_m" ? entry.drop_height_m : entry.drop_height_uncertainty_m) = length;
      } else if (key == "recording" || key == "ball" || key == "drop_height_m" ||
                 key == "drop_height_uncertainty_m") {
        throw InputError(where + ": \"" + key + "\" has the wrong type (" + value.type_name() +
                         "); give a " +
                         (key == "recording" || key == "ball" ? "string" : "number"));
      } else {
        throw InputError(where + ": unknown key \"" + key + "\"; the keys are " + kColumns);
      }
    }
    Finish(entry, path, where);
    entries.push_back(std::move(entry));
  }
  return entries;
}

}  // namespace

std::vector<ManifestEntry> ReadRecordingManifest(const std::filesystem::path& path) {
  std::ifstream stream(path);
  if (!stream) {
    throw InputError("manifest '" + path.string() + "' cannot be read; check the path");
  }
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  auto entries = extension == ".json" ? ReadJson(path, stream) : ReadCsv(path, stream);
  if (entries.empty()) {
    throw InputError("manifest '" + path.string() +
                     "' lists no recording; give one line per recording under the header " +
                     kColumns);
  }
  return entries;
}

void ValidateDropHeights(const std::vector<double>& drop_heights_m,
                         const std::vector<double>& drop_height_uncertainties_m) {
  for (double height : drop_heights_m) {
    if (!(height > 0 && height < 1e3)) {
      throw OptionError({"drop_height_m"},
                        fmt::format("drop_height_m must be in (0, 1000) m, got {}", height));
    }
  }
  for (double sigma : drop_height_uncertainties_m) {
    if (!(sigma >= 0 && std::isfinite(sigma))) {
      throw OptionError({"drop_height_uncertainty_m"},
                        fmt::format("drop_height_uncertainty_m must be >= 0 m, got {}", sigma));
    }
  }
}

std::vector<ManifestEntry> PlanRecordings(const std::vector<std::filesystem::path>& recordings,
                                          const std::vector<double>& drop_heights_m,
                                          const std::vector<double>& drop_height_uncertainties_m,
                                          const std::filesystem::path& manifest) {
  if (!manifest.empty()) {
    if (!recordings.empty() || !drop_heights_m.empty() || !drop_height_uncertainties_m.empty()) {
      throw OptionError({"manifest", "drop_height_m", "drop_height_uncertainty_m"},
                        "`manifest` lists the recordings and their heights; give the "
                        "recordings, drop_height_m and drop_height_uncertainty_m there or without "
                        "`manifest`, not both");
    }
    return ReadRecordingManifest(manifest);
  }
  const auto per_recording = [&](const std::vector<double>& values, const char* field) {
    if (values.size() > 1 && values.size() != recordings.size()) {
      throw OptionError({field, "manifest"},
                        std::string(field) + " is given " + std::to_string(values.size()) +
                            " times for " + std::to_string(recordings.size()) +
                            " recordings; give it once for all, or once per recording "
                            "in the recordings' order (or use `manifest`)");
    }
  };
  per_recording(drop_heights_m, "drop_height_m");
  per_recording(drop_height_uncertainties_m, "drop_height_uncertainty_m");
  if (!drop_height_uncertainties_m.empty() && drop_heights_m.empty()) {
    throw OptionError({"drop_height_uncertainty_m", "drop_height_m"},
                      "drop_height_uncertainty_m needs drop_height_m (without a height nothing "
                      "depends on it)");
  }
  std::vector<ManifestEntry> entries;
  for (std::size_t i = 0; i < recordings.size(); ++i) {
    ManifestEntry entry;
    entry.recording = recordings[i];
    if (!drop_heights_m.empty()) {
      entry.drop_height_m = drop_heights_m[drop_heights_m.size() > 1 ? i : 0];
    }
    if (!drop_height_uncertainties_m.empty()) {
      entry.drop_height_uncertainty_m =
          drop_height_uncertainties_m[drop_height_uncertainties_m.size() > 1 ? i : 0];
    }
    entries.push_back(std::move(entry));
  }
  return entries;
}

}  // namespace bouncecal::calibrate
