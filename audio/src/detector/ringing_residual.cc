#include "detector/ringing_residual.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <complex>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>

#include "detector/select_kth.h"

namespace bouncecal::audio {
namespace {

constexpr double kWindowS = 5.3e-3;
constexpr int kMinWindow = 32;
// Hop a third of the window (1.8 ms at 48 kHz). Measured on the free plate: hop 1/4 found
// 134/144 at 1.25x the cost, hop 1/2 132/144 with 5 extras.
constexpr int kHopsPerWindow = 3;
// How far back each bin's reference reaches: longer than the beat period of two modes a
// bin apart (~5 ms) and than a hit's own echoes (8-10 ms), so neither reads as new; shorter
// than the 30 ms of the shortest flights, so the previous impact's attack is not the reference.
constexpr double kLookbackS = 0.02;
// Floor of a bin's reference power, far below any sound (-300 dB): digital silence must not
// divide by zero.
constexpr float kTinyPower = 1e-30f;
// A bin's reference is at least the noise per bin (its minimum over seconds) this far down. A
// transform codec zeroes the bins under its masking threshold, and from one of its frames to the
// next a zeroed bin becomes another near-zero value: rises of 20-34 dB, 60-160 dB under the
// noise, that in a tenth of a quiet stretch's frames made a mean novelty of 1-2.6 dB (the shared
// Palla-audio.wav as AAC 128k and MP3 128k: 7.5 and 11 % of frames over the 0.6 dB threshold,
// the WAV 0.3 %), and 160 "impacts" where the WAV has 17. A bin of noise stays this far under
// its mean over a whole lookback with a probability of about 1e-20.
constexpr double kReferenceFloorUnderNoise = 0.01;
// CodecNoveltyDb's floor, in a transform codec's file (set_transform_coded): a bin's reference is
// at least the median bin's reference this far down. Inside a loud tail such a codec leaves out
// whole bands that the tail masks and codes them again as its bit allocation moves from frame to
// frame (MP3 above 16 kHz in the detector suite's reverb_strong): from 35-46 dB under the median
// bin they rose by 20-31 dB, a cluster of such bins made a novelty of 0.9-1.5 dB in a room's
// reverberation with no impact in it, and the MP3 copy held 11 impacts against the WAV's 7 (the
// drop's bounces heard only in the ringing then timed like chance: no sequence). Without a codec
// a bin whose loudest power over a whole lookback lies 20 dB under the median bin's does not
// occur (the novelty of no frame of the suite's 20 WAVs changes, an emulation of it), so other
// files skip the second median and pass.
constexpr double kReferenceFloorUnderMedian = 0.01;
// A bin more than this far under the median bin is a codec's zeroed bin, not noise (a noise bin
// lies that low once in 1400), and where at least one bin in kMinHoleShareInverse is such, the
// noise is the lower quartile of the others: MP3, Vorbis and Opus zero a third of the bins of a
// quiet stretch and put the quartile of all 60-90 dB under the noise (AAC 7 dB).
constexpr float kHoleUnderMedian = 1e-3f;
constexpr std::size_t kMinHoleShareInverse = 20;
// The windows between two looks for zeroed bins where the quartile gives no sign of them.
constexpr std::int64_t kHoleCheckWindows = 16;
// A bin holds content when its loudest power is within this range of the median bin's: a codec's
// or a phone path's stop band lies 60-100 dB under its pass band (noise included), while noise
// fills every bin of the pass band to within a few dB of the median (pink noise falls 19 dB over
// 300 Hz-24 kHz, at most ~10 dB below the median bin) and modes only rise above it. The median,
// not the loudest bin: over a quiet recording a plate's loudest mode lies 70 dB above the noise
// in the bins beside it. A cut that removes more than half of the band's bins puts the median in
// the stop band and is not seen (then nothing changes).
constexpr double kContentRangeDb = 30.0;
// Lower quartile of an exponential distribution (the power of a noise bin): ln(4/3) of its mean.
constexpr double kQuartileOfMean = 0.28768207245178085;
// A frame whose window overlaps the current one by more than half shares the onset's samples,
// so the reference skips it: with a hop of a third, the frame just before.
constexpr std::size_t kSkipFrames = (kHopsPerWindow - 1) / 2;

// The power of two within a factor 2/3 .. 4/3 of kWindowS.
int WindowOf(int sample_rate_hz) {
  return std::max(kMinWindow, static_cast<int>(std::bit_floor(static_cast<unsigned>(
                                  std::lround(1.5 * kWindowS * sample_rate_hz)))));
}

std::size_t LookbackFramesOf(int sample_rate_hz, int hop) {
  return std::max<std::size_t>(
      2, static_cast<std::size_t>(std::lround(kLookbackS * sample_rate_hz / hop)));
}

// A power of two, so a frame's slot is a mask, not a 64-bit division (which took 15 % of
// Powers).
std::size_t SlotsOf(std::size_t lookback_frames) {
  return std::bit_ceil(lookback_frames + kSkipFrames + 1 +
                       static_cast<std::size_t>(RingingResidual::kMaxQueryAgeFrames));
}

// The loops over a window's samples and a frame's bins, also compiled for AVX and picked when
// the library loads where the processor has it: eight floats per instruction instead of four.
// Every operation is an exact IEEE one (products, sums of two products, maxima, quotients; AVX
// has no fused multiply-add, which would round differently: that is FMA, not enabled here), so
// the values are the same either way.
#if defined(__x86_64__) && defined(__GNUC__)
#define BOUNCECAL_AVX_CLONES [[gnu::target_clones("avx", "default")]]
#else
#define BOUNCECAL_AVX_CLONES
#endif

// out[i] = x[i] taper[i].
BOUNCECAL_AVX_CLONES
void Taper(const float* x, const float* taper, float* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = x[i] * taper[i];
}

// powers[k] = |spectrum[k]|^2.
BOUNCECAL_AVX_CLONES
void BinPowers(const std::complex<float>* spectrum, float* powers, std::size_t n) {
  for (std::size_t k = 0; k < n; ++k) powers[k] = std::norm(spectrum[k]);
}

// reference[k] = max(reference[k], max(a[k], b[k])).
BOUNCECAL_AVX_CLONES
void MaxOfTwoInto(float* reference, const float* a, const float* b, std::size_t n) {
  for (std::size_t k = 0; k < n; ++k) reference[k] = std::max(reference[k], std::max(a[k], b[k]));
}

// reference[k] = max(reference[k], a[k]).
BOUNCECAL_AVX_CLONES
void MaxInto(float* reference, const float* a, std::size_t n) {
  for (std::size_t k = 0; k < n; ++k) reference[k] = std::max(reference[k], a[k]);
}

// reference[k] = max(1, current[k] / max(reference[k], floor)): each bin's rise as a power ratio.
BOUNCECAL_AVX_CLONES
void RisesOverReference(float* reference, const float* current, float floor, std::size_t n) {
  for (std::size_t k = 0; k < n; ++k) {
    reference[k] = std::max(1.0f, current[k] / std::max(reference[k], floor));
  }
}

#undef BOUNCECAL_AVX_CLONES

// The mean over n bins of 10 log10(ratios[k]) (ratios at least 1, as RisesOverReference leaves
// them).
double MeanRiseDb(const float* ratios, std::size_t n) {
  // The sum of log ratios is the log of their product; a log per bin would cost more than
  // the FFT. Ratios are at most ~1e35 (a float), so products of 8 of them fit a double. Four
  // products side by side (bins k = lane mod 4): one running product was a chain of ~130
  // dependent multiplications per frame. Each is renormalised by its binary exponent after
  // every 8 of its bins, so the whole sum costs one log.
  constexpr std::size_t kLanes = 4;
  constexpr std::size_t kChunk = 8 * kLanes;
  std::array<double, kLanes> mantissa;
  mantissa.fill(1.0);
  long long exponent = 0;
  for (std::size_t k = 0; k < n; k += kChunk) {
    std::array<double, kLanes> product = mantissa;
    const std::size_t end = std::min(n, k + kChunk);
    std::size_t i = k;
    for (; i + kLanes <= end; i += kLanes) {
      for (std::size_t lane = 0; lane < kLanes; ++lane) product[lane] *= ratios[i + lane];
    }
    // The rest (fewer than kLanes bins) one per lane, so no lane takes more than 8 ratios.
    for (std::size_t lane = 0; i < end; ++i, ++lane) product[lane] *= ratios[i];
    for (std::size_t lane = 0; lane < kLanes; ++lane) {
      // std::frexp from the bits (exact, and not a libm call): product is a positive normal
      // double (at least 0.5, at most ~1e280).
      const auto bits = std::bit_cast<std::uint64_t>(product[lane]);
      exponent += static_cast<long long>((bits >> 52) & 0x7ff) - 1022;
      mantissa[lane] =
          std::bit_cast<double>((bits & 0x000fffffffffffffULL) | 0x3fe0000000000000ULL);
    }
  }
  // Four mantissas in [1/2, 1): their product is at least 1/16, no underflow.
  const double all_mantissas = (mantissa[0] * mantissa[1]) * (mantissa[2] * mantissa[3]);
  const double sum_log10 = (static_cast<double>(exponent) + std::log2(all_mantissas)) *
                           std::numbers::ln2 / std::numbers::ln10;
  return 10.0 * sum_log10 / static_cast<double>(n);
}

}  // namespace

std::size_t RingingResidual::HistorySamples(int sample_rate_hz) {
  // The oldest frame a slot can hold starts slots * hop samples before the newest one, which
  // ends a window after its start; a run pushed at once is at most a window.
  const int window = WindowOf(sample_rate_hz);
  const int hop = window / kHopsPerWindow;
  return SlotsOf(LookbackFramesOf(sample_rate_hz, hop)) * static_cast<std::size_t>(hop) +
         static_cast<std::size_t>(window);
}

RingingResidual::RingingResidual(int sample_rate_hz, double band_low_hz, double band_high_hz,
                                 const SampleHistory<float>* source)
    : window_(WindowOf(sample_rate_hz)),
      hop_(window_ / kHopsPerWindow),
      taper_(static_cast<std::size_t>(window_)),
      noise_minimum_(static_cast<double>(window_) / sample_rate_hz),
      fft_(window_) {
  const double bin_hz = static_cast<double>(sample_rate_hz) / window_;
  const auto all_bins = static_cast<std::size_t>(window_ / 2 + 1);
  first_bin_ = std::clamp<std::size_t>(static_cast<std::size_t>(std::ceil(band_low_hz / bin_hz)), 1,
                                       all_bins);
  std::size_t end_bin =
      band_high_hz > 0
          ? std::min(all_bins, static_cast<std::size_t>(std::floor(band_high_hz / bin_hz)) + 1)
          : all_bins - 1;  // the Nyquist bin is real-only: half the statistics of the others
  bins_ = end_bin > first_bin_ ? end_bin - first_bin_ : 0;
  bin_hz_ = bin_hz;
  loudest_.assign(bins_, 0.0f);
  content_edge_hz_ = static_cast<double>(first_bin_ + bins_) * bin_hz_;
  content_bins_ = bins_;
  skip_frames_ = kSkipFrames;
  lookback_frames_ = LookbackFramesOf(sample_rate_hz, hop_);
  slots_.resize(SlotsOf(lookback_frames_));
  history_samples_ = HistorySamples(sample_rate_hz);
  if (source == nullptr) {
    own_.emplace(history_samples_ + static_cast<std::size_t>(window_));
    source = &*own_;
  }
  source_ = source;
  powers_.assign(slots_.size() * bins_, 0.0f);
  reference_.assign(bins_, 0.0f);
  // Periodic Hann window: its low side lobes keep a loud mode out of the neighbouring bins.
  for (int i = 0; i < window_; ++i) {
    taper_[static_cast<std::size_t>(i)] =
        static_cast<float>(0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * i / window_));
  }
}

void RingingResidual::CompleteFrame() {
  const std::int64_t t = frames_++;
  const std::size_t slot = SlotOf(t);
  slots_[slot] = Slot{};
  // The noise estimate is needed once per window length (frames that far apart share no
  // samples, and the floor built from these estimates, minimum statistics over seconds, needs no
  // more); the other spectra only when a novelty is asked for, which the detector does only
  // inside a tail: elsewhere two FFTs in three are skipped.
  if (bins_ > 0 && t % kHopsPerWindow == 0) {
    const float* powers = Powers(t);
    // The maxima rarely grow once the first loud sounds are in: the edge is found again only when
    // one does.
    // Every bin stored and the flag or-ed, without a branch: the loop vectorises (a branch per
    // bin, taken at random while the maxima still grow, cost a fifth of this function).
    int grew = 0;
    for (std::size_t k = 0; k < bins_; ++k) {
      grew |= powers[k] > loudest_[k] ? 1 : 0;
      loudest_[k] = std::max(loudest_[k], powers[k]);
    }
    if (grew != 0) content_edge_hz_ = ContentEdgeHz();
    // The noise is read only where the recording holds content: a cut spectrum's stop band (a
    // third of the bins of a 22.05 kHz file band-limited at 6.4 kHz) put the lower quartile 70
    // dB under the noise, and every sound in a tail then passed the gate against it. The last
    // estimate is the guess: the noise changes little from one window to the next.
    const std::span<const float> content{powers, content_bins_};
    float quartile = SelectKth(content, content_bins_ / 4, select_scratch_, last_quartile_);
    last_quartile_ = quartile;
    // The median costs a second selection (5 % of analysing a WAV at every window): it is taken
    // where the quartile lies within 20 dB of the last hole threshold, where holes may have
    // pulled it down, and once in kHoleCheckWindows windows to keep that threshold current. A
    // quartile of noise lies 4 dB under the median.
    const std::int64_t estimate = t / kHopsPerWindow;
    if (estimate % kHoleCheckWindows == 0 || quartile < last_median_ * kHoleUnderMedian * 100) {
      const float median = SelectKth(content, content_bins_ / 2, select_scratch_, last_median_);
      last_median_ = median;
      const float hole = median * kHoleUnderMedian;
      std::size_t holes = 0;
      for (const float power : content) holes += power < hole ? 1 : 0;
      if (holes * kMinHoleShareInverse >= content_bins_) {
        quartile = SelectKth(content, holes + (content_bins_ - holes) / 4, select_scratch_);
      }
    }
    // Parseval with the Hann window's mean square 3/8: a bin of white noise of variance s^2
    // has mean power 3/8 N s^2.
    noise_power_ = quartile / kQuartileOfMean / (0.375 * window_);
    noise_minimum_.Add(noise_power_);
    reference_floor_ =
        static_cast<float>(noise_minimum_.power() * 0.375 * window_ * kReferenceFloorUnderNoise);
  }
  slots_[slot].reference_floor = reference_floor_;
  fill_ = window_ - hop_;
}

double RingingResidual::ContentEdgeHz() {
  std::vector<float>& sorted = edge_scratch_;
  sorted.assign(loudest_.begin(), loudest_.end());
  const auto middle = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
  std::size_t top = bins_;
  if (middle != sorted.end()) {
    std::nth_element(sorted.begin(), middle, sorted.end());
    const double level = *middle * std::pow(10.0, -0.1 * kContentRangeDb);
    if (level > 0) {
      while (top > 0 && !(loudest_[top - 1] >= level)) --top;
    }
  }
  content_bins_ = std::max<std::size_t>(top, 1);
  return static_cast<double>(first_bin_ + top) * bin_hz_;
}

bool RingingResidual::Valid(std::int64_t frame) const {
  // The reference of frame t is the lookback ending skip + 1 frames before it.
  const std::int64_t j = frame - static_cast<std::int64_t>(skip_frames_) - 1;
  return j >= static_cast<std::int64_t>(lookback_frames_) - 1 && bins_ > 0;
}

const float* RingingResidual::Powers(std::int64_t frame) {
  const std::size_t slot = SlotOf(frame);
  float* powers = powers_.data() + slot * bins_;
  if (slots_[slot].spectrum_frame == frame) return powers;
  // The window in at most two views, where the source's ring wraps.
  auto real = fft_.real();
  const std::int64_t start = frame * hop_;
  for (std::size_t i = 0; i < taper_.size();) {
    const auto view = source_->Contiguous(start + static_cast<std::int64_t>(i), taper_.size() - i);
    Taper(view.data(), taper_.data() + i, real.data() + i, view.size());
    i += view.size();
  }
  fft_.Forward();
  BinPowers(fft_.spectrum().data() + first_bin_, powers, bins_);
  slots_[slot].spectrum_frame = frame;
  return powers;
}

double RingingResidual::ComputeNoveltyDb(std::int64_t frame) {
  if (frame < 0 || frame >= frames_ || frames_ - 1 - frame > kMaxQueryAgeFrames) {
    throw std::logic_error("RingingResidual::NoveltyDb: frame " + std::to_string(frame) +
                           " is not among the last " + std::to_string(kMaxQueryAgeFrames + 1) +
                           " of " + std::to_string(frames_));
  }
  Slot& slot = slots_[SlotOf(frame)];
  if (slot.novelty_frame == frame) return slot.novelty_db;
  double novelty_db = 0;
  double codec_novelty_db = 0;
  if (Valid(frame)) {
    // The reference of each bin is its maximum over frames [j - L + 1, j], j = t - skip - 1.
    const std::int64_t j = frame - static_cast<std::int64_t>(skip_frames_) - 1;
    const auto lookback = static_cast<std::int64_t>(lookback_frames_);
    const float* first = Powers(j - lookback + 1);
    std::copy(first, first + bins_, reference_.begin());
    // Two frames per pass over the reference: it is loaded and stored half as often.
    std::int64_t i = j - lookback + 2;
    for (; i + 1 <= j; i += 2) {
      const float* a = Powers(i);
      const float* b = Powers(i + 1);
      MaxOfTwoInto(reference_.data(), a, b, bins_);
    }
    if (i == j) MaxInto(reference_.data(), Powers(i), bins_);
    const float floor = std::max(kTinyPower, slot.reference_floor);
    const float* powers = Powers(frame);
    if (transform_coded_) codec_reference_.assign(reference_.begin(), reference_.end());
    RisesOverReference(reference_.data(), powers, floor, bins_);
    novelty_db = MeanRiseDb(reference_.data(), bins_);
    // The floor only lowers the novelty, so under codec_least_db_ the unfloored value decides
    // the same; the median is taken for the few frames over it (every frame: 5 % more time for an
    // AAC copy).
    codec_novelty_db = novelty_db;
    if (transform_coded_ && novelty_db >= codec_least_db_) {
      const float median =
          SelectKth(codec_reference_, bins_ / 2, select_scratch_, last_reference_median_);
      last_reference_median_ = median;
      RisesOverReference(codec_reference_.data(), powers,
                         std::max(floor, median * static_cast<float>(kReferenceFloorUnderMedian)),
                         bins_);
      codec_novelty_db = MeanRiseDb(codec_reference_.data(), bins_);
    }
  }
  slot.novelty_frame = frame;
  slot.novelty_db = novelty_db;
  slot.codec_novelty_db = codec_novelty_db;
  return novelty_db;
}

}  // namespace bouncecal::audio
