#ifndef BOUNCECAL_AUDIO_CODEC_TIMING_H_
#define BOUNCECAL_AUDIO_CODEC_TIMING_H_

#include <optional>
#include <string>

#include "bouncecal/audio/impact_detector.h"
#include "bouncecal/audio/load_recording.h"

namespace bouncecal::audio {

// How far a lossy codec moves the onsets the detector finds. A perceptual codec (AAC, MP3,
// Vorbis, Opus) spreads its quantisation noise over a transform block, so energy appears up to a
// short block (2.7-4 ms) before a click (pre-echo), and it low-passes the edge; both move an
// onset by an amount that differs from impact to impact, so it does not cancel in the
// intervals. bench/codec_timing_bench measured it on synthetic drops encoded with Debian's
// encoders (docs/codecs.md): the sigma below covers 95 % of the onset shifts against the WAV's
// at 1.96 sigma, per codec family and bit rate class, the largest over 16, 44.1 and 48 kHz.
struct CodecTiming {
  // "aac", "mp3", "vorbis", "opus", "g711", "adpcm", or "other" for a codec not measured
  std::string family;
  // The stream's average bit rate per channel is at or above the family's
  // high_bit_rate_bps_per_channel. An unknown bit rate counts as low: the larger error is the
  // safe side.
  bool high_bit_rate = false;
  double high_bit_rate_bps_per_channel = 0;
  // One sigma to add in quadrature to every onset's uncertainty.
  double onset_uncertainty_s = 0;
  // False for a lossy codec the bench did not measure (AMR, WMA, AC-3, MP2, G.726, ...):
  // the largest measured sigma stands in for it.
  bool measured = true;
  // How often a transform codec draws its quantisation noise anew (its frame, or MP3's granule,
  // at the decoded rate; long blocks): pre-echo reaches at most this far ahead of an attack
  // (DetectImpactsInFile widens the onsets a merge may have taken from it), and through a ringing
  // tail the ringing residual can rise once a frame (SequenceOptions::codec_frame_s). nullopt
  // for a codec that codes sample by sample (G.711, ADPCM).
  std::optional<double> frame_s;
};

// The codec timing error of a recording, or nullopt for lossless input.
std::optional<CodecTiming> CodecTimingOf(const RecordingInfo& info);

// Adds sigma_s in quadrature to the onset uncertainty of every impact and tentative impact of
// the detection. DetectImpactsInFile applies it to every lossy file (FileDetection::
// codec_timing), so AnalyzeBounces, `bouncecal analyze` and the calibration input all carry it;
// call it yourself only for impacts detected in decoded audio you fed to ImpactDetector.
void WidenOnsetUncertainties(DetectionResult& detection, double sigma_s);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_CODEC_TIMING_H_
