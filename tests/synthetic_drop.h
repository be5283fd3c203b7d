#ifndef BOUNCECAL_TESTS_SYNTHETIC_DROP_H_
#define BOUNCECAL_TESTS_SYNTHETIC_DROP_H_

#include <cstdint>
#include <filesystem>

#include "bouncecal/audio/synthesize.h"
#include "bouncecal/audio/write_recording.h"

namespace bouncecal::testing {

// A steel ball (e = 0.648, the paper's eta = 0.58) dropped from height_m onto a plate whose
// modes ring for tens of ms (a plate resting on a table), without noise, written to `path` as a
// 48 kHz PCM16 WAV. With the synthesiser's free-plate default, later bounces are quieter than
// the tail of earlier ones in every band; see docs/recordings.md.
inline std::filesystem::path WriteTableDampedDrop(const std::filesystem::path& path,
                                                  double height_m, std::uint64_t seed) {
  audio::SynthesisOptions options;
  options.drop.drop_height_m = height_m;
  for (auto& mode : options.modes) mode.decay_s *= 0.1;
  options.noise = audio::NoiseOptions{};
  options.seed = seed;
  audio::WriteRecording(path, audio::SynthesizeBounces(options).channels);
  return path;
}

}  // namespace bouncecal::testing

#endif  // BOUNCECAL_TESTS_SYNTHETIC_DROP_H_
