#include "detector/impact_sample_keeper.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

namespace bouncecal::audio {

ImpactSampleKeeper::ImpactSampleKeeper(std::int64_t before_samples, std::int64_t after_samples)
    : before_(before_samples), after_(after_samples) {}

namespace {

// history[from, to) appended to samples, in the ring's (at most two) contiguous runs.
void AppendHeld(const SampleHistory<float>& history, std::int64_t from, std::int64_t to,
                std::vector<float>& samples) {
  while (from < to) {
    const auto run = history.Contiguous(from, static_cast<std::size_t>(to - from));
    samples.insert(samples.end(), run.begin(), run.end());
    from += static_cast<std::int64_t>(run.size());
  }
}

}  // namespace

std::int64_t ImpactSampleKeeper::CollectedEnd() const {
  const SampleStretch& newest = stretches_.back();
  return newest.begin + static_cast<std::int64_t>(newest.samples.size());
}

void ImpactSampleKeeper::Keep(double onset_sample, const SampleHistory<float>& history) {
  const auto at = static_cast<std::int64_t>(std::floor(onset_sample));
  // What the history no longer holds is lost; the response timing reads it as silence, which
  // leaves that impact unaligned rather than wrong.
  const std::int64_t begin = std::max({std::int64_t{0}, at - before_, history.begin()});
  const std::int64_t end = at + after_ + 1;
  const std::int64_t held_end = history.end();
  if (stretches_.empty() || begin > CollectedEnd()) {
    SampleStretch stretch;
    stretch.begin = begin;
    // The whole stretch at once: Append then only copies into it, never reallocates.
    stretch.samples.reserve(static_cast<std::size_t>(end - begin));
    AppendHeld(history, begin, std::min(end, held_end), stretch.samples);
    stretches_.push_back(std::move(stretch));
    wanted_end_ = end;
    return;
  }
  // Overlaps the newest stretch: grow it at either end from what the history holds.
  SampleStretch& newest = stretches_.back();
  if (begin < newest.begin) {
    std::vector<float> earlier;
    AppendHeld(history, begin, newest.begin, earlier);
    newest.samples.insert(newest.samples.begin(), earlier.begin(), earlier.end());
    newest.begin = begin;
  }
  AppendHeld(history, CollectedEnd(), std::min(end, held_end), newest.samples);
  wanted_end_ = std::max(wanted_end_, end);
}

void ImpactSampleKeeper::Append(std::int64_t block_begin, std::span<const float> block) {
  if (stretches_.empty()) return;
  const std::int64_t collected = CollectedEnd();
  if (collected >= wanted_end_) return;
  // The newest stretch is kept current with the stream, so the block continues it.
  assert(collected == block_begin);
  (void)block_begin;
  const auto count = static_cast<std::size_t>(
      std::min<std::int64_t>(wanted_end_ - collected, static_cast<std::int64_t>(block.size())));
  auto& samples = stretches_.back().samples;
  samples.insert(samples.end(), block.begin(), block.begin() + static_cast<std::ptrdiff_t>(count));
}

std::vector<SampleStretch> ImpactSampleKeeper::Take() {
  wanted_end_ = 0;
  return std::exchange(stretches_, {});
}

}  // namespace bouncecal::audio
