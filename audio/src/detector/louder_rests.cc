#include "detector/louder_rests.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

namespace bouncecal::audio {
namespace {

// How many rise thresholds louder than the kept onset's own sound a rest must be to take the
// onset. In any file: two, the level below which the bounce sequence never weighs a merged sound
// as a member's alternative either (kMaxQuieterDb, merged_alternatives.cc): a precursor click 9-14
// dB under its bounce rings into it, and which of the two a member is timed on is for the
// sequence to weigh across its members. With one threshold in every file,
// silent_wrong_sweep.py --precursors seed 9 #159 (clicks 13 dB and 5.9 ms before each bounce)
// moved three members to a part of their sound 2.9 ms in, 10 dB louder than the click, and the
// sequence then sat on three different sounds: eta-bar 8.2 sigmas off (2.5 before).
constexpr double kRisesInAnyFile = 2.0;
// Within a codec's frame, one: the merger's own test for a precursor kept apart
// (event_merger.cc), since there the codec's noise, not the sound, may have joined the two.
constexpr double kRisesWithinACodecFrame = 1.0;

}  // namespace

// A transform codec spreads the quantisation noise of a loud attack over the block before it
// (pre-echo, up to a frame ahead), and that noise can rise into the attack without a break: the
// merger then keeps the onset where the rise began and counts the attack as the rest of its
// sound, whatever its level. Where such a rest follows within one frame, either onset may be the
// impact's: half their distance goes into its uncertainty in quadrature, as the response timing
// does where it and the detector disagree (a later alignment, if any, still decides). Where the
// rest is louder by the full rise threshold, it is the onset. basketball.wav as MP3 128k: a -27
// dBFS sound 8.1 ms before the first bounce, kept apart in the WAV (the bounce's first 8 ms 18.7
// dB louder), rose into the bounce in the copy and took its onset: eta-bar 0.3000 against the
// WAV's 0.2937, stated +- 0.0003 (13 sigmas) before the widening and +- 0.0051 with it. Taking the
// louder rest: 0.2938 +- 0.0032.
// Without a codec a faint sound can still rise into a bounce: a ball's or a hand's noise, or the
// plate touched, milliseconds before the contact. alessia rimbalzi's Palla-audio.wav: its 3rd
// bounce was timed on a -54 dBFS sound 8.4 ms before it, the bounce 29.6 dB louder as its rest
// (+-0.76 ms stated; every codec copy of the file timed the bounce itself), and its eta_k read
// 0.431 / 0.353 / 0.386 where the copies read 0.417 / 0.390 / 0.364.
void TakeLouderRestsAsImpacts(DetectionResult& detection, std::optional<double> codec_frame_s,
                              double rise_threshold_db) {
  for (MergedEvent& merged : detection.merged) {
    const double gap_s = merged.time_s - merged.winner_s;
    if (!merged.rest_of_sound || !(merged.level_difference_db < 0) || !(gap_s > 0)) continue;
    const bool within_a_codec_frame = codec_frame_s && gap_s <= *codec_frame_s;
    const double rises = within_a_codec_frame ? kRisesWithinACodecFrame : kRisesInAnyFile;
    const bool rest_is_the_hit = -merged.level_difference_db >= rises * rise_threshold_db;
    if (!rest_is_the_hit && !within_a_codec_frame) continue;
    // Impacts are in time order, and one that moves stays before the next: a rest lies within
    // min_gap_ms of its kept onset, and the next impact beyond it.
    bool moved = false;
    auto impact = std::lower_bound(
        detection.impacts.begin(), detection.impacts.end(), merged.winner_s,
        [](const Impact& candidate, double onset_s) { return candidate.onset_s < onset_s; });
    for (; impact != detection.impacts.end() && impact->onset_s == merged.winner_s; ++impact) {
      if (within_a_codec_frame) {
        impact->onset_uncertainty_s = std::hypot(impact->onset_uncertainty_s, 0.5 * gap_s);
      }
      if (rest_is_the_hit) {
        impact->onset_s = merged.time_s;
        std::swap(impact->peak_dbfs, merged.peak_dbfs);
        moved = true;
      }
    }
    // Another rest of a sound whose impact already moved finds no impact there any more.
    if (!moved) continue;
    char reason[256];
    if (within_a_codec_frame) {
      std::snprintf(reason, sizeof reason,
                    "precursor %.1f ms before the impact at %.5f s, %.1f dB quieter; a lossy "
                    "codec's pre-echo joined them into one rise (merged; half their distance is "
                    "in the impact's uncertainty)",
                    gap_s * 1e3, merged.time_s, -merged.level_difference_db);
    } else {
      std::snprintf(reason, sizeof reason,
                    "precursor %.1f ms before the impact at %.5f s, %.1f dB quieter, that rose "
                    "into it as one sound (merged)",
                    gap_s * 1e3, merged.time_s, -merged.level_difference_db);
    }
    // The precursors and echoes merged into the kept sound now belong to the impact where it
    // moved. Another rest of that sound keeps its old winner and so takes no part: its level
    // was measured against the kept sound, not against the rest that became the impact.
    for (MergedEvent& other : detection.merged) {
      if (&other != &merged && !other.rest_of_sound && other.winner_s == merged.winner_s) {
        other.winner_s = merged.time_s;
      }
    }
    std::swap(merged.time_s, merged.winner_s);
    merged.reason = reason;
    merged.rest_of_sound = false;
    merged.level_difference_db = -merged.level_difference_db;
  }
}

}  // namespace bouncecal::audio
