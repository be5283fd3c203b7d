#include "bouncecal/calibrate/card_creation_time.h"

#include <charconv>
#include <cstdlib>
#include <string>
#include <string_view>

#include "bouncecal/error.h"

namespace bouncecal::calibrate {

namespace {
// 9999-12-31T23:59:59Z: the last second a four-digit ISO 8601 year can show.
constexpr long long kLastFourDigitYearSecond = 253402300799LL;
}  // namespace

std::time_t CardCreationTimeFromEnvironment(std::string_view remedy) {
  const char* value = std::getenv("SOURCE_DATE_EPOCH");
  if (value == nullptr) return std::time(nullptr);
  const std::string_view text = value;
  long long seconds = -1;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), seconds);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() || seconds < 0 ||
      seconds > kLastFourDigitYearSecond) {
    throw ConfigError("SOURCE_DATE_EPOCH='" + std::string(text) +
                      "' is not a whole number of seconds since 1970-01-01 UTC in 0.." +
                      std::to_string(kLastFourDigitYearSecond) + "; " + std::string(remedy));
  }
  return static_cast<std::time_t>(seconds);
}

}  // namespace bouncecal::calibrate
