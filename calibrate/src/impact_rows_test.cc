#include "bouncecal/calibrate/impact_rows.h"

#include <gtest/gtest.h>

#include "bouncecal/error.h"

namespace bouncecal::calibrate {
namespace {

// One recording's entry as `analyze --json` writes it, reduced to the fields the rows read: a
// stray sound, then a four-impact sequence analysed without a drop height (e_k from the second
// impact on), then a sound after it.
nlohmann::json Entry() {
  auto impact = [](double onset_s, nlohmann::json sequence, bool residual_only = false) {
    return nlohmann::json{{"onset_s", onset_s},           {"onset_uncertainty_s", 2e-5},
                          {"peak_dbfs", -12.5},           {"residual_only", residual_only},
                          {"timed_from_response", false}, {"sequence", sequence}};
  };
  nlohmann::json sequence = {{"onsets_s", {0.5, 0.9, 1.2, 1.42}},
                             {"intervals_s", {0.4, 0.3, 0.22}},
                             {"bounce_height_m", {0.196, 0.110, 0.059}},
                             {"restitution_impact_index", {1, 2}},
                             {"restitution", {0.75, 0.733}},
                             {"restitution_uncertainty", {0.001, 0.002}},
                             {"energy_loss", {0.4375, 0.4627}},
                             {"energy_loss_uncertainty", {0.0015, 0.0029}}};
  return {{"file", "drop.wav"},
          {"channel", 1},
          {"impacts",
           {impact(0.1, nullptr), impact(0.5, 0), impact(0.9, 0), impact(1.2, 0),
            impact(1.42, 0, true), impact(2.0, nullptr)}},
          {"sequences", {sequence}}};
}

TEST(ImpactRows, NumberEachSequenceMemberAsEtaKAndLeaveWhatTheSequenceDoesNotGiveEmpty) {
  const auto rows = ImpactRows(Entry());
  ASSERT_EQ(rows.size(), 6u);
  // Sounds outside the sequence: no sequence, k or sequence values.
  for (const auto index : {0u, 5u}) {
    EXPECT_FALSE(rows[index].sequence);
    EXPECT_FALSE(rows[index].k);
    EXPECT_FALSE(rows[index].interval_s);
    EXPECT_FALSE(rows[index].energy_loss);
  }
  EXPECT_EQ(rows[0].file, "drop.wav");
  EXPECT_EQ(rows[0].channel, 1);
  for (int k = 1; k <= 4; ++k) {
    const auto& row = rows[static_cast<std::size_t>(k)];
    EXPECT_EQ(row.sequence, 0);
    EXPECT_EQ(row.k, k);
  }
  // No drop height: the first member has its flight but no e_1; e_2 is the second member's.
  EXPECT_EQ(rows[1].interval_s, 0.4);
  EXPECT_FALSE(rows[1].restitution);
  EXPECT_EQ(rows[2].restitution, 0.75);
  EXPECT_EQ(rows[2].energy_loss_uncertainty, 0.0015);
  EXPECT_EQ(rows[3].energy_loss, 0.4627);
  // The last member: no flight after it, and here no e either (restitution_impact_index ends at
  // 2), though the sequence has four onsets.
  EXPECT_EQ(rows[3].bounce_height_m, 0.059);
  EXPECT_FALSE(rows[4].interval_s);
  EXPECT_FALSE(rows[4].restitution);
  EXPECT_TRUE(rows[4].residual_only);
  EXPECT_EQ(rows[4].onset_s, 1.42);
}

TEST(ImpactRows, SamplesInMemoryHaveNoFileAndNullsAreEmpty) {
  auto entry = Entry();
  entry["file"] = nullptr;
  // A quantity not measured is null in the document (JSON has no NaN).
  entry["sequences"][0]["restitution_uncertainty"][0] = nullptr;
  const auto rows = ImpactRows(entry);
  EXPECT_FALSE(rows[0].file);
  EXPECT_EQ(rows[2].restitution, 0.75);
  EXPECT_FALSE(rows[2].restitution_uncertainty);
}

TEST(ImpactRows, AnEntryThatIsNotAnAnalysisIsAnInputErrorNamingWhatIsWrong) {
  auto missing = Entry();
  missing.erase("impacts");
  EXPECT_THROW(
      {
        try {
          ImpactRows(missing);
        } catch (const InputError& error) {
          EXPECT_NE(std::string(error.what()).find("impacts"), std::string::npos) << error.what();
          throw;
        }
      },
      InputError);
  auto unknown_sequence = Entry();
  unknown_sequence["impacts"][1]["sequence"] = 3;
  auto too_many_members = Entry();
  too_many_members["impacts"][5]["sequence"] = 0;  // a fifth member of a four-onset sequence
  for (const auto& entry : {unknown_sequence, too_many_members}) {
    try {
      ImpactRows(entry);
      ADD_FAILURE() << "no error";
    } catch (const InputError& error) {
      // One line that says what was wrong and what to give instead.
      const std::string message = error.what();
      EXPECT_NE(message.find("sequence"), std::string::npos) << message;
      EXPECT_NE(message.find("docs/json.md"), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }
}

}  // namespace
}  // namespace bouncecal::calibrate
