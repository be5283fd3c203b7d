#include "bouncecal/error.h"

#include <gtest/gtest.h>

#include <string>

namespace bouncecal {
namespace {

TEST(Error, MessagesStayOnOneLineWhateverTheyQuote) {
  // A JSON key or file name may hold any control character; the CLI prints the message as one
  // line, so each is escaped visibly instead.
  const InputError error(std::string("scene.json: unknown key 'a\nb\tc\x01\x7f\r'"));
  EXPECT_STREQ(error.what(), "scene.json: unknown key 'a\\nb\\tc\\x01\\x7f\\r'");
}

TEST(Error, PlainMessagesAndUtf8AreUntouched) {
  const std::string message = "recording.wav: 8000 Hz is below the minimum; η_k needs more";
  EXPECT_EQ(ConfigError(message).what(), message);
  EXPECT_EQ(std::string(OutputError("x.csv: cannot write").what()), "x.csv: cannot write");
}

}  // namespace
}  // namespace bouncecal
