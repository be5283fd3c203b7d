#ifndef BOUNCECAL_CALIBRATE_IMPACT_TIMES_H_
#define BOUNCECAL_CALIBRATE_IMPACT_TIMES_H_

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bouncecal/calibrate/restitution.h"

namespace bouncecal::calibrate {

// One measured bounce sequence: the input of every fit. Onsets are seconds from any fixed origin
// (a constant offset cancels in every interval).
struct MeasuredSequence {
  std::string source;  // file name, with "#k" (1-based sequence number) when a file holds several
  std::filesystem::path path;  // the file it came from (hashed into material cards)
  std::vector<TimedImpact> impacts;
  // FileContentHash of `path` when read through LoadSequences, else empty; named in the warning
  // when the same content is given twice.
  std::string content_hash;
  // For a sequence from a lossy recording: its codec and the timing error (one sigma, s) already
  // added in quadrature to every onset uncertainty not timed from the impact's response, so a
  // caller can say why they are wide.
  std::string lossy_codec;
  double codec_timing_uncertainty_s = 0;
  // This sequence's own release height and its one-sigma uncertainty, m (a protocol of drops from
  // several heights); unset: FitOptions' height, if any, applies.
  std::optional<double> drop_height_m;
  double drop_height_uncertainty_m = 0;
};

struct ImpactTimesOptions {
  // One-sigma onset uncertainty assumed where the file gives none: 10 us, the onset-timing
  // target of the audio stage on clean 48 kHz recordings (half a sample).
  double default_uncertainty_s = 10e-6;
  // Sequences with fewer impacts carry no restitution and are skipped.
  int min_impacts = 3;
  // OptionError unless default_uncertainty_s is a positive, finite number of seconds. It names
  // the option as both front ends call it (onset_uncertainty_s, --onset-uncertainty-s).
  void Validate() const;
};

// Reads impact times from
//  - a CSV file: one impact per line, columns onset_s[,onset_uncertainty_s[,sequence]]; an
//    optional header line, '#' comments and blank lines are skipped; rows with the same sequence
//    number (any integer) form one sequence, otherwise the whole file is one sequence. Where a
//    header names the sequence column, a row with it blank is in no sequence; header columns
//    file and channel keep each recording's sequences apart, and incoming_flight_uncertainty_s
//    gives each flight's own uncertainty (TimedImpact): the rows of `bouncecal analyze --csv`;
//  - the JSON `bouncecal analyze --json` writes ("format": "bouncecal-analysis/1",
//    docs/json.md): per entry of "recordings", "sequences": [{"onsets_s": [...],
//    "incoming_flight_uncertainty_s": [...]}, ...] and "impacts": [{"onset_s",
//    "onset_uncertainty_s"}] giving each onset's uncertainty. The shapes
//    written before the format field (one such entry, or an array of them) are still read; a
//    document of another format, or of a later version, is an InputError saying so.
// The format is chosen by the extension (.csv / .json). Throws InputError naming the file and the
// line or key for unreadable or malformed content, or when no sequence has min_impacts impacts.
std::vector<MeasuredSequence> ReadImpactTimes(const std::filesystem::path& path,
                                              const ImpactTimesOptions& options = {});

// True when ReadImpactTimes understands the file's extension.
bool IsImpactTimesFile(const std::filesystem::path& path);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_IMPACT_TIMES_H_
