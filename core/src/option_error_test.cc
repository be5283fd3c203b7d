#include "bouncecal/option_error.h"

#include <gtest/gtest.h>

namespace bouncecal {
namespace {

std::string Flag(std::string_view field) {
  std::string flag = "--";
  for (char c : field) flag += c == '_' ? '-' : c;
  return flag;
}

TEST(SpellFields, NamesWithAnUnderscoreAreReplacedAsWholeWordsOnly) {
  EXPECT_EQ(SpellFields("drop_height_m must be positive; drop_height_m_extra and xdrop_height_m "
                        "stay",
                        {"drop_height_m"}, Flag),
            "--drop-height-m must be positive; drop_height_m_extra and xdrop_height_m stay");
}

TEST(SpellFields, OneWordNamesAreReplacedOnlyInBackticks) {
  EXPECT_EQ(SpellFields("the ball is needed: give `ball` NAME", {"ball"}, Flag),
            "the ball is needed: give --ball NAME");
  // A keyword keeps its name, without the backticks.
  EXPECT_EQ(SpellFields("give `ball` NAME", {"ball"},
                        [](std::string_view field) { return std::string(field); }),
            "give ball NAME");
}

TEST(SpellFields, FieldsNotNamedAreLeftAlone) {
  EXPECT_EQ(SpellFields("first_n and `ball`", {}, Flag), "first_n and `ball`");
}

}  // namespace
}  // namespace bouncecal
