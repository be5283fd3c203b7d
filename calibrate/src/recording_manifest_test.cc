#include "bouncecal/calibrate/recording_manifest.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "bouncecal/error.h"
#include "bouncecal/option_error.h"
#include "bouncecal/testing/scratch_folder.h"

namespace bouncecal::calibrate {
namespace {

using bouncecal::testing::ScratchFolder;

class RecordingManifestTest : public ::testing::Test {
 protected:
  std::filesystem::path Write(const std::string& name, const std::string& text) {
    const auto path = folder_ / name;
    std::ofstream(path) << text;
    return path;
  }

  const ScratchFolder folder_;
};

TEST_F(RecordingManifestTest, CsvGivesEachRecordingItsHeightFromTheManifestsFolder) {
  const auto path = Write("drops.csv",
                          "# Fr4nci's protocol\n"
                          "recording,drop_height_m,drop_height_uncertainty_m,ball\n"
                          "a.wav,2.5,0.01,tennis\n"
                          "\n"
                          "\"b, second.wav\",1.5,,\n"
                          "/abs/c.wav,,,\n");
  const auto entries = ReadRecordingManifest(path);
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_EQ(entries[0].recording, folder_ / "a.wav");
  EXPECT_EQ(entries[0].drop_height_m, 2.5);
  EXPECT_EQ(entries[0].drop_height_uncertainty_m, 0.01);
  EXPECT_EQ(entries[0].ball, "tennis");
  EXPECT_EQ(entries[1].recording, folder_ / "b, second.wav");
  EXPECT_EQ(entries[1].drop_height_m, 1.5);
  EXPECT_FALSE(entries[1].drop_height_uncertainty_m.has_value());
  EXPECT_EQ(entries[2].recording, std::filesystem::path("/abs/c.wav"));
  EXPECT_FALSE(entries[2].drop_height_m.has_value());
}

TEST_F(RecordingManifestTest, JsonTakesAnArrayOrARecordingsObject) {
  const auto path = Write("drops.json",
                          R"({"recordings": [{"recording": "a.wav", "drop_height_m": 0.2},
                                             {"recording": "b.wav", "drop_height_m": null}]})");
  const auto entries = ReadRecordingManifest(path);
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[0].drop_height_m, 0.2);
  EXPECT_FALSE(entries[1].drop_height_m.has_value());
  const auto array = Write("array.json", R"([{"recording": "a.wav"}])");
  EXPECT_EQ(ReadRecordingManifest(array).size(), 1u);
}

TEST_F(RecordingManifestTest, BadManifestsAreOneLineNamingTheFileAndTheFix) {
  const auto expect_error = [&](const std::string& name, const std::string& text,
                                const std::string& part) {
    const auto path = Write(name, text);
    try {
      ReadRecordingManifest(path);
      ADD_FAILURE() << name << " was accepted";
    } catch (const InputError& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find(path.string()), std::string::npos) << message;
      EXPECT_NE(message.find(part), std::string::npos) << message;
    }
  };
  expect_error("unknown.csv", "recording,height\na.wav,0.2\n", "unknown column 'height'");
  expect_error("negative.csv", "recording,drop_height_m\na.wav,-0.2\n",
               "drop_height_m '-0.2' is not a positive number of metres");
  expect_error("text.csv", "recording,drop_height_m\na.wav,20cm\n", "'20cm'");
  expect_error("empty.csv", "recording,drop_height_m\n", "lists no recording");
  expect_error("sigma.csv", "recording,drop_height_uncertainty_m\na.wav,0.01\n",
               "drop_height_uncertainty_m without drop_height_m");
  expect_error("key.json", R"([{"recording": "a.wav", "height": 0.2}])", "unknown key \"height\"");
  expect_error("type.json", R"([{"recording": "a.wav", "drop_height_m": "0.2"}])", "wrong type");
  EXPECT_THROW(ReadRecordingManifest(folder_ / "missing.csv"), InputError);
}

TEST(PlanRecordings, OneHeightIsEveryRecordingsAndOnePerRecordingIsTakenInOrder) {
  const std::vector<std::filesystem::path> files{"a.wav", "b.wav"};
  const auto all = PlanRecordings(files, {0.2}, {});
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].drop_height_m, 0.2);
  EXPECT_EQ(all[1].drop_height_m, 0.2);
  const auto each = PlanRecordings(files, {0.2, 0.4}, {0.002});
  EXPECT_EQ(each[0].drop_height_m, 0.2);
  EXPECT_EQ(each[1].drop_height_m, 0.4);
  EXPECT_EQ(each[1].drop_height_uncertainty_m, 0.002);
  const auto none = PlanRecordings(files, {}, {});
  EXPECT_FALSE(none[0].drop_height_m.has_value());
}

TEST(PlanRecordings, AMismatchedCountIsRefusedNamingTheField) {
  const std::vector<std::filesystem::path> files{"a.wav", "b.wav", "c.wav"};
  try {
    PlanRecordings(files, {0.2, 0.4}, {});
    ADD_FAILURE() << "two heights for three recordings accepted";
  } catch (const OptionError& error) {
    EXPECT_EQ(error.fields().front(), "drop_height_m");
    EXPECT_NE(std::string(error.what()).find("given 2 times for 3 recordings"), std::string::npos)
        << error.what();
  }
  EXPECT_THROW(PlanRecordings(files, {}, {0.01}), OptionError);
  EXPECT_THROW(PlanRecordings(files, {0.2}, {}, "m.csv"), OptionError);
}

}  // namespace
}  // namespace bouncecal::calibrate

namespace bouncecal::calibrate {
namespace {

// The check the command line and Python make before reading a file: each bad value is refused
// naming its field, whichever position it holds.
TEST(ValidateDropHeights, EachHeightAndUncertaintyIsCheckedNamingItsField) {
  EXPECT_NO_THROW(ValidateDropHeights({0.2, 1.5}, {0.0, 0.005}));
  EXPECT_NO_THROW(ValidateDropHeights({}, {}));
  for (const double bad : {0.0, -1.0, 1e3, std::nan("")}) {
    try {
      ValidateDropHeights({0.2, bad}, {});
      ADD_FAILURE() << "height " << bad << " was accepted";
    } catch (const OptionError& error) {
      EXPECT_EQ(error.fields(), std::vector<std::string>{"drop_height_m"});
    }
  }
  for (const double bad : {-1e-3, std::nan(""), std::numeric_limits<double>::infinity()}) {
    try {
      ValidateDropHeights({0.2}, {0.001, bad});
      ADD_FAILURE() << "uncertainty " << bad << " was accepted";
    } catch (const OptionError& error) {
      EXPECT_EQ(error.fields(), std::vector<std::string>{"drop_height_uncertainty_m"});
    }
  }
}

}  // namespace
}  // namespace bouncecal::calibrate
