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

std::string CommandLine(std::string_view field, std::string_view value) {
  std::string flag = Flag(field);
  if (!value.empty()) flag.append(" ").append(value);
  return flag;
}

TEST(SpellOptions, EachBacktickedOptionIsSpeltWithItsValue) {
  EXPECT_EQ(SpellOptions("fit with `objective=mean-energy-loss`, or rank with `compare_laws`; "
                         "`first_n=3` at least",
                         CommandLine),
            "fit with --objective mean-energy-loss, or rank with --compare-laws; --first-n 3 at "
            "least");
}

TEST(SpellOptions, BacktickedTextThatIsNotAnOptionNameIsLeftAlone) {
  // Upper case, spaces, an empty value and an unclosed backtick are not option mentions.
  EXPECT_EQ(SpellOptions("`Hertz` `a b` `x=` `` `gamma_n", CommandLine),
            "`Hertz` `a b` `x=` `` `gamma_n");
  // A closing backtick of a skipped span does not open the next mention.
  EXPECT_EQ(SpellOptions("`a b` then `plot`", CommandLine), "`a b` then --plot");
  EXPECT_EQ(SpellOptions("no options here", CommandLine), "no options here");
}

}  // namespace
}  // namespace bouncecal
