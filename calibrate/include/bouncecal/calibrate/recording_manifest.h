#ifndef BOUNCECAL_CALIBRATE_RECORDING_MANIFEST_H_
#define BOUNCECAL_CALIBRATE_RECORDING_MANIFEST_H_

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace bouncecal::calibrate {

// One recording of a protocol of several drops, with what is known of its geometry.
struct ManifestEntry {
  std::filesystem::path recording;
  std::optional<double> drop_height_m;              // release height of this recording's drops, m
  std::optional<double> drop_height_uncertainty_m;  // one sigma, m
  std::string ball;  // a ball preset name, empty when the manifest gives none
};

// Reads a manifest of recordings (docs/calibration.md, "Several drops and heights"):
//  - CSV with a header naming its columns: recording (required), drop_height_m,
//    drop_height_uncertainty_m, ball; '#' comments and blank lines skipped; an empty cell is
//    "not given";
//  - JSON: an array of objects with those keys, or {"recordings": [...]}.
// Relative recording paths are taken from the manifest's folder. Throws InputError naming the
// file and line or entry for unknown columns or keys, a missing recording, a height that is not
// a positive number of metres, or an empty manifest.
std::vector<ManifestEntry> ReadRecordingManifest(const std::filesystem::path& path);

// Throws OptionError naming drop_height_m unless every height is in (0, 1000) m, and naming
// drop_height_uncertainty_m unless every uncertainty is a finite value >= 0 m: the front ends'
// check of heights given once or once per recording, before any file is read.
void ValidateDropHeights(const std::vector<double>& drop_heights_m,
                         const std::vector<double>& drop_height_uncertainties_m);

// The recordings of one run with their heights: `recordings` with drop_height_m given once (every
// recording, and every drop in it, was released from that height) or once per recording in
// order, and drop_height_uncertainty_m the same way (once, or once per recording); or, when
// `manifest` is not empty, the manifest's entries (then `recordings` and the heights must be
// empty). Throws OptionError naming the fields when the counts do not match, and InputError for
// a bad manifest.
std::vector<ManifestEntry> PlanRecordings(const std::vector<std::filesystem::path>& recordings,
                                          const std::vector<double>& drop_heights_m,
                                          const std::vector<double>& drop_height_uncertainties_m,
                                          const std::filesystem::path& manifest = {});

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_RECORDING_MANIFEST_H_
