#ifndef BOUNCECAL_AUDIO_RESPONSE_TIMING_H_
#define BOUNCECAL_AUDIO_RESPONSE_TIMING_H_

#include <cstdint>
#include <span>
#include <vector>

#include "bouncecal/audio/impact_detector.h"
#include "bouncecal/audio/load_recording.h"

namespace bouncecal::audio {

// Timing of impacts from their whole response: for recordings whose first lobe is unreliable,
// and for every other recording whose contact durations it determines.
//
// A transform codec (AAC, MP3, Vorbis, Opus) spreads quantisation noise over a short block before
// a click (pre-echo, up to 2.7-4 ms), and at 8-16 kHz a click's first lobe is a sample or two
// wide and often buried in the previous impact's ringing: the detector's onset, which times the
// first lobe, then jumps by up to milliseconds on a few percent of the impacts. The response
// after each impact (the plate's and the ball's ringing) survives both, and the impacts of one
// recording excite nearly the same modes, so each impact's response is aligned to a template
// response of the same recording (normalised cross-correlation of the first differences over the
// first 12 ms, at lags up to 5 ms). Only relative times enter intervals: the alignment's
// median shift over the recording is removed, so a template whose own onset is off costs
// nothing.
//
// An impact whose alignment is unambiguous (one correlation peak clearly above every other lag)
// gets a second measurement of its onset with an uncertainty from the alignment's own quality
// (the residual 1 - rho^2 over the template's bandwidth). The detector's onset, whose error is its
// own sigma and the first lobe's (a codec's, codec_timing.h) in quadrature, is combined with it by
// their variances where the two agree within 3 combined sigmas; where they do not, the detector's
// onset jumped (pre-echo, a hop in ringing) and the alignment's replaces it. Either way the
// impact is stated with the alignment's precision, not the codec's; an impact without a usable
// alignment (weak or ambiguous correlation: another kind of sound, a double hit, a response cut
// short) keeps the detector's onset with the first lobe's error added.
//
// A real ball's impacts excite its modes in a different mix and phase from one contact spot to
// the next, so their waveforms rarely align (rho 0.2-0.5). In a transform-codec file those
// impacts are timed from their band envelopes instead (detector/envelope_alignment.h), which do
// not depend on the phases: relative to the detector's onsets of the neighbouring impacts (a
// local median, since envelope and first lobe drift apart as contacts lengthen), they confirm
// the detector's onset or, where it jumped, replace it, stated with the envelopes' own sigma and
// their scatter against the first lobe over those neighbours.
//
// The alignment locks on the centroid of each impact's contact force, t0 + tau_k / 2, and a
// slower impact's contact lasts longer (tau ~ v^-1/5): the aligned onsets are moved back to the
// start of contact by half of each contact's lengthening over the template's, estimated from the
// spectra of the aligned responses (contact_duration.h). Where that estimate exists, the
// alignment alone gives the onset (the first lobe's pick drifts with the contact too); PCM at 20
// kHz and above is retimed only then (require_contact_durations), since its first lobe is right
// to a sample and the uncorrected drift would read as a speed trend.
struct ResponseTimingOptions {
  double search_s = 5e-3;        // largest lag tried either side of the detector's onset
  double response_s = 12e-3;     // length of response compared
  double min_response_s = 2e-3;  // shorter (the next impact follows) is not aligned
  double min_correlation = 0.6;  // weaker peaks are not used
  // A peak must stand this far (in correlation) above the best lag outside its own lobe: a
  // response dominated by one mode correlates almost as well one period away.
  double min_peak_margin = 0.15;
  // An impact found only inside ringing (Impact::residual_only) whose response correlates this
  // well with the template's is an impact of the same ball on the same surface, not speech or
  // handling noise, and counts as band-detected. A transform codec's noise lowers a bounce's
  // correlation, so there every usable alignment confirms (ResponseTimingFor): the detector suite's
  // steel_ref as Opus 32k at 16 kHz (a messenger's voice note) has bounces 2-5 at rho 0.65-0.85,
  // its 2nd at 0.67 kept residual-only, and the drop formed no sequence; the speech of
  // knock_speech_before in the same coding aligns at 0.06-0.41. The same below 20 kHz, where the
  // bands above the Nyquist frequency, in which a click rises most, are gone: zaky-ptv's
  // ping-pong resampled to 16 kHz kept bounces 2, 5 and 7 (rho 0.68-0.78) residual-only behind
  // sounds 15-26 ms before them, and a chain of the room's sounds 168 combined sigmas off took
  // the drop's place.
  double confirming_correlation = 0.8;
  // Leave the onsets as detected unless the recording determines its contact durations. Where
  // the first lobe is reliable (PCM at 20 kHz and above) the stage is worth it only with the
  // centroid correction (contact_duration.h): uncorrected, the aligned onsets drift with the
  // contact's duration and, stated with the alignment's precision, read as a speed trend.
  bool require_contact_durations = false;
  // Time the impacts whose waveform does not align from their band envelopes
  // (detector/envelope_alignment.h), which do not depend on the modes' phases: a real ball's
  // impacts excite its modes in a different mix and phase from one spot to the next, and a
  // transform codec's pre-echo moves the first lobe that times them otherwise. Only for
  // transform codecs, where the alternative is the codec table's sigma; a WAV keeps its first
  // lobe.
  bool envelope_alignment = false;
  // A transform codec's pre-echo can rise into an attack without a break, so the detector's
  // onset may be the noise's start: an impact stated with the first lobe's error (not its own
  // alignment) also states half the distance to a later attack in its window (later_attack.h).
  // Below 20 kHz a linear-phase recording chain or band limit rings milliseconds ahead of a
  // loud attack in the same way (8 kHz: 4.3 ms; the sweep's seed 101 #112, 3.07 ms early at a
  // stated 168 us), so such files state it too.
  bool pre_echo = false;
};

// Whether a recording's first lobes are unreliable enough for the stage: a transform codec
// (every lossy codec but G.711 and ADPCM, which code sample by sample and keep the lobe) or a
// sample rate below 20 kHz.
bool FirstLobeUnreliable(const RecordingInfo& info);
// Whether a recording is coded by a transform codec (lossy, but not G.711 or ADPCM).
bool TransformCodec(const RecordingInfo& info);
// The stage's options for a recording: where its first lobe is reliable, the onsets are retimed
// only with the centroid correction (require_contact_durations).
ResponseTimingOptions ResponseTimingFor(const RecordingInfo& info);

struct ResponseTimingSummary {
  int considered = 0;        // impacts and tentative impacts
  int aligned = 0;           // with an unambiguous alignment
  int combined = 0;          // detector and alignment agreed and were combined
  int replaced = 0;          // the detector's onset jumped; the alignment's replaced it
  int own_sigma = 0;         // stated with the alignment's sigma, without the first lobe's error
  int envelope_aligned = 0;  // of those, aligned by their band envelopes (not their waveform)
  std::int64_t template_onset_sample = -1;
  // The template impact's contact duration (s) and the jackknife sd of its log, from the spectra
  // of the aligned responses; the aligned onsets were moved from their force's centroid to the
  // start of contact with it. 0 where the recording does not determine it (no correction).
  double contact_duration_s = 0;
  double contact_duration_log_sd = 0;
};

// Collects the samples around each onset of a detection (memory: ~2 x (search + response) per
// impact), from the stretches the detector kept (ImpactDetector::KeepSamplesAroundImpacts) or
// from the whole stream, then retimes the detection.
class ResponseTimer {
 public:
  ResponseTimer(const DetectionResult& detection, const ResponseTimingOptions& options = {});

  // The samples it reads around an onset: this many before it and after it (what an
  // ImpactDetector must keep, KeepSamplesAroundImpacts).
  static std::int64_t SamplesBeforeOnset(int sample_rate_hz,
                                         const ResponseTimingOptions& options = {});
  static std::int64_t SamplesAfterOnset(int sample_rate_hz,
                                        const ResponseTimingOptions& options = {});

  // Consecutive samples of the analysed channel, from sample 0 on.
  void Process(std::span<const float> samples);
  // A stretch of them (ImpactDetector::TakeKeptSamples), in any order; samples of a window that
  // no stretch holds read as silence.
  void Process(const SampleStretch& stretch);
  // Retimes the detection; first_lobe_sigma_s is the error of the detector's onsets beyond their
  // own uncertainty (a lossy codec's, codec_timing.h; 0 for PCM): it is added in quadrature to
  // every onset but those the alignment times on its own.
  ResponseTimingSummary Apply(DetectionResult& detection, double first_lobe_sigma_s) const;

 private:
  struct Window {
    bool tentative = false;
    std::size_t index = 0;
    std::int64_t begin = 0;  // first sample
    std::vector<float> samples;
  };
  ResponseTimingOptions options_;
  int sample_rate_hz_ = 0;
  std::int64_t length_ = 0;      // samples per window
  std::int64_t lead_ = 0;        // samples of a window before its onset sample
  std::vector<Window> windows_;  // by begin
  ResponseTimingSummary Retime(DetectionResult& detection, double first_lobe_sigma_s,
                               std::vector<bool>& own) const;
  // The window whose response the others are aligned to; windows_.size() where none can be.
  std::size_t ChooseTemplate(const DetectionResult& detection,
                             const std::vector<std::int64_t>& lengths,
                             const std::vector<std::vector<float>>& differences) const;
  // Copies samples[i], the recording's sample begin + i, into every window that holds it.
  void Fill(std::int64_t begin, std::span<const float> samples);
  std::int64_t position_ = 0;  // where the next consecutive block (Process) starts
};

// Convenience for a recording in memory.
ResponseTimingSummary RetimeFromResponses(DetectionResult& detection,
                                          std::span<const float> samples,
                                          double first_lobe_sigma_s = 0,
                                          const ResponseTimingOptions& options = {});

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_RESPONSE_TIMING_H_
