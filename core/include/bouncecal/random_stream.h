#ifndef BOUNCECAL_RANDOM_STREAM_H_
#define BOUNCECAL_RANDOM_STREAM_H_

#include <cmath>
#include <cstdint>
#include <numbers>

namespace bouncecal {

// A seeded pseudo-random stream (xoshiro256**, Blackman & Vigna 2018) whose state is derived
// from (seed, stream, substream) with SplitMix64 (Steele, Lea & Flood 2014), so each part of a
// computation (replicate r, recording k, ...) draws from its own independent sequence whichever
// thread runs it. The standard library's distributions (std::normal_distribution, ...) are
// implementation-defined, so the draws here are written out: the same seed gives the same numbers
// with every standard library, which the byte-identical outputs of the README rely on.
// Header-only and small on purpose: it is the one stream of the project (a scene's insertion
// draws straight from SplitMix64 below, a sequence its shipped packs are pinned to).
class RandomStream {
 public:
  RandomStream(std::uint64_t seed, std::uint64_t stream, std::uint64_t substream = 0) {
    std::uint64_t mix = seed ^ (stream * 0x9E3779B97F4A7C15ULL) ^
                        (substream * 0xD1B54A32D192ED03ULL + 0x632BE59BD9B4E019ULL);
    for (std::uint64_t& word : state_) word = SplitMix64(mix);
  }

  std::uint64_t NextBits() {
    const std::uint64_t result = Rotl(state_[1] * 5, 7) * 9;
    const std::uint64_t t = state_[1] << 17;
    state_[2] ^= state_[0];
    state_[3] ^= state_[1];
    state_[1] ^= state_[2];
    state_[0] ^= state_[3];
    state_[2] ^= t;
    state_[3] = Rotl(state_[3], 45);
    return result;
  }

  // Uniform in [0, 1) with 53 random bits.
  double Uniform() { return static_cast<double>(NextBits() >> 11) * 0x1.0p-53; }

  // Standard normal (Box-Muller; the second value of each pair is kept for the next call).
  double Gaussian() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - Uniform();  // (0, 1]: log stays finite
    const double u2 = Uniform();
    const double radius = std::sqrt(-2.0 * std::log(u1));
    spare_ = radius * std::sin(2.0 * std::numbers::pi * u2);
    has_spare_ = true;
    return radius * std::cos(2.0 * std::numbers::pi * u2);
  }

  // One step of SplitMix64 on `x` (advanced in place): also a good hash of a counter.
  static std::uint64_t SplitMix64(std::uint64_t& x) {
    std::uint64_t z = (x += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }

 private:
  static std::uint64_t Rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

  std::uint64_t state_[4];
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace bouncecal

#endif  // BOUNCECAL_RANDOM_STREAM_H_
