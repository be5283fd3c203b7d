#ifndef BOUNCECAL_DEM_SCENE_JSON_READER_H_
#define BOUNCECAL_DEM_SCENE_JSON_READER_H_

#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <string_view>

#include "bouncecal/dem/scene.h"

namespace bouncecal::dem::scene {

// Reads one JSON object strictly: every value is checked for type and range, and Finish()
// rejects any key nobody asked for. Every problem is an InputError (the scene FILE is malformed:
// exit status 2) with a one-line message: "<file>: <key.path>: what, range".
class JsonReader {
 public:
  JsonReader(const nlohmann::json& object, std::string file, std::string path);

  bool Has(std::string_view key);                   // also records the key as a valid one
  const nlohmann::json& Raw(std::string_view key);  // marks the key used; must exist
  JsonReader Object(std::string_view key);
  double Number(std::string_view key, double min, double max);
  double Number(std::string_view key, double min, double max, double fallback);
  // A JSON integer, or a float holding a whole number (1e5); needs 0 <= max.
  std::int64_t Integer(std::string_view key, std::int64_t min, std::int64_t max);
  std::int64_t Integer(std::string_view key, std::int64_t min, std::int64_t max,
                       std::int64_t fallback);
  bool Boolean(std::string_view key, bool fallback);
  std::string String(std::string_view key);
  std::string String(std::string_view key, std::string fallback);
  // An array of exactly `size` finite numbers.
  Vec3 Vector(std::string_view key, int size);
  Vec3 Vector(std::string_view key, int size, Vec3 fallback);
  void Finish() const;

  std::string Key(std::string_view key) const;  // "particles.count"
  [[noreturn]] void Fail(std::string_view key, const std::string& what) const;
  const std::string& file() const { return file_; }

 private:
  const nlohmann::json& Required(std::string_view key);

  const nlohmann::json& object_;
  std::string file_;
  std::string path_;
  std::set<std::string, std::less<>> used_;
  std::set<std::string, std::less<>> known_;
};

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_SCENE_JSON_READER_H_
