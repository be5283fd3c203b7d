// bouncecal synth end to end: the written file, the truth CSV and the exit statuses.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "bouncecal/audio/impact_csv.h"
#include "bouncecal/audio/synthesize.h"
#include "bouncecal/testing/file_text.h"
#include "bouncecal/testing/scratch_folder.h"
#include "cli_runner.h"

namespace bouncecal::testing {
namespace {

TEST(SynthCli, WritesTheRecordingAndATruthMatchingTheLibrary) {
  const auto dir = ScratchSubfolder("truth");
  const auto result =
      RunBouncecal("synth -o " + (dir / "s.wav").string() + " --truth " + (dir / "s.csv").string() +
                   " --drop-height-m 0.3 --restitution 0.8 --snr-db 30 "
                   "--knock-s 0.1 --channels 2 --channel-delay-s 0.00025 "
                   "--sample-rate-hz 44100 --format pcm24 --seed 3");
  ASSERT_EQ(result.exit_status, 0) << result.output;
  EXPECT_NE(result.output.find("44100 Hz, 2 channel(s)"), std::string::npos) << result.output;
  const std::string truth = ReadFileText(dir / "s.csv");
  EXPECT_NE(truth.find(",knock,-1"), std::string::npos) << truth;

  audio::SynthesisOptions options;
  options.drop.drop_height_m = 0.3;
  options.drop.restitution.constant = 0.8;
  const auto expected = audio::PlanBallImpacts(options);
  const auto written = audio::ParseImpactCsv(truth, "s.csv");
  ASSERT_EQ(written.size(), expected.size());
  // 9 decimals in the CSV: 0.5 ns.
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_NEAR(written[i].onset_s, expected[i].onset_s, 5e-10);
  }
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir),
                          std::filesystem::directory_iterator()),
            2);  // no temporaries left behind
}

TEST(SynthCli, ImpactTimesFromATruthFileReproduceTheOnsets) {
  const auto dir = ScratchSubfolder("impacts");
  std::ofstream(dir / "in.csv") << "onset_s,impact_speed_mps\n0.2,1.5\n0.45,1.0\n0.6,0.7\n";
  const auto result =
      RunBouncecal("synth -o " + (dir / "x.wav").string() + " --impact-times " +
                   (dir / "in.csv").string() + " --truth " + (dir / "x.csv").string());
  ASSERT_EQ(result.exit_status, 0) << result.output;
  const auto written = audio::ParseImpactCsv(ReadFileText(dir / "x.csv"), "x.csv");
  ASSERT_EQ(written.size(), 3u);
  EXPECT_NEAR(written[1].onset_s, 0.45, 5e-10);
  EXPECT_NEAR(written[2].impact_speed_mps, 0.7, 5e-7);  // speeds have 6 decimals
}

TEST(SynthCli, BadOptionsMissingInputsAndUnwritableOutputsMapToExitStatuses) {
  const auto dir = ScratchSubfolder("errors");
  const std::string out = " -o " + (dir / "x.wav").string();
  auto result = RunBouncecal("synth" + out + " --restitution 1.3");
  EXPECT_EQ(result.exit_status, 3) << result.output;
  EXPECT_NE(result.output.find("drop.restitution.constant"), std::string::npos) << result.output;
  result = RunBouncecal("synth" + out + " --impact-times " + (dir / "none.csv").string());
  EXPECT_EQ(result.exit_status, 2) << result.output;
  result = RunBouncecal("synth -o " + (dir / "missing" / "x.wav").string());
  EXPECT_EQ(result.exit_status, 4) << result.output;
  result = RunBouncecal("synth" + out + " --echo-delay-s 0.009");  // gain missing
  EXPECT_EQ(result.exit_status, 3) << result.output;
  result = RunBouncecal("synth" + out + " --agc-target-dbfs -20");  // no gain stage
  EXPECT_EQ(result.exit_status, 3) << result.output;
  result = RunBouncecal("synth" + out + " --limiter-gain-db 70");
  EXPECT_EQ(result.exit_status, 3) << result.output;
  EXPECT_NE(result.output.find("limiter.gain_db"), std::string::npos) << result.output;
  result = RunBouncecal("synth -o " + (dir / "x.flac").string() + " --format float");
  EXPECT_EQ(result.exit_status, 3) << result.output;
  EXPECT_TRUE(std::filesystem::is_empty(dir));  // nothing written by any failed run
}

TEST(SynthCli, AdcChainAndContactClickAreAppliedAndDescribedInTheSummaryAndTruth) {
  const auto dir = ScratchSubfolder("adc");
  const auto result =
      RunBouncecal("synth -o " + (dir / "a.wav").string() + " --truth " + (dir / "a.csv").string() +
                   " --adc linear-phase --click-gain 0.2 --sample-rate-hz 16000 "
                   "--format float --seed 4");
  ASSERT_EQ(result.exit_status, 0) << result.output;
  // 16 kHz: automatic oversampling 24 (384 kHz), the default band edges and stop band.
  EXPECT_NE(result.output.find("recording chain: linear-phase anti-aliasing FIR"),
            std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("at 384000 Hz (24 x 16000 Hz)"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("passband to 7256 Hz"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("contact click: "), std::string::npos) << result.output;
  const std::string truth = ReadFileText(dir / "a.csv");
  EXPECT_EQ(truth.rfind("# recording chain: linear-phase", 0), 0u) << truth;
  EXPECT_NE(truth.find("# contact click: "), std::string::npos) << truth;

  // The same render through the library: the CLI adds nothing of its own.
  audio::SynthesisOptions options;
  options.sample_rate_hz = 16000;
  options.click_gain = 0.2;
  options.chain = audio::RecordingChain{};
  options.seed = 4;
  const auto expected = audio::SynthesizeBounces(options);
  EXPECT_EQ(truth, audio::TruthCsv(expected));

  // --adc-* without --adc, and an oversampling of 1, are refused (exit 3) and write nothing.
  const auto lone = RunBouncecal("synth -o " + (dir / "b.wav").string() + " --adc-oversampling 4");
  EXPECT_EQ(lone.exit_status, 3) << lone.output;
  const auto one = RunBouncecal("synth -o " + (dir / "c.wav").string() +
                                " --adc minimum-phase --adc-oversampling 1");
  EXPECT_EQ(one.exit_status, 3) << one.output;
  EXPECT_NE(one.output.find("chain.oversampling = 1"), std::string::npos) << one.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "b.wav"));
  EXPECT_FALSE(std::filesystem::exists(dir / "c.wav"));
}

}  // namespace
}  // namespace bouncecal::testing
