#ifndef BOUNCECAL_AUDIO_IMPACT_CSV_H_
#define BOUNCECAL_AUDIO_IMPACT_CSV_H_

#include <filesystem>
#include <string_view>
#include <vector>

#include "bouncecal/audio/synthesize.h"

namespace bouncecal::audio {

// Reads explicit impacts for SynthesisOptions::impacts from CSV text: one impact per line as
// "onset_s,impact_speed_mps[,...]". An optional header line names the columns; when it has a
// "kind" column (as TruthCsv writes), only rows of kind ball_impact are taken, and a "drop"
// column sets ImpactSpec::drop_index, so a truth file can be fed back. Blank lines and lines
// starting with '#' are skipped. Throws InputError naming the source and line for anything else
// (missing column, non-numeric or non-finite value, speed <= 0, onset < 0) or when no impact is
// found.
std::vector<ImpactSpec> ParseImpactCsv(std::string_view text, std::string_view source_name);

// ParseImpactCsv on a file; throws InputError when it cannot be read.
std::vector<ImpactSpec> ReadImpactCsv(const std::filesystem::path& path);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_IMPACT_CSV_H_
