#ifndef BOUNCECAL_CALIBRATE_CONTENT_HASH_H_
#define BOUNCECAL_CALIBRATE_CONTENT_HASH_H_

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

namespace bouncecal::calibrate {

// 64-bit FNV-1a (Fowler, Noll, Vo; offset basis 0xcbf29ce484222325, prime 0x100000001b3). It is
// an identity check for the recordings a material card was fitted to (did the file change?),
// not a cryptographic hash: chosen because it is ten lines, has published test vectors and needs
// no dependency. Feed data in any chunking: Update(a); Update(b) equals Update(a + b).
class Fnv1a64 {
 public:
  static constexpr std::uint64_t kOffsetBasis = 0xcbf29ce484222325ULL;
  static constexpr std::uint64_t kPrime = 0x100000001b3ULL;

  void Update(std::span<const std::byte> data);
  void Update(std::string_view text);
  std::uint64_t digest() const { return state_; }

 private:
  std::uint64_t state_ = kOffsetBasis;
};

// "fnv1a64:" followed by 16 lower-case hex digits of the file's bytes. Reads in blocks, so
// an hour-long recording costs no memory. Throws InputError when the file cannot be read.
std::string FileContentHash(const std::filesystem::path& path);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_CONTENT_HASH_H_
