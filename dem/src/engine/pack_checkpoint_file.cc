#include "engine/pack_checkpoint_file.h"

#include <fmt/format.h>

#include <cstring>

#include "bouncecal/error.h"
#include "engine/checkpoint_bytes.h"

namespace bouncecal::dem::scene {
namespace {

constexpr char kMagic[8] = {'B', 'C', 'P', 'A', 'C', 'K', '\r', '\n'};
// Read back in the host's order: a file from a machine of the other byte order reads as
// 0x04030201 and is refused rather than misread.
constexpr std::uint32_t kByteOrderMark = 0x01020304;

}  // namespace

std::string WritePackCheckpointFrame(const PackCheckpointFrame& frame) {
  ByteWriter out;
  out.mutable_bytes().append(kMagic, sizeof(kMagic));
  out.Put(kByteOrderMark);
  out.Put(kPackCheckpointVersion);
  out.Put(frame.dimension);
  out.Put(frame.fingerprint);
  out.Put(frame.step);
  out.Put(frame.time_s);
  out.PutString(frame.payload);
  out.Put(Fnv1a(frame.payload));
  return out.bytes();
}

PackCheckpointFrame ReadPackCheckpointFrame(std::string_view bytes, const std::string& name) {
  if (bytes.size() < sizeof(kMagic) || std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0) {
    throw InputError(fmt::format(
        "{}: is not a bouncecal pack checkpoint (no BCPACK header); give the checkpoint file a "
        "run with `checkpoint_every_s` or an interrupted run wrote",
        name));
  }
  ByteReader in(bytes.substr(sizeof(kMagic)), name);
  if (in.Get<std::uint32_t>() != kByteOrderMark) {
    in.Fail("it was written on a machine of the other byte order");
  }
  const auto version = in.Get<std::uint32_t>();
  if (version != kPackCheckpointVersion) {
    throw InputError(fmt::format(
        "{}: is a checkpoint of format version {}, this bouncecal reads version {}; resume it "
        "with the bouncecal that wrote it, or start the run again",
        name, version, kPackCheckpointVersion));
  }
  PackCheckpointFrame frame;
  frame.dimension = in.Get<std::uint32_t>();
  frame.fingerprint = in.Get<std::uint64_t>();
  frame.step = in.Get<std::int64_t>();
  frame.time_s = in.Get<double>();
  frame.payload = in.GetString();
  const auto checksum = in.Get<std::uint64_t>();
  if (in.left() != 0) in.Fail("it has bytes after its end");
  if (checksum != Fnv1a(frame.payload)) in.Fail("its checksum does not match (corrupt)");
  return frame;
}

}  // namespace bouncecal::dem::scene
