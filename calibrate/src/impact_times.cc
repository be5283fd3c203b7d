#include "bouncecal/calibrate/impact_times.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>

#include "bouncecal/error.h"
#include "bouncecal/option_error.h"
#include "csv_line.h"

namespace bouncecal::calibrate {
namespace {

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
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

// Column positions: by header name when the file has a header, else onset_s, uncertainty,
// sequence in that order. A "kind" column (the synthesiser's truth files) keeps only
// ball_impact rows; a "drop" column serves as the sequence number (-1 rows are not drops).
// `bouncecal analyze --csv` also names each row's file and channel, whose sequences are numbered
// from 0 in each, and leaves the sequence blank for an impact in none.
struct CsvColumns {
  int onset = 0;
  int uncertainty = 1;
  int sequence = 2;
  int kind = -1;
  int flight_uncertainty = -1;  // analyze --csv's incoming_flight_uncertainty_s
  int file = -1;
  int channel = -1;
  bool named = false;  // from a header
};

std::optional<CsvColumns> HeaderColumns(const std::vector<std::string>& fields) {
  CsvColumns columns{-1, -1, -1, -1, -1, -1, -1, true};
  for (size_t i = 0; i < fields.size(); ++i) {
    const std::string name = Lower(fields[i]);
    const int index = static_cast<int>(i);
    if (name == "onset_s") columns.onset = index;
    if (name == "onset_uncertainty_s" || name == "uncertainty_s") columns.uncertainty = index;
    if (name == "sequence" || name == "drop") columns.sequence = index;
    if (name == "kind") columns.kind = index;
    if (name == "incoming_flight_uncertainty_s") columns.flight_uncertainty = index;
    if (name == "file") columns.file = index;
    if (name == "channel") columns.channel = index;
  }
  if (columns.onset < 0) return std::nullopt;
  return columns;
}

std::string Field(const std::vector<std::string>& fields, int index) {
  return index >= 0 && index < static_cast<int>(fields.size()) ? fields[static_cast<size_t>(index)]
                                                               : std::string();
}

// The rows of one sequence: of one recording (file and channel, where named) and number.
struct CsvSequence {
  std::string file, channel;
  long long number = 0;
  std::vector<TimedImpact> impacts;
};

std::vector<MeasuredSequence> ReadCsv(const std::filesystem::path& path, std::istream& stream,
                                      const ImpactTimesOptions& options) {
  std::vector<CsvSequence> by_sequence;  // in the order the file first names each
  std::string line;
  int line_number = 0;
  bool seen_data = false;
  CsvColumns columns;
  while (std::getline(stream, line)) {
    ++line_number;
    line = internal::TrimBlanks(line);
    if (line.empty() || line[0] == '#') continue;
    const auto fields = internal::SplitCsvLine(line);
    double onset = 0;
    if (!seen_data && !fields[0].empty() &&
        std::isalpha(static_cast<unsigned char>(fields[0][0]))) {
      const auto header = HeaderColumns(fields);
      if (!header) {
        throw InputError(Where(path, line_number) + ": the header has no onset_s column");
      }
      columns = *header;
      continue;
    }
    if (columns.kind >= 0 && Field(fields, columns.kind) != "ball_impact") continue;
    if (!ParseDouble(Field(fields, columns.onset), onset)) {
      throw InputError(Where(path, line_number) + ": '" + Field(fields, columns.onset) +
                       "' is not a finite onset time in seconds; expected onset_s[,uncertainty_s"
                       "[,sequence]]");
    }
    seen_data = true;
    double sigma = options.default_uncertainty_s;
    const std::string sigma_text = Field(fields, columns.uncertainty);
    if (!sigma_text.empty() && (!ParseDouble(sigma_text, sigma) || sigma < 0)) {
      throw InputError(Where(path, line_number) + ": onset uncertainty '" + sigma_text +
                       "' must be a non-negative number of seconds");
    }
    double sequence = 0;
    const std::string sequence_text = Field(fields, columns.sequence);
    // A blank sequence under a header that names the column is an impact in no sequence (analyze
    // --csv): taken into sequence 0, a stray sound of clipping.wav (detector suite) turned its
    // eta-bar 0.5505 +- 0.0003 into -0.04 +- 0.29.
    if (sequence_text.empty() && columns.named && columns.sequence >= 0) continue;
    if (!sequence_text.empty() &&
        (!ParseDouble(sequence_text, sequence) || sequence != std::floor(sequence))) {
      throw InputError(Where(path, line_number) + ": sequence '" + sequence_text +
                       "' must be an integer");
    }
    double flight_sigma = 0;
    const std::string flight_text = Field(fields, columns.flight_uncertainty);
    if (!flight_text.empty() && (!ParseDouble(flight_text, flight_sigma) || flight_sigma < 0)) {
      throw InputError(Where(path, line_number) + ": incoming flight uncertainty '" + flight_text +
                       "' must be a non-negative number of seconds");
    }
    if (sequence < 0) continue;  // the truth files' -1: not part of a drop
    const std::string file = Field(fields, columns.file), channel = Field(fields, columns.channel);
    const auto number = static_cast<long long>(sequence);
    auto group = std::find_if(by_sequence.begin(), by_sequence.end(), [&](const CsvSequence& s) {
      return s.file == file && s.channel == channel && s.number == number;
    });
    if (group == by_sequence.end()) {
      by_sequence.push_back({file, channel, number, {}});
      group = std::prev(by_sequence.end());
    }
    group->impacts.push_back({onset, sigma, flight_sigma});
  }
  std::vector<MeasuredSequence> sequences;
  for (auto& group : by_sequence) {
    auto& impacts = group.impacts;
    std::sort(impacts.begin(), impacts.end(),
              [](const TimedImpact& a, const TimedImpact& b) { return a.onset_s < b.onset_s; });
    // No flight of the sequence ends at its first impact.
    if (!impacts.empty()) impacts.front().incoming_flight_uncertainty_s = 0;
    // A recording's rows are named as its analysis is (drop.wav#1 for its first sequence).
    // Appended, not "#" + to_string(...): GCC 12 warns falsely (-Wrestrict) on that insert.
    std::string name = path.filename().string(), suffix;
    if (!group.file.empty()) {
      name = std::filesystem::path(group.file).filename().string();
      suffix.append("#").append(std::to_string(group.number + 1));
    } else if (by_sequence.size() > 1) {
      suffix.append("#").append(std::to_string(group.number));
    }
    sequences.push_back({name + suffix, path, std::move(impacts), {}, {}, 0.0, std::nullopt, 0.0});
  }
  return sequences;
}

constexpr std::string_view kAnalysisFormat = "bouncecal-analysis/1";

// Collects the per-recording objects of analyze output written before it had a format field: one
// object, or an array of them followed by {"summary": ...}.
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
                     "); expected the JSON that analyze writes (" + std::string(kAnalysisFormat) +
                     ")");
  }
  std::vector<const nlohmann::json*> objects;
  if (document.is_object() && document.contains("format")) {
    const std::string format =
        document["format"].is_string() ? document["format"].get<std::string>() : "";
    if (format != kAnalysisFormat) {
      const bool newer = format.rfind("bouncecal-analysis/", 0) == 0;
      throw InputError("'" + path.string() + "' has \"format\": \"" + format + "\", " +
                       (newer ? "which this bouncecal does not read (it reads " +
                                    std::string(kAnalysisFormat) +
                                    "); analyze the recording again with this version"
                              : "not analyze output; expected the JSON that analyze writes (" +
                                    std::string(kAnalysisFormat) + ")"));
    }
    if (!document.contains("recordings") || !document["recordings"].is_array()) {
      throw InputError("'" + path.string() + "' is " + std::string(kAnalysisFormat) +
                       " without a \"recordings\" array; write it again with analyze");
    }
    for (const auto& recording : document["recordings"]) {
      if (recording.is_object() && recording.contains("sequences")) objects.push_back(&recording);
    }
  } else {
    CollectAnalyzeObjects(document, objects);
  }
  if (objects.empty()) {
    throw InputError("'" + path.string() +
                     "' has no \"sequences\" key; expected the JSON that analyze writes (" +
                     std::string(kAnalysisFormat) + ")");
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
        MeasuredSequence measured{
            source + "#" + std::to_string(number), path, {}, {}, {}, 0.0, std::nullopt, 0.0};
        const auto& onsets = sequence.at("onsets_s");
        // Older files have no incoming-flight uncertainties: none was stated then.
        const nlohmann::json* flight_sigmas = nullptr;
        if (sequence.contains("incoming_flight_uncertainty_s") &&
            sequence["incoming_flight_uncertainty_s"].size() == onsets.size()) {
          flight_sigmas = &sequence["incoming_flight_uncertainty_s"];
        }
        for (std::size_t j = 0; j < onsets.size(); ++j) {
          const double onset = onsets[j].get<double>();
          TimedImpact timed{onset, options.default_uncertainty_s};
          // The analyzer copies onsets verbatim, so equality to a nanosecond finds the impact.
          for (const auto& impact : known) {
            if (std::abs(impact.onset_s - onset) < 1e-9) timed.uncertainty_s = impact.uncertainty_s;
          }
          if (flight_sigmas && j > 0) {
            const double sigma = (*flight_sigmas)[j].get<double>();
            if (!(sigma >= 0) || !std::isfinite(sigma)) {
              throw InputError("'" + path.string() + "' sequence " + std::to_string(number) +
                               ": incoming_flight_uncertainty_s must be a non-negative number "
                               "of seconds");
            }
            timed.incoming_flight_uncertainty_s = sigma;
          }
          measured.impacts.push_back(timed);
        }
        sequences.push_back(std::move(measured));
      }
    }
  } catch (const nlohmann::json::exception& error) {
    throw InputError("'" + path.string() +
                     "' does not have the shape of the JSON that analyze writes (" + error.what() +
                     ")");
  }
  return sequences;
}

}  // namespace

void ImpactTimesOptions::Validate() const {
  if (default_uncertainty_s > 0 && std::isfinite(default_uncertainty_s)) return;
  std::ostringstream value;
  value << default_uncertainty_s;
  const std::string given =
      std::isfinite(default_uncertainty_s) ? "got " + value.str() : "got a non-finite value";
  throw OptionError(
      {"onset_uncertainty_s"},
      "onset_uncertainty_s must be a positive number of seconds (e.g. 1e-5), " + given);
}

bool IsImpactTimesFile(const std::filesystem::path& path) {
  const auto extension = Lower(path.extension().string());
  return extension == ".csv" || extension == ".json";
}

std::vector<MeasuredSequence> ReadImpactTimes(const std::filesystem::path& path,
                                              const ImpactTimesOptions& options) {
  if (!IsImpactTimesFile(path)) {
    throw InputError("'" + path.string() + "' is neither .csv nor .json; give an impact-time CSV " +
                     "or the JSON that analyze writes (" + std::string(kAnalysisFormat) + ")");
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
