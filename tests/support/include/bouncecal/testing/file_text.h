#ifndef BOUNCECAL_TESTING_FILE_TEXT_H_
#define BOUNCECAL_TESTING_FILE_TEXT_H_

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace bouncecal::testing {

// The whole file, byte for byte; empty when it cannot be read (the test's comparison then says
// what was expected).
std::string ReadFileText(const std::filesystem::path& path);

// The file parsed as JSON; nlohmann::json's parse_error names the offset when it is not JSON.
nlohmann::json ReadJsonFile(const std::filesystem::path& path);

}  // namespace bouncecal::testing

#endif  // BOUNCECAL_TESTING_FILE_TEXT_H_
