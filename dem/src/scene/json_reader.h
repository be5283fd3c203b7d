#ifndef BOUNCECAL_DEM_SCENE_JSON_READER_H_
#define BOUNCECAL_DEM_SCENE_JSON_READER_H_

#include <cstdint>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "bouncecal/dem/scene.h"

namespace bouncecal::dem::scene {

// Thrown by JsonReader::Fail once the problem is recorded: the rest of that part of the file is
// skipped (its values cannot be trusted) and the caller reads the next part (ReadSection).
struct SectionAbandoned {};

// What is wrong with one file, gathered over all of it so that one error names every missing and
// every unknown key instead of one per run. Shared by a reader and every reader made from it.
struct JsonProblems {
  std::vector<std::string> missing;  // key paths, "particles.count"
  // Key path and the valid keys beside it: ("material.frictoin", "friction, hamaker_j, ...").
  std::vector<std::pair<std::string, std::string>> unknown;
  // "time_step_s: must be a number" (true: a whole message from another parser).
  std::vector<std::pair<std::string, bool>> values;
};

// Reads one JSON object strictly: every value is checked for type and range, and Finish()
// rejects any key nobody asked for (keys starting with '_' are comments and are skipped).
// A missing required key is recorded and stands in as a neutral value so reading goes on; a wrong
// value is recorded by Fail(), which then abandons the section. ThrowProblems() turns what was
// recorded into one InputError (the scene FILE is malformed: exit status 2) on one line:
// "<file>: <key.path>: what, range" for one problem, every problem after the file for several.
class JsonReader {
 public:
  JsonReader(const nlohmann::json& object, std::string file, std::string path);

  bool Has(std::string_view key);                   // also records the key as a valid one
  const nlohmann::json& Raw(std::string_view key);  // marks the key used; null when missing
  JsonReader Object(std::string_view key);
  // Object(key), or an empty object (every key takes its default) when the key is absent.
  JsonReader OptionalObject(std::string_view key);
  // The object at `index` of the array `list` (read from this reader's `key`).
  JsonReader Element(const nlohmann::json& list, std::string_view key, std::size_t index);
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
  // Records "<key.path>: what" (unless the section lacks a required key, whose stand-in value may
  // be what failed) and throws SectionAbandoned.
  [[noreturn]] void Fail(std::string_view key, const std::string& what) const;
  // Records an InputError thrown by another parser of part of the file (its message is whole).
  void Record(const std::string& message) const;
  // True when this reader's section has lost a required key: its values are not all the file's.
  bool Incomplete() const;
  bool HasProblems() const;
  // Throws the InputError naming every recorded problem, if there is any.
  void ThrowProblems() const;
  const std::string& file() const { return file_; }

 private:
  JsonReader(const nlohmann::json& object, const JsonReader& parent, std::string path, bool absent);
  const nlohmann::json& Required(std::string_view key);
  bool Absent(const nlohmann::json& value) const;
  // Fail(), but recorded even in an incomplete section: the value's type is the file's own.
  [[noreturn]] void FailType(std::string_view key, const std::string& what) const;

  const nlohmann::json& object_;
  std::string file_;
  std::string path_;
  std::shared_ptr<JsonProblems> problems_;
  // Missing keys recorded before this reader's top-level section began.
  std::size_t missing_before_ = 0;
  // The whole object is missing (already recorded): its keys are not reported one by one.
  bool absent_ = false;
  std::set<std::string, std::less<>> used_;
  std::set<std::string, std::less<>> known_;
};

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_SCENE_JSON_READER_H_
