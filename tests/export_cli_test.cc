// The export subcommand's command-line contract: what it writes and prints, and its exit
// statuses for bad input (2), bad options (3) and unwritable output (4). No engine is needed.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "bouncecal/testing/scratch_folder.h"
#include "cli_runner.h"

namespace bouncecal::testing {
namespace {

namespace fs = std::filesystem;

class ExportCli : public ::testing::Test {
 protected:
  void SetUp() override {
    WriteCard(
        R"({"law": "walton-braun", "parameters": {"stiffness_n_per_m": 1e7, "gamma_n": 0.5}})");
  }

  void WriteCard(const std::string& contact_law) {
    std::ofstream(folder_ / "card.json")
        << R"({"format": "bouncecal-material/1", "contact_law": )" << contact_law
        << R"(, "ball": {"diameter_m": 0.01, "density_kg_per_m3": 7800}})";
  }
  std::string Card() const { return (folder_ / "card.json").string(); }

  const ScratchFolder folder_;
};

TEST_F(ExportCli, WritesTheDeckAndPrintsMappingDeviationAndRunCommand) {
  const fs::path deck = folder_ / "deck";
  const auto result =
      RunBouncecal("export --material " + Card() + " --engine liggghts -o " + deck.string());
  ASSERT_EQ(result.exit_status, 0) << result.output;
  ASSERT_TRUE(fs::exists(deck / "in.drop"));
  EXPECT_NE(result.output.find("MAPPED LAW: LIGGGHTS has no Walton-Braun"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("within +-0.20 %"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("cd " + deck.string() + " && liggghts -in in.drop"),
            std::string::npos)
      << result.output;
  // Nothing half-written is left beside the deck.
  for (const auto& entry : fs::directory_iterator(deck)) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos) << entry.path();
  }
}

TEST_F(ExportCli, SceneAddsThePackingDeckForMpirun) {
  const fs::path deck = folder_ / "deck";
  const auto scene = SourceDir() / "samples/scenes/paper000_cylinder_pour.json";
  const auto result = RunBouncecal("export --material " + Card() + " --engine lammps --scene " +
                                   scene.string() + " -o " + deck.string());
  ASSERT_EQ(result.exit_status, 0) << result.output;
  EXPECT_TRUE(fs::exists(deck / "in.drop"));
  ASSERT_TRUE(fs::exists(deck / "in.pack"));
  EXPECT_NE(result.output.find("cd " + deck.string() + " && mpirun -np 2 lmp -in in.pack"),
            std::string::npos)
      << result.output;
  std::ifstream script(deck / "in.pack");
  std::stringstream text;
  text << script.rdbuf();
  // The paper's pour: 2000 spheres into R = 10 cm at 10 us for 3 s. The deck starts from the
  // first batch bouncecal's engine places and pours the rest: 2000 in all.
  EXPECT_NE(text.str().find("read_data       start.data"), std::string::npos) << text.str();
  std::stringstream data;
  data << std::ifstream(deck / "start.data").rdbuf();
  long started = 0, poured = 0;
  ASSERT_EQ(std::sscanf(data.str().c_str() + data.str().find('\n'), "%ld atoms", &started), 1)
      << data.str().substr(0, 300);
  const std::string pour = "fix             pour all pour ";
  const auto at = text.str().find(pour);
  if (at != std::string::npos) poured = std::stol(text.str().substr(at + pour.size()));
  EXPECT_GT(started, 0);
  EXPECT_EQ(started + poured, 2000) << started << " read + " << poured << " poured";
  EXPECT_NE(text.str().find("zcylinder 0.1"), std::string::npos);
  // The rest are poured after the scene's 0.1 s batch interval: 3 s in two runs.
  EXPECT_NE(text.str().find("run             10000\n"), std::string::npos) << text.str();
  EXPECT_NE(text.str().find("run             290000\n"), std::string::npos) << text.str();
}

TEST_F(ExportCli, TwoDimensionalSceneWithLocalDampingIsABadOptionNamingTheKey) {
  // 2D boxes are exported (from their start positions), but the literal reading of paper 004 uses
  // Cundall's local damping, which neither engine's hooke models have (its van der Waals, refused
  // first, is switched off here).
  auto json = nlohmann::json::parse(
      std::ifstream(SourceDir() / "samples/scenes/paper004_disks_friction_vdw_literal.json"));
  json["physics"]["van_der_waals"] = false;
  const fs::path scene = folder_ / "literal.json";
  std::ofstream(scene) << json.dump();
  const auto result = RunBouncecal("export --material " + Card() + " --engine lammps --scene " +
                                   scene.string() + " -o " + (folder_ / "deck").string());
  EXPECT_EQ(result.exit_status, 3) << result.output;
  EXPECT_NE(result.output.find("physics.local_damping"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(folder_ / "deck")) << "nothing written, not even the folder, on error";
}

TEST_F(ExportCli, TwoDimensionalDeckIsWrittenForLammpsOnly) {
  auto json = nlohmann::json::parse(
      std::ifstream(SourceDir() / "samples/scenes/paper004_disks_frictionless.json"));
  json["physics"]["local_damping"] = false;
  json["physics"]["stop_at_first_contact"] = false;
  const fs::path scene = folder_ / "disks.json";
  std::ofstream(scene) << json.dump();
  // The scene's own soft spring: the 1 cm ball's k = 1e7 N/m is unstable for 100 um disks at 1 us.
  const std::string card = (folder_ / "soft.json").string();
  std::ofstream(card) << R"({"format": "bouncecal-material/1",
    "contact_law": {"law": "linear-dashpot",
                    "parameters": {"stiffness_n_per_m": 100, "damping_ratio": 0.1}},
    "ball": {"diameter_m": 1e-4, "density_kg_per_m3": 7860}})";
  const auto refused = RunBouncecal("export --material " + card + " --engine liggghts --scene " +
                                    scene.string() + " -o " + (folder_ / "refused").string());
  EXPECT_EQ(refused.exit_status, 3) << refused.output;
  EXPECT_NE(refused.output.find("LAMMPS only"), std::string::npos) << refused.output;

  const fs::path deck = folder_ / "deck";
  const auto result = RunBouncecal("export --material " + card + " --engine lammps --scene " +
                                   scene.string() + " -o " + deck.string());
  ASSERT_EQ(result.exit_status, 0) << result.output;
  std::stringstream text;
  text << std::ifstream(deck / "in.pack").rdbuf();
  for (const char* line :
       {"dimension       2", "read_data       start.data", "fix             plane all enforce2d",
        "yplane 0 0.002", "xplane 0 0.002", "vector 0 -1 0"}) {
    EXPECT_NE(text.str().find(line), std::string::npos) << line << "\n" << text.str();
  }
  // The start is the scene's own: 240 disks at rest, in the scene's coordinates.
  std::stringstream data;
  data << std::ifstream(deck / "start.data").rdbuf();
  EXPECT_NE(data.str().find("240 atoms"), std::string::npos) << data.str().substr(0, 300);
}

TEST_F(ExportCli, HelpShowsAnExample) {
  const auto result = RunBouncecal("export --help");
  EXPECT_EQ(result.exit_status, 0);
  EXPECT_NE(result.output.find("Example:"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("--engine lammps"), std::string::npos) << result.output;
}

TEST_F(ExportCli, ExportCheckOfAFolderWithoutDeckRecordIsAnInputFileError) {
  const auto result = RunBouncecal("export-check " + folder_.string());
  EXPECT_EQ(result.exit_status, 2) << result.output;
  EXPECT_NE(result.output.find("deck.json"), std::string::npos) << result.output;
  EXPECT_NE(RunBouncecal("export-check --help").output.find("Example:"), std::string::npos);
}

TEST_F(ExportCli, MissingCardIsAnInputFileError) {
  const auto result = RunBouncecal("export --material " + (folder_ / "none.json").string() +
                                   " --engine lammps -o " + (folder_ / "deck").string());
  EXPECT_EQ(result.exit_status, 2) << result.output;
  EXPECT_NE(result.output.find("none.json"), std::string::npos) << result.output;
}

// The law is part of the card file: out of range is a malformed input file (status 2).
TEST_F(ExportCli, OutOfRangeLawParameterIsABadInputFileNamingFileAndKey) {
  WriteCard(R"({"law": "walton-braun", "parameters": {"gamma_n": 2}})");
  const auto result = RunBouncecal("export --material " + Card() + " --engine lammps -o " +
                                   (folder_ / "d").string());
  EXPECT_EQ(result.exit_status, 2) << result.output;
  EXPECT_NE(result.output.find("card.json: contact_law"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("gamma_n"), std::string::npos) << result.output;
}

TEST_F(ExportCli, UnknownEngineAndOutOfRangeOptionsAreUsageErrors) {
  const std::string base = "export --material " + Card() + " -o " + (folder_ / "d").string();
  EXPECT_EQ(RunBouncecal(base + " --engine gromacs").exit_status, 3);
  EXPECT_EQ(RunBouncecal(base + " --engine lammps --bounces 0").exit_status, 3);
  EXPECT_EQ(RunBouncecal(base + " --engine lammps --drop-height-m -1").exit_status, 3);
}

TEST_F(ExportCli, UnwritableOutputIsAnOutputError) {
  std::ofstream(folder_ / "a_file") << "x";
  const auto result = RunBouncecal("export --material " + Card() + " --engine lammps -o " +
                                   (folder_ / "a_file" / "deck").string());
  EXPECT_EQ(result.exit_status, 4) << result.output;
}

}  // namespace
}  // namespace bouncecal::testing
