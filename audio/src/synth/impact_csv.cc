#include "bouncecal/audio/impact_csv.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "bouncecal/error.h"

namespace bouncecal::audio {
namespace {

std::vector<std::string_view> SplitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    std::string_view field =
        line.substr(start, comma == std::string_view::npos ? comma : comma - start);
    while (!field.empty() && (field.front() == ' ' || field.front() == '\t'))
      field.remove_prefix(1);
    while (!field.empty() &&
           (field.back() == ' ' || field.back() == '\t' || field.back() == '\r')) {
      field.remove_suffix(1);
    }
    fields.push_back(field);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return fields;
}

bool ParseNumber(std::string_view field, double& value) {
  const char* end = field.data() + field.size();
  const auto result = std::from_chars(field.data(), end, value);
  return result.ec == std::errc() && result.ptr == end && std::isfinite(value);
}

}  // namespace

std::vector<ImpactSpec> ParseImpactCsv(std::string_view text, std::string_view source_name) {
  std::vector<ImpactSpec> impacts;
  const std::string source(source_name);
  int kind_column = -1;
  int drop_column = -1;
  bool first_content_line = true;
  int line_number = 0;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t newline = text.find('\n', start);
    const std::string_view line = text.substr(
        start, newline == std::string_view::npos ? text.size() - start : newline - start);
    start = newline == std::string_view::npos ? text.size() + 1 : newline + 1;
    ++line_number;
    const std::vector<std::string_view> fields = SplitFields(line);
    if ((fields.size() == 1 && fields[0].empty()) || (!fields[0].empty() && fields[0][0] == '#')) {
      continue;
    }
    const std::string where = source + ":" + std::to_string(line_number) + ": ";
    double onset_s = 0.0;
    if (first_content_line && !ParseNumber(fields[0], onset_s)) {
      // A header: remember where the kind column is, if any.
      for (size_t i = 0; i < fields.size(); ++i) {
        if (fields[i] == "kind") kind_column = static_cast<int>(i);
        if (fields[i] == "drop") drop_column = static_cast<int>(i);
      }
      first_content_line = false;
      continue;
    }
    first_content_line = false;
    if (fields.size() < 2) {
      throw InputError(where + "expected 'onset_s,impact_speed_mps'; give both columns");
    }
    if (kind_column >= 0 && static_cast<size_t>(kind_column) < fields.size() &&
        fields[static_cast<size_t>(kind_column)] != ToString(SoundEventKind::kBallImpact)) {
      continue;
    }
    double speed_mps = 0.0;
    if (!ParseNumber(fields[0], onset_s) || !ParseNumber(fields[1], speed_mps)) {
      throw InputError(where + "'" + std::string(line) +
                       "' is not two finite numbers; write onset_s,impact_speed_mps");
    }
    if (onset_s < 0.0 || speed_mps <= 0.0) {
      throw InputError(where + "onset_s must be >= 0 and impact_speed_mps > 0; fix the values");
    }
    double drop = 0.0;
    if (drop_column >= 0 && static_cast<size_t>(drop_column) < fields.size() &&
        (!ParseNumber(fields[static_cast<size_t>(drop_column)], drop) || drop < 0.0 ||
         drop != std::floor(drop) || drop > 1e6)) {
      throw InputError(where + "the drop column must hold a whole number >= 0; fix the value");
    }
    impacts.push_back({onset_s, speed_mps, static_cast<int>(drop)});
  }
  if (impacts.empty()) {
    throw InputError(source + ": holds no impacts; give lines 'onset_s,impact_speed_mps'");
  }
  return impacts;
}

std::vector<ImpactSpec> ReadImpactCsv(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot open the impact CSV; check the path");
  std::ostringstream text;
  text << in.rdbuf();
  return ParseImpactCsv(text.str(), path.string());
}

}  // namespace bouncecal::audio
