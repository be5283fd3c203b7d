#include "bouncecal/dem/contact_law_json.h"

#include <gtest/gtest.h>

#include <string>

#include "bouncecal/dem/contact_laws.h"
#include "bouncecal/error.h"

namespace bouncecal::dem {
namespace {

std::string ErrorOf(const nlohmann::json& object) {
  try {
    ContactLawConfigFromJson(object, "card.json: contact_law");
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(ContactLawJson, EveryLawRoundTripsWithAllItsParameters) {
  for (ContactLawKind kind : kAllContactLawKinds) {
    ContactLawConfig config{.kind = kind, .parameters = {}};
    const nlohmann::json json = ToJson(config);
    EXPECT_EQ(json.at("parameters").size(), ParameterSpecs(kind).size());
    const ContactLawConfig back = ContactLawConfigFromJson(json, "test");
    EXPECT_EQ(back.kind, kind);
    for (const ParameterSpec& spec : ParameterSpecs(kind)) {
      EXPECT_EQ(back.Get(spec.name), config.Get(spec.name));
    }
  }
}

TEST(ContactLawJson, ReadsThePaperLaw) {
  const auto config = ContactLawConfigFromJson(
      nlohmann::json::parse(
          R"({"law": "walton-braun", "parameters": {"stiffness_n_per_m": 1e7, "gamma_n": 0.408}})"),
      "test");
  EXPECT_EQ(config.kind, ContactLawKind::kWaltonBraun);
  EXPECT_EQ(config.Get("gamma_n"), 0.408);
}

TEST(ContactLawJson, MissingParametersTakeDefaults) {
  const auto config = ContactLawConfigFromJson({{"law", "hertz"}}, "test");
  EXPECT_EQ(config.Get("effective_modulus_pa"), 1.1e11);
}

TEST(ContactLawJson, BadObjectsAreRefusedWithContextAndName) {
  std::string message = ErrorOf({{"law", "hooke"}});
  EXPECT_EQ(message.rfind("card.json: contact_law:", 0), 0u) << message;
  EXPECT_NE(message.find("hooke"), std::string::npos);
  message = ErrorOf({{"law", "walton-braun"}, {"colour", 1}});
  EXPECT_NE(message.find("\"colour\""), std::string::npos) << message;
  message = ErrorOf({{"law", "walton-braun"}, {"parameters", {{"gamma", 0.5}}}});
  EXPECT_NE(message.find("'gamma'"), std::string::npos) << message;
  message = ErrorOf({{"law", "walton-braun"}, {"parameters", {{"gamma_n", "0.5"}}}});
  EXPECT_NE(message.find("gamma_n"), std::string::npos) << message;
  message = ErrorOf({{"law", "walton-braun"}, {"parameters", {{"gamma_n", 2}}}});
  EXPECT_NE(message.find("[0, 1]"), std::string::npos) << message;
  message = ErrorOf({{"parameters", nlohmann::json::object()}});
  EXPECT_NE(message.find("\"law\""), std::string::npos) << message;
  EXPECT_NE(ErrorOf(nlohmann::json::array()), "");
}

}  // namespace
}  // namespace bouncecal::dem
