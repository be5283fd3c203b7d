#include "bouncecal/dem/contact_law_kind.h"

#include <gtest/gtest.h>

#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/error.h"

namespace bouncecal::dem {
namespace {

TEST(ContactLawKind, EveryNameRoundTrips) {
  for (ContactLawKind kind : kAllContactLawKinds) {
    EXPECT_EQ(ContactLawKindFromString(ToString(kind)), kind);
  }
}

TEST(ContactLawKind, UnknownNameListsTheValidOnes) {
  try {
    ContactLawKindFromString("hooke");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("'hooke'"), std::string::npos);
    EXPECT_NE(message.find("walton-braun-plastic"), std::string::npos);
  }
}

}  // namespace
}  // namespace bouncecal::dem
