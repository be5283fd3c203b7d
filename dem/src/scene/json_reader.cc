#include "scene/json_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "bouncecal/error.h"

namespace bouncecal::dem::scene {
namespace {

// What a missing key reads as: nothing, so no check passes or fails on it by accident.
const nlohmann::json& AbsentValue() {
  static const nlohmann::json absent;
  return absent;
}

const nlohmann::json& EmptyObject() {
  static const nlohmann::json empty = nlohmann::json::object();
  return empty;
}

}  // namespace

JsonReader::JsonReader(const nlohmann::json& object, std::string file, std::string path)
    : object_(object),
      file_(std::move(file)),
      path_(std::move(path)),
      problems_(std::make_shared<JsonProblems>()) {
  if (!object_.is_object()) {
    throw InputError(fmt::format("{}: {}: must be a JSON object {{...}}", file_,
                                 path_.empty() ? std::string("top level") : path_));
  }
}

JsonReader::JsonReader(const nlohmann::json& object, const JsonReader& parent, std::string path,
                       bool absent)
    : object_(object),
      file_(parent.file_),
      path_(std::move(path)),
      problems_(parent.problems_),
      // A section of the top level starts counting its own missing keys here.
      missing_before_(parent.path_.empty() ? parent.problems_->missing.size()
                                           : parent.missing_before_),
      absent_(absent || parent.absent_) {}

std::string JsonReader::Key(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

bool JsonReader::Incomplete() const {
  return absent_ || (!path_.empty() && problems_->missing.size() > missing_before_);
}

void JsonReader::Fail(std::string_view key, const std::string& what) const {
  if (!Incomplete()) problems_->values.emplace_back(Key(key) + ": " + what, false);
  throw SectionAbandoned{};
}

void JsonReader::FailType(std::string_view key, const std::string& what) const {
  problems_->values.emplace_back(Key(key) + ": " + what, false);
  throw SectionAbandoned{};
}

void JsonReader::Record(const std::string& message) const {
  problems_->values.emplace_back(message, true);
}

bool JsonReader::HasProblems() const {
  return !problems_->missing.empty() || !problems_->unknown.empty() || !problems_->values.empty();
}

void JsonReader::ThrowProblems() const {
  const auto& p = *problems_;
  std::vector<std::string> items;
  if (p.missing.size() == 1) {
    items.push_back(p.missing.front() + ": is missing");
  } else if (!p.missing.empty()) {
    items.push_back(fmt::format("missing keys {}", fmt::join(p.missing, ", ")));
  }
  const std::size_t count = (p.missing.empty() ? 0 : 1) + p.unknown.size() + p.values.size();
  for (const auto& [key, valid] : p.unknown) {
    items.push_back(count == 1 ? fmt::format("unknown key '{}'; valid keys here: {}", key, valid)
                               : fmt::format("unknown key '{}' (valid keys here: {})", key, valid));
  }
  if (count == 1 && p.values.size() == 1 && p.values.front().second) {
    throw InputError(p.values.front().first);
  }
  for (const auto& [text, whole] : p.values) items.push_back(text);
  if (items.empty()) return;
  if (items.size() == 1) throw InputError(fmt::format("{}: {}", file_, items.front()));
  const std::size_t problems = p.missing.size() + p.unknown.size() + p.values.size();
  throw InputError(fmt::format("{}: {} problems: {}", file_, problems, fmt::join(items, "; ")));
}

bool JsonReader::Absent(const nlohmann::json& value) const { return &value == &AbsentValue(); }

bool JsonReader::Has(std::string_view key) {
  known_.insert(std::string(key));
  return object_.contains(std::string(key));
}

const nlohmann::json& JsonReader::Required(std::string_view key) {
  known_.insert(std::string(key));
  const auto it = object_.find(std::string(key));
  if (it == object_.end()) {
    if (!absent_) problems_->missing.push_back(Key(key));
    return AbsentValue();
  }
  used_.insert(std::string(key));
  return *it;
}

const nlohmann::json& JsonReader::Raw(std::string_view key) { return Required(key); }

JsonReader JsonReader::Object(std::string_view key) {
  const auto& value = Required(key);
  if (Absent(value)) return JsonReader(EmptyObject(), *this, Key(key), /*absent=*/true);
  if (!value.is_object()) FailType(key, "must be a JSON object {...}");
  return JsonReader(value, *this, Key(key), /*absent=*/false);
}

JsonReader JsonReader::OptionalObject(std::string_view key) {
  if (Has(key)) return Object(key);
  return JsonReader(EmptyObject(), *this, Key(key), /*absent=*/false);
}

JsonReader JsonReader::Element(const nlohmann::json& list, std::string_view key,
                               std::size_t index) {
  const std::string element = fmt::format("{}[{}]", key, index);
  if (!list[index].is_object()) FailType(element, "must be a JSON object {...}");
  return JsonReader(list[index], *this, Key(element), /*absent=*/false);
}

double JsonReader::Number(std::string_view key, double min, double max) {
  const auto& value = Required(key);
  if (Absent(value)) return min <= max ? std::clamp(1.0, min, max) : min;
  if (!value.is_number()) FailType(key, "must be a number");
  const double x = value.get<double>();
  if (!std::isfinite(x) || x < min || x > max) {
    Fail(key, fmt::format("{} is outside the valid range [{}, {}]", x, min, max));
  }
  return x;
}

double JsonReader::Number(std::string_view key, double min, double max, double fallback) {
  return Has(key) ? Number(key, min, max) : fallback;
}

std::int64_t JsonReader::Integer(std::string_view key, std::int64_t min, std::int64_t max) {
  const auto& value = Required(key);
  if (Absent(value)) return min <= max ? std::clamp<std::int64_t>(1, min, max) : min;
  const auto range = [&](const auto& x) {
    Fail(key, fmt::format("{} is outside the valid range [{}, {}]", x, min, max));
  };
  if (value.is_number_unsigned()) {
    // Above 2^63 a get<std::int64_t>() would wrap to a negative count.
    const auto x = value.get<std::uint64_t>();
    if (x > static_cast<std::uint64_t>(max) || static_cast<std::int64_t>(x) < min) range(x);
    return static_cast<std::int64_t>(x);
  }
  if (value.is_number_integer()) {
    const auto x = value.get<std::int64_t>();
    if (x < min || x > max) range(x);
    return x;
  }
  // People write counts as 1e5: accept a float holding a whole number, range-checked before
  // the conversion (a double outside the int64 range does not convert).
  const double x = value.is_number_float() ? value.get<double>() : 0.5;
  if (!value.is_number_float() || !std::isfinite(x) || x != std::floor(x)) {
    FailType(key, "must be an integer");
  }
  if (x < static_cast<double>(min) || x > static_cast<double>(max) || x >= 0x1p63) range(x);
  return static_cast<std::int64_t>(x);
}

std::int64_t JsonReader::Integer(std::string_view key, std::int64_t min, std::int64_t max,
                                 std::int64_t fallback) {
  return Has(key) ? Integer(key, min, max) : fallback;
}

bool JsonReader::Boolean(std::string_view key, bool fallback) {
  if (!Has(key)) return fallback;
  const auto& value = Required(key);
  if (!value.is_boolean()) FailType(key, "must be true or false");
  return value.get<bool>();
}

std::string JsonReader::String(std::string_view key) {
  const auto& value = Required(key);
  if (Absent(value)) return "";
  if (!value.is_string()) FailType(key, "must be a string");
  return value.get<std::string>();
}

std::string JsonReader::String(std::string_view key, std::string fallback) {
  return Has(key) ? String(key) : fallback;
}

Vec3 JsonReader::Vector(std::string_view key, int size) {
  const auto& value = Required(key);
  Vec3 out{0, 0, 0};
  if (Absent(value)) return out;
  if (!value.is_array() || static_cast<int>(value.size()) != size) {
    FailType(key, fmt::format("must be an array of {} numbers", size));
  }
  for (int d = 0; d < size; ++d) {
    if (!value[d].is_number() || !std::isfinite(value[d].get<double>())) {
      FailType(key, fmt::format("must be an array of {} finite numbers", size));
    }
    out[d] = value[d].get<double>();
  }
  return out;
}

Vec3 JsonReader::Vector(std::string_view key, int size, Vec3 fallback) {
  return Has(key) ? Vector(key, size) : fallback;
}

void JsonReader::Finish() const {
  if (absent_) return;
  for (const auto& [key, value] : object_.items()) {
    // Keys starting with '_' are comments ("_comment": "...", docs/scenes.md).
    if (used_.count(key) != 0 || (!key.empty() && key.front() == '_')) continue;
    std::string valid;
    for (const auto& k : known_) valid += (valid.empty() ? "" : ", ") + k;
    problems_->unknown.emplace_back(Key(key), valid);
  }
}

}  // namespace bouncecal::dem::scene
