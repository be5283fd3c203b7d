#include "scene/json_reader.h"

#include <fmt/format.h>

#include <cmath>

#include "bouncecal/error.h"

namespace bouncecal::dem::scene {

JsonReader::JsonReader(const nlohmann::json& object, std::string file, std::string path)
    : object_(object), file_(std::move(file)), path_(std::move(path)) {
  if (!object_.is_object()) {
    throw InputError(fmt::format("{}: {}: must be a JSON object {{...}}", file_,
                                 path_.empty() ? std::string("top level") : path_));
  }
}

std::string JsonReader::Key(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

void JsonReader::Fail(std::string_view key, const std::string& what) const {
  throw InputError(fmt::format("{}: {}: {}", file_, Key(key), what));
}

bool JsonReader::Has(std::string_view key) {
  known_.insert(std::string(key));
  return object_.contains(std::string(key));
}

const nlohmann::json& JsonReader::Required(std::string_view key) {
  known_.insert(std::string(key));
  const auto it = object_.find(std::string(key));
  if (it == object_.end()) Fail(key, "is missing");
  used_.insert(std::string(key));
  return *it;
}

const nlohmann::json& JsonReader::Raw(std::string_view key) { return Required(key); }

JsonReader JsonReader::Object(std::string_view key) {
  const auto& value = Required(key);
  if (!value.is_object()) Fail(key, "must be a JSON object {...}");
  return JsonReader(value, file_, Key(key));
}

double JsonReader::Number(std::string_view key, double min, double max) {
  const auto& value = Required(key);
  if (!value.is_number()) Fail(key, "must be a number");
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
    Fail(key, "must be an integer");
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
  if (!value.is_boolean()) Fail(key, "must be true or false");
  return value.get<bool>();
}

std::string JsonReader::String(std::string_view key) {
  const auto& value = Required(key);
  if (!value.is_string()) Fail(key, "must be a string");
  return value.get<std::string>();
}

std::string JsonReader::String(std::string_view key, std::string fallback) {
  return Has(key) ? String(key) : fallback;
}

Vec3 JsonReader::Vector(std::string_view key, int size) {
  const auto& value = Required(key);
  if (!value.is_array() || static_cast<int>(value.size()) != size) {
    Fail(key, fmt::format("must be an array of {} numbers", size));
  }
  Vec3 out{0, 0, 0};
  for (int d = 0; d < size; ++d) {
    if (!value[d].is_number() || !std::isfinite(value[d].get<double>())) {
      Fail(key, fmt::format("must be an array of {} finite numbers", size));
    }
    out[d] = value[d].get<double>();
  }
  return out;
}

Vec3 JsonReader::Vector(std::string_view key, int size, Vec3 fallback) {
  return Has(key) ? Vector(key, size) : fallback;
}

void JsonReader::Finish() const {
  for (const auto& [key, value] : object_.items()) {
    if (used_.count(key) == 0) {
      std::string valid;
      for (const auto& k : known_) valid += (valid.empty() ? "" : ", ") + k;
      throw InputError(
          fmt::format("{}: unknown key '{}'; valid keys here: {}", file_, Key(key), valid));
    }
  }
}

}  // namespace bouncecal::dem::scene
