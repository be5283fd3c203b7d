#ifndef BOUNCECAL_DEM_ENGINE_PACK_CHECKPOINT_FILE_H_
#define BOUNCECAL_DEM_ENGINE_PACK_CHECKPOINT_FILE_H_

// The envelope of a pack checkpoint (docs/scenes.md, "Checkpoints"): a header that says what the
// file is, which format version, which set-up it belongs to and how long its payload is, then
// the payload (packing.cc writes and reads it), then a checksum of the payload. Reading it
// refuses, with one line naming the file, anything that is not a whole checkpoint of this
// version.

#include <cstdint>
#include <string>
#include <string_view>

namespace bouncecal::dem::scene {

// Raised whenever the payload's layout changes; an older or newer file is refused by number.
// 2: the pending kick of a run stopped inside a block, and the wall time so far.
inline constexpr std::uint32_t kPackCheckpointVersion = 2;

struct PackCheckpointFrame {
  std::uint32_t dimension = 3;
  std::uint64_t fingerprint = 0;  // of the set-up: scene dynamics and the options that steer it
  std::int64_t step = 0;
  double time_s = 0;
  std::string payload;
};

std::string WritePackCheckpointFrame(const PackCheckpointFrame& frame);

// Throws InputError "<name>: <problem>; <what to do>" when `bytes` are not a pack checkpoint, are
// of another version, another byte order, cut short or damaged (checksum).
PackCheckpointFrame ReadPackCheckpointFrame(std::string_view bytes, const std::string& name);

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_ENGINE_PACK_CHECKPOINT_FILE_H_
