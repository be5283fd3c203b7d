#include "bouncecal/calibrate/impact_times.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

std::string Trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
}

std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream stream(line);
  std::string field;
  while (std::getline(stream, field, ',')) fields.push_back(Trim(field));
  return fields;
}

bool ParseDouble(const std::string& text, double& value) {
  try {
    size_t used = 0;
    value = std::stod(text, &used);
    return used == text.size() && std::isfinite(value);
  } catch (const std::exception&) {
    return false;
  }
}

std::string Where(const std::filesystem::path& path, int line) {
  return "'" + path.string() + "' line " + std::to_string(line);
}

std::vector<MeasuredSequence> ReadCsv(const std::filesystem::path& path, std::istream& stream,
                                      const ImpactTimesOptions& options) {
  std::map<long long, std::vector<TimedImpact>> by_sequence;
  std::string line;
  int line_number = 0;
  bool seen_data = false;
  while (std::getline(stream, line)) {
    ++line_number;
    line = Trim(line);
    if (line.empty() || line[0] == '#') continue;
    const auto fields = SplitCsv(line);
    double onset = 0;
    if (!ParseDouble(fields[0], onset)) {
      if (!seen_data && std::isalpha(static_cast<unsigned char>(fields[0][0]))) continue;  // header
      throw InputError(Where(path, line_number) + ": '" + fields[0] +
                       "' is not a finite onset time in seconds; expected onset_s[,uncertainty_s"
                       "[,sequence]]");
    }
    seen_data = true;
    double sigma = options.default_uncertainty_s;
    if (fields.size() > 1 && !fields[1].empty() && (!ParseDouble(fields[1], sigma) || sigma < 0)) {
      throw InputError(Where(path, line_number) + ": onset uncertainty '" + fields[1] +
                       "' must be a non-negative number of seconds");
    }
    double sequence = 0;
    if (fields.size() > 2 && !fields[2].empty() &&
        (!ParseDouble(fields[2], sequence) || sequence != std::floor(sequence))) {
      throw InputError(Where(path, line_number) + ": sequence '" + fields[2] +
                       "' must be an integer");
    }
    by_sequence[static_cast<long long>(sequence)].push_back({onset, sigma});
  }
  std::vector<MeasuredSequence> sequences;
  for (auto& [number, impacts] : by_sequence) {
    std::sort(impacts.begin(), impacts.end(),
              [](const TimedImpact& a, const TimedImpact& b) { return a.onset_s < b.onset_s; });
    sequences.push_back({path.filename().string(), path, std::move(impacts)});
  }
  return sequences;
}

// Collects the analyze result objects: one object, an array of them, or an object that wraps
// them in an array (a multi-file summary).
void CollectAnalyzeObjects(const nlohmann::json& node, std::vector<const nlohmann::json*>& found) {
  if (node.is_array()) {
    for (const auto& item : node) CollectAnalyzeObjects(item, found);
  } else if (node.is_object()) {
    if (node.contains("sequences")) {
      found.push_back(&node);
      return;
    }
    for (const auto& [key, value] : node.items()) {
      if (value.is_array()) CollectAnalyzeObjects(value, found);
    }
  }
}

std::vector<MeasuredSequence> ReadJson(const std::filesystem::path& path, std::istream& stream,
                                       const ImpactTimesOptions& options) {
  nlohmann::json document;
  try {
    document = nlohmann::json::parse(stream);
  } catch (const nlohmann::json::exception& error) {
    throw InputError("'" + path.string() + "' is not valid JSON (" + error.what() +
                     "); expected the output of bouncecal analyze --json");
  }
  std::vector<const nlohmann::json*> objects;
  CollectAnalyzeObjects(document, objects);
  if (objects.empty()) {
    throw InputError("'" + path.string() +
                     "' has no \"sequences\" key; expected the output of bouncecal analyze --json");
  }
  std::vector<MeasuredSequence> sequences;
  try {
    for (const auto* object : objects) {
      std::string source = path.filename().string();
      if (object->contains("file") && (*object)["file"].is_string()) {
        source = std::filesystem::path((*object)["file"].get<std::string>()).filename().string();
      }
      std::vector<TimedImpact> known;
      if (object->contains("impacts")) {
        for (const auto& impact : (*object)["impacts"]) {
          TimedImpact timed{impact.at("onset_s").get<double>(), options.default_uncertainty_s};
          if (impact.contains("onset_uncertainty_s") && impact["onset_uncertainty_s"].is_number())
            timed.uncertainty_s = impact["onset_uncertainty_s"].get<double>();
          known.push_back(timed);
        }
      }
      int number = 0;
      for (const auto& sequence : (*object)["sequences"]) {
        ++number;
        MeasuredSequence measured{source + "#" + std::to_string(number), path, {}};
        for (const auto& onset_json : sequence.at("onsets_s")) {
          const double onset = onset_json.get<double>();
          TimedImpact timed{onset, options.default_uncertainty_s};
          // The analyzer copies onsets verbatim, so equality to a nanosecond finds the impact.
          for (const auto& impact : known) {
            if (std::abs(impact.onset_s - onset) < 1e-9) timed.uncertainty_s = impact.uncertainty_s;
          }
          measured.impacts.push_back(timed);
        }
        sequences.push_back(std::move(measured));
      }
    }
  } catch (const nlohmann::json::exception& error) {
    throw InputError("'" + path.string() + "' does not have the shape bouncecal analyze --json " +
                     "writes (" + error.what() + ")");
  }
  return sequences;
}

}  // namespace

bool IsImpactTimesFile(const std::filesystem::path& path) {
  const auto extension = Lower(path.extension().string());
  return extension == ".csv" || extension == ".json";
}

std::vector<MeasuredSequence> ReadImpactTimes(const std::filesystem::path& path,
                                              const ImpactTimesOptions& options) {
  if (!IsImpactTimesFile(path)) {
    throw InputError("'" + path.string() + "' is neither .csv nor .json; give an impact-time CSV " +
                     "or the JSON of bouncecal analyze --json");
  }
  std::ifstream stream(path);
  if (!stream) {
    throw InputError("cannot open '" + path.string() + "'; check that it exists and is readable");
  }
  auto sequences = Lower(path.extension().string()) == ".csv" ? ReadCsv(path, stream, options)
                                                              : ReadJson(path, stream, options);
  std::erase_if(sequences, [&](const MeasuredSequence& sequence) {
    return static_cast<int>(sequence.impacts.size()) < options.min_impacts;
  });
  if (sequences.empty()) {
    throw InputError("'" + path.string() + "' holds no bounce sequence with at least " +
                     std::to_string(options.min_impacts) + " impacts; nothing to calibrate");
  }
  for (const auto& sequence : sequences) {
    for (size_t i = 1; i < sequence.impacts.size(); ++i) {
      if (!(sequence.impacts[i].onset_s > sequence.impacts[i - 1].onset_s)) {
        throw InputError("'" + path.string() + "': two impacts of " + sequence.source +
                         " share the onset " + std::to_string(sequence.impacts[i].onset_s) +
                         " s; remove the duplicate");
      }
    }
  }
  return sequences;
}

}  // namespace bouncecal::calibrate
