#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_RINGING_RESIDUAL_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_RINGING_RESIDUAL_H_

#include <algorithm>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "detector/noise_floor.h"
#include "detector/sample_history.h"
#include "dsp/real_fft.h"

namespace bouncecal::audio {

// Spectral novelty that the ringing of earlier impacts does not explain, frame by frame.
//
// Inside the tail of a long-ringing plate a late, weak impact is quieter than the tail in every
// band, but not in every *bin*: the tail is a set of decaying modes, the loud low ones ringing
// for seconds and the high ones dying within tens of ms, while a new impact is broadband and
// sudden, so it raises many bins at once, most in the bins where the tail has already died.
// Each bin is therefore compared with its own loudest value over the last ~20 ms (a ringing
// bin, even one where several modes beat, never exceeds the maxima of its recent beats), and
// the per-bin rises in dB, half-wave rectified, are averaged over the band: the log-magnitude
// spectral flux that Dixon (DAFx 2006, "Onset detection revisited") found the most reliable
// onset function, with the per-bin adaptive reference of a rise detector. Averaging in dB gives
// every bin the same vote whatever its level, so a few loud beating bins cannot mask a
// broadband onset (the robustness argument of Bello et al., IEEE Trans. Speech Audio Process.
// 13(5), 2005, sec. III-A), and it needs no model of the modes.
//
// It replaces a complex-domain prediction (X_t = X_{t-1}^2 / X_{t-2} per bin of a 2.7 ms
// STFT; Bello et al. 2004), which assumes one tone per bin: on a free steel plate with modes
// ~220 Hz apart two or more modes share every 375 Hz bin, beat, and the prediction failed in
// exactly the tails it was for (87 of 144 impacts found on the synthesiser's Kirchhoff plate,
// against 137 with this novelty; a time-domain LPC residual of order 32-128 did no better than
// the old one: the plate's 61 modes need more poles than a 20 ms fit can estimate).
class RingingResidual {
 public:
  // Window of about 5.3 ms (a power of two in samples, at least 32): bins ~190 Hz wide, narrow
  // enough to resolve most plate modes, and short against the 30 ms of the shortest bounce
  // flights worth timing. Hop a third of it. Bins outside [band_low_hz, band_high_hz]
  // (band_high_hz <= 0: up to Nyquist) are ignored.
  //
  // With a source, the residual keeps no samples of its own: the caller pushes the signal into
  // that history (which must hold at least history_samples() samples before the newest one the
  // residual was advanced to, plus whatever the caller pushes ahead of it) and tells the
  // residual how far to read with Advance(). Without one, Push/PushRun keep a history inside.
  RingingResidual(int sample_rate_hz, double band_low_hz, double band_high_hz,
                  const SampleHistory<float>* source = nullptr);
  RingingResidual(const RingingResidual&) = delete;
  RingingResidual& operator=(const RingingResidual&) = delete;

  // Whether the input was decoded from a transform codec (off by default): CodecNoveltyDb then
  // counts each bin's rise only from 20 dB under the median bin's reference, in the frames whose
  // NoveltyDb reaches least_novelty_db (under it, CodecNoveltyDb is NoveltyDb: the caller decides
  // nothing there).
  void set_transform_coded(bool transform_coded, double least_novelty_db = 0) {
    transform_coded_ = transform_coded;
    codec_least_db_ = least_novelty_db;
  }

  int window_samples() const { return window_; }
  int hop_samples() const { return hop_; }
  // Feeds one sample (of the band-filtered signal); true when a frame completed. Its results are
  // then read from novelty_db(), noise_power() and valid(). Only without a source.
  bool Push(float sample) { return PushRun({&sample, 1}); }
  // Samples still needed to complete the next frame.
  std::size_t samples_to_frame() const { return static_cast<std::size_t>(window_ - fill_); }
  // Feeds at most samples_to_frame() samples at once; true when they completed a frame. Only
  // without a source.
  bool PushRun(std::span<const float> samples) {
    own_->PushBlock(samples);
    return Advance(samples.size());
  }
  // With a source: the next `count` (at most samples_to_frame()) samples are in it; true when
  // they completed a frame.
  bool Advance(std::size_t count) {
    fill_ += static_cast<int>(count);
    if (fill_ < window_) return false;
    CompleteFrame();
    return true;
  }
  // How many of the newest samples a source must hold (see the constructor).
  std::size_t history_samples() const { return history_samples_; }
  static std::size_t HistorySamples(int sample_rate_hz);
  // Index of the latest completed frame (0, 1, ...), -1 before the first.
  std::int64_t latest_frame() const { return frames_ - 1; }
  // Mean over the band's bins of max(0, rise in dB of the bin over its loudest value in the
  // lookback) of frame `frame`, which must be one of the last kMaxQueryAgeFrames + 1 frames.
  // 0 for a stationary or decaying sound; stationary noise gives a few tenths of a dB; 0 while
  // the frame is not valid. Computed on demand (see CompleteFrame) and cached, so asking only
  // where the answer matters skips most of the FFTs; the result does not depend on when or
  // whether other frames were asked for.
  double NoveltyDb(std::int64_t frame) {
    // The cached answer inline: the detector asks about each frame once per envelope frame of
    // its attack window, several times in all.
    if (frame >= 0 && frame < frames_ && frames_ - 1 - frame <= kMaxQueryAgeFrames) {
      const Slot& slot = slots_[SlotOf(frame)];
      if (slot.novelty_frame == frame) return slot.novelty_db;
    }
    return ComputeNoveltyDb(frame);
  }
  // The same for the latest frame.
  double novelty_db() { return NoveltyDb(latest_frame()); }
  // NoveltyDb with each bin's reference at least the median bin's 20 dB down, in a transform
  // codec's file (set_transform_coded; elsewhere NoveltyDb itself): what rose in the bands the
  // codec left out and coded again does not count. Same frames as NoveltyDb.
  double CodecNoveltyDb(std::int64_t frame) {
    NoveltyDb(frame);
    return slots_[SlotOf(frame)].codec_novelty_db;
  }
  // Noise power per sample under the ringing: the lower quartile of the band's bin powers
  // (a ringing tail fills a few bins, the noise all of them), scaled to a mean square.
  double noise_power() const { return noise_power_; }
  // The highest frequency at which the recording has held content so far: the top of the highest
  // bin whose loudest power over every window seen (one in three frames, which together cover
  // every sample) is within kContentRangeDb of the median bin's. Below the band's upper edge
  // when a codec or a phone path has cut the top of the spectrum (less than half of it); the
  // band's upper edge (or Nyquist) before any window or in silence.
  double content_edge_hz() const { return content_edge_hz_; }
  // False until the lookback holds enough frames for a reference; novelty_db() is 0 until then.
  bool valid() const { return Valid(latest_frame()); }

  // How many frames before the latest one NoveltyDb may be asked about: the detector asks for
  // the frames that ended in its attack window (2 ms, or one envelope frame of at most 5 ms,
  // plus the current one: at most ~10 ms), and a hop is at least ~1.2 ms.
  static constexpr std::int64_t kMaxQueryAgeFrames = 16;

 private:
  struct Slot {
    std::int64_t spectrum_frame = -1;  // the frame whose bin powers `powers` holds, -1 none
    std::int64_t novelty_frame = -1;   // the frame whose novelty `novelty_db` holds, -1 none
    double novelty_db = 0;
    double codec_novelty_db = 0;  // CodecNoveltyDb's
    // The least reference power of a bin when the frame completed (kReferenceFloorUnderNoise).
    float reference_floor = 0;
  };
  void CompleteFrame();
  double ComputeNoveltyDb(std::int64_t frame);
  bool Valid(std::int64_t frame) const;
  double ContentEdgeHz();
  std::size_t SlotOf(std::int64_t frame) const {
    return static_cast<std::size_t>(frame) & (slots_.size() - 1);
  }
  // Bin powers of `frame` (computing its FFT from the stored window if not done yet).
  const float* Powers(std::int64_t frame);

  int window_ = 0;
  int hop_ = 0;
  int fill_ = 0;
  std::size_t first_bin_ = 0;
  std::size_t bins_ = 0;  // in the band
  std::size_t lookback_frames_ = 0;
  std::size_t skip_frames_ = 0;
  std::vector<float> taper_;
  // The band-filtered input, read in place when a frame's spectrum is needed (copying every
  // window out cost 5 float copies per sample, keeping a stream of our own one more): frame t
  // is samples [t * hop, t * hop + window) of *source_, which is own_ without a caller's source.
  std::size_t history_samples_ = 0;  // samples the oldest queryable frame can need
  std::optional<SampleHistory<float>> own_;
  const SampleHistory<float>* source_ = nullptr;
  // Per slot (a ring of the last lookback + skip + 1 + kMaxQueryAgeFrames frames): its band's
  // bin powers once computed.
  std::vector<Slot> slots_;
  std::vector<float> powers_;
  std::vector<float> reference_;
  std::vector<float> codec_reference_;  // CodecNoveltyDb's
  std::vector<float> select_scratch_;   // SelectKth's
  float last_quartile_ = 0;          // of the last noise estimate's bin powers, SelectKth's guess
  float last_median_ = 0;            // the same for their median
  float last_reference_median_ = 0;  // the last novelty reference's median bin, its guess
  bool transform_coded_ = false;
  double codec_least_db_ = 0;  // set_transform_coded's least_novelty_db
  std::int64_t frames_ = 0;
  double noise_power_ = 0;
  // The noise estimates' minimum over seconds, and the reference floor it sets.
  NoiseFloor noise_minimum_;
  float reference_floor_ = 0;
  double bin_hz_ = 0;
  std::vector<float> loudest_;  // per bin, over the windows of the noise estimates
  std::vector<float> edge_scratch_;
  double content_edge_hz_ = 0;    // content_edge_hz(), updated with loudest_
  std::size_t content_bins_ = 0;  // the bins below it
  RealFft fft_;
};

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_RINGING_RESIDUAL_H_
