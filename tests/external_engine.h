#ifndef BOUNCECAL_TESTS_EXTERNAL_ENGINE_H_
#define BOUNCECAL_TESTS_EXTERNAL_ENGINE_H_

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace bouncecal::testing {

// Whether an external engine (lmp, liggghts) can be run: the tests that run one skip without it.
inline bool OnPath(const std::string& executable) {
  return std::system(("command -v " + executable + " >/dev/null 2>&1").c_str()) == 0;
}

// The end of an engine's log, where its error is, for a failing assertion's message.
inline std::string Tail(const std::filesystem::path& path, std::size_t characters = 1500) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  const std::string all = text.str();
  return all.size() > characters ? all.substr(all.size() - characters) : all;
}

}  // namespace bouncecal::testing

#endif  // BOUNCECAL_TESTS_EXTERNAL_ENGINE_H_
