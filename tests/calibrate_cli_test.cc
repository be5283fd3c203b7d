#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "bouncecal/testing/file_text.h"
#include "bouncecal/testing/scratch_folder.h"
#include "cli_runner.h"

namespace bouncecal::testing {
namespace {

namespace fs = std::filesystem;

std::string Sample() { return (SourceDir() / "samples" / "steel_ball_h0.2m.wav").string(); }

// The README's sample command: the paper's experiment, whose ball and height are known.
const std::string kPaperSetUp = " --ball steel-10mm --drop-height-m 0.2";

TEST(CalibrateCli, ShippedSampleGivesGammaNearTheFormulaWithJsonAndCard) {
  const auto json = ScratchPath("fit.json"), card = ScratchPath("card.json");
  const auto result = RunBouncecal("calibrate " + Sample() + kPaperSetUp + " --json " +
                                   json.string() + " --card " + card.string());
  ASSERT_EQ(result.exit_status, 0) << result.output;
  EXPECT_NE(result.output.find("gamma_n"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("analytic check"), std::string::npos) << result.output;
  std::ifstream in(json);
  const auto fit = nlohmann::json::parse(in);
  for (const char* key :
       {"law", "parameters", "confidence_interval", "analytic", "objective", "residual",
        "evaluations", "stop_reason", "uncertainty", "model_adequacy", "warnings"}) {
    EXPECT_TRUE(fit.contains(key)) << key;
  }
  // The sample was synthesised with a constant eta = 0.58 (samples/README.md): gamma_n from the
  // formula is 0.408; the synthesiser's flights neglect the contact time (70 us of ~0.27 s) and
  // the fit's Verlet step adds ~5e-4, so 0.408 +- 5e-3.
  EXPECT_NEAR(fit["parameters"]["gamma_n"].get<double>(), 0.408, 5e-3);
  EXPECT_TRUE(fit["analytic"]["gamma_n"].is_number());
  std::ifstream card_in(card);
  const auto material = nlohmann::json::parse(card_in);
  EXPECT_EQ(material["format"], "bouncecal-material/1");
  // The card states the ball, the height and what its interval includes.
  EXPECT_EQ(material["ball"]["preset"], "steel-10mm");
  EXPECT_DOUBLE_EQ(material["fit"]["drop_height_m"].get<double>(), 0.2);
  EXPECT_EQ(material["fit"]["release"], "drop-height");
  EXPECT_EQ(material["fit"]["uncertainty"]["recordings"], 1);
  EXPECT_EQ(material["fit"]["uncertainty"]["sequences"], 1);
  EXPECT_NE(material["fit"]["uncertainty"]["model"].get<std::string>().find("per-impact scatter"),
            std::string::npos);
}

// The card records the ball that was used, named or given by size and mass (issue 28: a tennis
// card said 7800 kg/m^3, steel). walton-braun's gamma_n does not depend on the ball, so the steel
// sample fits with any of them.
TEST(CalibrateCli, CardRecordsTheDensityOfANamedOrAMassGivenBall) {
  const auto card = ScratchPath("ball_card.json");
  const std::string csv = (SourceDir() / "samples" / "steel_ball_h0.2m.csv").string();
  struct Case {
    std::string ball;
    double diameter_m, mass_kg;
  };
  for (const Case& c : {Case{"--ball tennis", 0.067, 0.0577},
                        Case{"--diameter-m 0.04 --mass-kg 0.0027", 0.04, 0.0027}}) {
    const auto result = RunBouncecal("calibrate " + csv + " " + c.ball +
                                     " --drop-height-m 0.2 --card " + card.string());
    ASSERT_EQ(result.exit_status, 0) << c.ball << "\n" << result.output;
    const auto ball = nlohmann::json::parse(ReadFileText(card))["ball"];
    const double volume = std::numbers::pi * std::pow(c.diameter_m, 3) / 6;
    EXPECT_DOUBLE_EQ(ball["mass_kg"].get<double>(), c.mass_kg) << c.ball;
    // The card prints 17 significant digits; the division is the only rounding.
    EXPECT_NEAR(ball["density_kg_per_m3"].get<double>(), c.mass_kg / volume, 1e-9) << c.ball;
  }
}

// The card states k_n and the contact it implies; --contact-duration-s sets k_n so that the
// fitted law's contact lasts that long (refitted once with the fitted damping), and a named ball
// whose stiffness is left at a default far from its real contact is warned about.
TEST(CalibrateCli, CardStatesTheContactDurationItsStiffnessImplies) {
  const auto card = ScratchPath("contact_card.json");
  const std::string csv = (SourceDir() / "samples" / "steel_ball_h0.2m.csv").string();
  const std::string head = "calibrate " + csv + " --ball tennis --drop-height-m 0.2 --card ";
  const auto plain = RunBouncecal(head + card.string());
  ASSERT_EQ(plain.exit_status, 0) << plain.output;
  EXPECT_NE(plain.output.find("WARNING: stiffness_n_per_m = 1e+07 N/m (the walton-braun law's "
                              "default) makes the tennis ball's contact last"),
            std::string::npos)
      << plain.output;
  EXPECT_NE(plain.output.find("--contact-duration-s 0.005"), std::string::npos) << plain.output;
  const auto implied = nlohmann::json::parse(ReadFileText(card))["implied"];
  // gamma_n = 0.408 and 57.7 g at k_n = 1e7 N/m: (pi/2) sqrt(m/k) (1/sqrt(1.408) +
  // 1/sqrt(0.592)) = 0.2556 ms; the fitted gamma_n's +-0.005 moves it by 0.001 ms.
  EXPECT_NEAR(implied["contact_duration_s"].get<double>(), 2.556e-4, 0.01e-4);
  EXPECT_NEAR(implied["contact_speed_mps"].get<double>(), std::sqrt(2 * 9.81 * 0.2), 1e-12);

  const auto given = RunBouncecal(head + card.string() + " --contact-duration-s 0.005");
  ASSERT_EQ(given.exit_status, 0) << given.output;
  EXPECT_EQ(given.output.find("WARNING: stiffness_n_per_m"), std::string::npos) << given.output;
  const auto matched = nlohmann::json::parse(ReadFileText(card));
  // One refit with the fitted gamma_n: what is left is gamma_n's change through k_n (< 1e-3).
  EXPECT_NEAR(matched["implied"]["contact_duration_s"].get<double>(), 0.005, 0.005 * 1e-3);
  EXPECT_LT(matched["contact_law"]["parameters"]["stiffness_n_per_m"].get<double>(), 1e5);
}

// The reproducible-builds convention: with SOURCE_DATE_EPOCH set, the card records that time and
// two runs give byte-identical cards (without it, created_utc is the wall clock).
TEST(CalibrateCli, SourceDateEpochMakesTheCardByteIdentical) {
  const auto first = ScratchPath("epoch_1.json"), second = ScratchPath("epoch_2.json");
  const std::string environment = "SOURCE_DATE_EPOCH=1700000000";
  const std::string arguments = "calibrate " + Sample() + kPaperSetUp + " --card ";
  ASSERT_EQ(RunBouncecal(arguments + first.string(), environment).exit_status, 0);
  ASSERT_EQ(RunBouncecal(arguments + second.string(), environment).exit_status, 0);
  const auto card = ReadFileText(first);
  EXPECT_EQ(card, ReadFileText(second));
  EXPECT_EQ(nlohmann::json::parse(card)["created_utc"], "2023-11-14T22:13:20Z");
}

TEST(CalibrateCli, MalformedSourceDateEpochIsAnOptionErrorBeforeTheFit) {
  const auto card = ScratchPath("epoch_bad.json");
  for (const char* value : {"yesterday", "-5", "1e9", "99999999999999"}) {
    const auto result =
        RunBouncecal("calibrate " + Sample() + kPaperSetUp + " --card " + card.string(),
                     std::string("SOURCE_DATE_EPOCH=") + value);
    EXPECT_EQ(result.exit_status, 3) << value << ": " << result.output;
    EXPECT_NE(result.output.find("SOURCE_DATE_EPOCH"), std::string::npos) << result.output;
    EXPECT_FALSE(std::filesystem::exists(card)) << value;
  }
}

TEST(CalibrateCli, MissingRecordingExitsWithStatus2) {
  const auto result = RunBouncecal("calibrate /nonexistent/drop.wav");
  EXPECT_EQ(result.exit_status, 2) << result.output;
}

TEST(CalibrateCli, UnknownObjectiveOrLawExitsWithStatus3) {
  EXPECT_EQ(RunBouncecal("calibrate " + Sample() + " --objective energy").exit_status, 3);
  EXPECT_EQ(RunBouncecal("calibrate " + Sample() + " --law spring").exit_status, 3);
}

TEST(CalibrateCli, UnwritableCardExitsWithStatus4AndLeavesNothing) {
  const auto result =
      RunBouncecal("calibrate " + Sample() + kPaperSetUp + " --card /nonexistent/dir/card.json");
  EXPECT_EQ(result.exit_status, 4) << result.output;
}

TEST(CalibrateCli, FirstReboundAboveTheGivenHeightExitsWithStatus3AndBothHeights) {
  // The sample's first rebound rises to 0.2 * 0.42 = 0.084 m.
  const auto result = RunBouncecal("calibrate " + Sample() + " --drop-height-m 0.05");
  EXPECT_EQ(result.exit_status, 3) << result.output;
  EXPECT_NE(result.output.find("first rebound rose to 0.08"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("drop height 0.05 m"), std::string::npos) << result.output;
  // One line: the error and nothing else.
  EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
}

TEST(CalibrateCli, WithoutAHeightTheFitStartsFromTheFirstBounceAndSaysSo) {
  const auto result = RunBouncecal("calibrate " + Sample());
  ASSERT_EQ(result.exit_status, 0) << result.output;
  EXPECT_NE(result.output.find("drop height not given"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("ball: not given"), std::string::npos) << result.output;
  // The old flag still works, meaning the same; with a height it is a contradiction.
  const auto alias = RunBouncecal("calibrate " + Sample() + " --unknown-drop-height");
  EXPECT_EQ(alias.exit_status, 0) << alias.output;
  EXPECT_EQ(alias.output.substr(0, alias.output.find("optimiser")),
            result.output.substr(0, result.output.find("optimiser")));
  EXPECT_EQ(RunBouncecal("calibrate " + Sample() + " --unknown-drop-height --drop-height-m 0.2")
                .exit_status,
            3);
}

TEST(CalibrateCli, CardWithoutABallExitsWithStatus3BeforeFitting) {
  const auto card = ScratchPath("no_ball.json");
  const auto result = RunBouncecal("calibrate " + Sample() + " --card " + card.string());
  EXPECT_EQ(result.exit_status, 3) << result.output;
  EXPECT_NE(result.output.find("--ball"), std::string::npos) << result.output;
  EXPECT_EQ(result.output.find("gamma_n ="), std::string::npos) << "fitted before refusing";
  EXPECT_FALSE(std::filesystem::exists(card));
  // A speed-dependent law needs it too; an unknown preset names the valid ones.
  EXPECT_EQ(RunBouncecal("calibrate " + Sample() + " --law hertz-viscoelastic").exit_status, 3);
  const auto unknown = RunBouncecal("calibrate " + Sample() + " --ball bowling");
  EXPECT_EQ(unknown.exit_status, 3) << unknown.output;
  EXPECT_NE(unknown.output.find("pingpong-40mm"), std::string::npos) << unknown.output;
  // Half a ball is refused: a size needs a mass.
  EXPECT_EQ(RunBouncecal("calibrate " + Sample() + " --diameter-m 0.04").exit_status, 3);
}

TEST(CalibrateCli, SameRecordingTwiceGivesTheSameIntervalWithAWarning) {
  const auto once = ScratchPath("once.json"), twice = ScratchPath("twice.json");
  const auto one = RunBouncecal("calibrate " + Sample() + " --json " + once.string());
  const auto two =
      RunBouncecal("calibrate " + Sample() + " " + Sample() + " --json " + twice.string());
  ASSERT_EQ(one.exit_status, 0) << one.output;
  ASSERT_EQ(two.exit_status, 0) << two.output;
  std::ifstream once_in(once), twice_in(twice);
  const auto a = nlohmann::json::parse(once_in), b = nlohmann::json::parse(twice_in);
  EXPECT_EQ(a["confidence_interval"], b["confidence_interval"]);
  EXPECT_EQ(b["uncertainty"]["duplicates"], 1);
  EXPECT_NE(two.output.find("counted once"), std::string::npos) << two.output;
  EXPECT_EQ(one.output.find("counted once"), std::string::npos) << one.output;
}

TEST(CalibrateCli, RetiredBootstrapOptionsAreAcceptedWithAWarning) {
  const auto result = RunBouncecal("calibrate " + Sample() + " --bootstrap 16 --seed 3");
  EXPECT_EQ(result.exit_status, 0) << result.output;
  EXPECT_NE(result.output.find("--bootstrap and --seed no longer change anything"),
            std::string::npos)
      << result.output;
}

TEST(SweepCli, PrintsTheAnalyticColumnForWaltonBraun) {
  const auto result = RunBouncecal("sweep --law walton-braun --values 0.1:0.9:0.2");
  ASSERT_EQ(result.exit_status, 0) << result.output;
  EXPECT_NE(result.output.find("0.6667"), std::string::npos) << result.output;  // 2*0.5/1.5
}

TEST(CompareCli, NeedsExactlyOneOfGammaOrMaterial) {
  EXPECT_EQ(RunBouncecal("compare " + Sample() + " --drop-height-m 0.2").exit_status, 3);
  const auto result = RunBouncecal("compare " + Sample() + " --gamma 0.3,0.5 --drop-height-m 0.2");
  EXPECT_EQ(result.exit_status, 0) << result.output;
  EXPECT_NE(result.output.find("RMS"), std::string::npos) << result.output;
}

// Every drop option given to sweep or compare changes the drops they simulate (one set-up,
// DropCliOptions::DropSetUp; sweep once accepted --drag and ignored it). Each option is compared
// with the run without it on a ping-pong ball, whose flights drag shortens visibly; the JSON
// results must differ.
TEST(DropOptionsCli, EveryDropOptionChangesWhatSweepAndCompareSimulate) {
  const ScratchFolder folder("drop_options");
  // Each variation replaces or adds one option of the base set-up.
  const std::map<std::string, std::string> base = {{"--ball", "pingpong-40mm"},
                                                   {"--drop-height-m", "0.2"}};
  const std::vector<std::pair<std::string, std::string>> variations = {
      {"--drag", ""},
      {"--gravity-mps2", "9.5"},
      {"--drop-height-m", "0.3"},
      {"--integrator", "euler"},
      {"--time-step-s", "2e-6"},
      {"--steps-per-contact", "5"},
      {"--fixed-step-grid", ""},
      {"--ball", "tennis"},
      {"--contact-duration-s", "1e-4"}};
  const auto command = [&](const std::string& head, const std::map<std::string, std::string>& set,
                           const fs::path& json) {
    std::string text = head;
    for (const auto& [option, value] : set)
      text += " " + option + (value.empty() ? "" : " " + value);
    return text + " --json " + json.string();
  };
  for (const std::string& head :
       std::vector<std::string>{"sweep --values 0.3,0.5", "compare " + Sample() + " --gamma 0.3"}) {
    const std::string name = head.substr(0, head.find(' '));
    const auto reference = folder / (name + "_reference.json");
    ASSERT_EQ(RunBouncecal(command(head, base, reference)).exit_status, 0) << name;
    for (std::size_t i = 0; i < variations.size(); ++i) {
      auto set = base;
      set[variations[i].first] = variations[i].second;
      const auto changed = folder / (name + "_" + std::to_string(i) + ".json");
      const auto result = RunBouncecal(command(head, set, changed));
      ASSERT_EQ(result.exit_status, 0) << command(head, set, changed) << "\n" << result.output;
      EXPECT_NE(ReadFileText(changed), ReadFileText(reference))
          << name << " " << variations[i].first;
    }
  }
}

// The same for the drops `simulate drop` runs and `calibrate` fits: only their results are
// compared (the impacts; the fitted parameters and the analytic check), since both also echo
// their set-up. calibrate's base has drag on, so the ball matters (without drag the linear law's
// gamma_n does not depend on the ball, and an unchanged fit would be right).
TEST(DropOptionsCli, EveryDropOptionChangesWhatSimulateRunsAndCalibrateFits) {
  const ScratchFolder folder("drop_options_fit");
  const std::vector<std::pair<std::string, std::string>> variations = {
      {"--gravity-mps2", "9.5"}, {"--drop-height-m", "0.3"},      {"--integrator", "euler"},
      {"--time-step-s", "2e-6"}, {"--steps-per-contact", "5"},    {"--fixed-step-grid", ""},
      {"--ball", "tennis"},      {"--contact-duration-s", "1e-4"}};
  struct Subcommand {
    std::string head;
    std::map<std::string, std::string> base;
    std::vector<std::string> result_fields;
  };
  const std::vector<Subcommand> subcommands = {
      {"simulate drop --gamma 0.3",
       {{"--ball", "pingpong-40mm"}, {"--drop-height-m", "0.2"}},
       {"impacts"}},
      {"calibrate " + Sample(),
       {{"--ball", "pingpong-40mm"}, {"--drop-height-m", "0.2"}, {"--drag", ""}},
       {"parameters", "analytic"}},
  };
  for (std::size_t c = 0; c < subcommands.size(); ++c) {
    const auto& [head, base, fields] = subcommands[c];
    const auto run = [&](const std::map<std::string, std::string>& set, const fs::path& json) {
      std::string text = head;
      for (const auto& [option, value] : set) {
        text += " " + option + (value.empty() ? "" : " " + value);
      }
      text += " --json " + json.string();
      const auto result = RunBouncecal(text);
      EXPECT_EQ(result.exit_status, 0) << text << "\n" << result.output;
      nlohmann::json document = nlohmann::json::parse(ReadFileText(json));
      nlohmann::json results;
      for (const auto& field : fields) results[field] = document.at(field);
      return results;
    };
    const auto reference = run(base, folder / ("reference_" + std::to_string(c) + ".json"));
    auto tried = variations;
    if (!base.contains("--drag")) tried.emplace_back("--drag", "");
    for (std::size_t i = 0; i < tried.size(); ++i) {
      auto set = base;
      set[tried[i].first] = tried[i].second;
      const auto changed =
          run(set, folder / (std::to_string(c) + "_" + std::to_string(i) + ".json"));
      EXPECT_NE(changed, reference) << head << " " << tried[i].first;
    }
  }
}

// compare sets the measured arcs against drops released from the given height: it does not
// assume one (it assumed the paper's 0.2 m).
TEST(CompareCli, RefusesToAssumeADropHeight) {
  const auto result = RunBouncecal("compare " + Sample() + " --gamma 0.3,0.5");
  EXPECT_EQ(result.exit_status, 3) << result.output;
  EXPECT_NE(result.output.find("--drop-height-m"), std::string::npos) << result.output;
}

// The summary ends with what a researcher does next: the material card, compare and export, as
// commands with the real file names. Each suggested command is run as printed, from the folder
// the first run was in, and must succeed: the card first, then compare and export read it.
TEST(CalibrateCli, SummaryEndsWithNextCommandsThatRunAsPrinted) {
  const auto dir = ScratchSubfolder("next_steps");
  const std::string in_dir = "cd " + dir.string() + " &&";
  const auto first = RunBouncecal("calibrate " + Sample() + kPaperSetUp, in_dir);
  ASSERT_EQ(first.exit_status, 0) << first.output;
  const auto next = first.output.find("next steps:\n");
  ASSERT_NE(next, std::string::npos) << first.output;
  std::vector<std::string> commands;
  std::istringstream lines(first.output.substr(next));
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("  bouncecal ", 0) == 0) commands.push_back(line.substr(12));
  }
  ASSERT_EQ(commands.size(), 3u) << first.output;
  EXPECT_EQ(commands[0], "calibrate " + Sample() +
                             " --ball steel-10mm --drop-height-m 0.2 --card "
                             "steel_ball_h0.2m_material.json");
  EXPECT_EQ(commands[1].rfind("compare " + Sample() +
                                  " --material steel_ball_h0.2m_material.json --drop-height-m 0.2",
                              0),
            0u)
      << commands[1];
  EXPECT_EQ(
      commands[2].rfind("export --material steel_ball_h0.2m_material.json --engine lammps", 0), 0u)
      << commands[2];
  for (const auto& command : commands) {
    const auto run = RunBouncecal(command, in_dir);
    EXPECT_EQ(run.exit_status, 0) << command << "\n" << run.output;
  }
  EXPECT_TRUE(fs::exists(dir / "steel_ball_h0.2m_material.json"));
  EXPECT_TRUE(fs::exists(dir / "steel_ball_h0.2m_compare.png"));
  EXPECT_TRUE(fs::exists(dir / "steel_ball_h0.2m_material_lammps" / "in.drop"));
  // With the card written, the rerun's own suggestions start from it: compare and export only.
  const auto second = RunBouncecal(commands[0], in_dir);
  ASSERT_EQ(second.exit_status, 0) << second.output;
  EXPECT_NE(second.output.find("next steps:"), std::string::npos) << second.output;
  EXPECT_EQ(second.output.find("--card"), std::string::npos) << second.output;
}

// Without the drop height or the ball, the commands that need them say so with a placeholder.
TEST(CalibrateCli, NextCommandsNameWhatThisFitLacked) {
  const auto result = RunBouncecal("calibrate " + Sample());
  ASSERT_EQ(result.exit_status, 0) << result.output;
  EXPECT_NE(result.output.find("--ball BALL --card steel_ball_h0.2m_material.json"),
            std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("--drop-height-m HEIGHT_M"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace bouncecal::testing
