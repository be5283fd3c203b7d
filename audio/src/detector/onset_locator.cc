#include "detector/onset_locator.h"

#include <algorithm>
#include <cmath>

#include "detector/clipped_span.h"
#include "detector/onset_picker.h"
#include "detector/prediction_innovation.h"

namespace bouncecal::audio {
namespace {

// Noise before the onset that the AIC picker sees (bounded by the previous impact's peak).
constexpr double kPickerNoiseMs = 4.0;
// Window after the onset in which peak_dbfs is measured.
constexpr double kPeakLevelMs = 5.0;
// A clipped oscillation swings back inside full scale for less than half a period of its lowest
// loud component; 0.2 ms bridges those of a plate's modes above 2.5 kHz.
constexpr double kClippedBridgeS = 0.2e-3;
// Clipping is looked for this far before an onset: a longer stretch leaves the onset unknown
// anyway, and half of this (10 ms) already makes a member too weak to move eta-bar.
constexpr double kClippedReachS = 20e-3;
// Order of the linear predictor that removes ringing before picking an onset inside it: two
// coefficients per mode, so up to 12 modes in the band (a plate's strong low modes).
constexpr int kInnovationOrder = 24;
// Samples per predictor coefficient in the stretch before the search it is fitted on. The
// picker's kPickerNoiseMs give 8 at 48 kHz, where the innovation was measured; at a lower rate
// the same milliseconds hold fewer samples (64 at 16 kHz, under the 4 per coefficient below which
// PredictionInnovation refuses to fit), so the innovation was skipped and the onset picked on the
// tail itself. The fit spans at least this many samples per coefficient at every rate.
constexpr int kInnovationFitSamplesPerCoefficient = 8;
// How much of a prediction innovation's burst after its largest sample the change point is searched
// again with, where it fell on that sample (PickOnsetInInnovation): about the longest contact a
// ball makes (a rubber ball's 1.3 ms), so the second segment holds the burst, not what follows it.
// With the whole candidate after it instead, residual-only sequence members of the silent-wrong
// sweep's 8516 files moved closer to their exact onsets in 165 and further in 107 (by more than
// 200 us: 99 and 32), against 157 and 78 (93 and 21) with this, and the coverage suite's
// lead_e050_j4_s4112 took its 5th bounce 1.56 ms early (0.15 ms late before, 0.03 ms with this).
constexpr double kInnovationBurstS = 1e-3;
// How far, in units of the rise threshold, the low band's rise must lead every other band's for a
// sound to count as risen there (Locate).
constexpr double kLowBandLeadFraction = 0.25;
// The change point must stand out of the search's own start by this much in the AIC (-2
// log-likelihood: two sigmas of its profile likelihood), or it did not find where the impact
// began (see LocatedImpact::change_point_found).
constexpr double kMinChangePointAicExcess = 4.0;
// A pick this close after the bound the last candidate set lies on that candidate's own rise.
constexpr double kFloorHugSamples = 2.0;
// History kept for the picker and the peak level; longer than every window above together.
constexpr double kHistoryS = 0.1;

// The loudest level of band over the candidate's frames, in dB.
double LoudestDb(const EnvelopeBand& band, const Candidate& candidate) {
  double peak_db = band.Db(candidate.frame);
  for (std::int64_t i = candidate.frame + 1; i <= candidate.closed_at; ++i) {
    peak_db = std::max(peak_db, band.Db(i));
  }
  return peak_db;
}

// The index in [begin, end) of the largest |sample| (the first of equals); begin when empty.
template <typename Samples, typename Index>
Index LargestSampleIndex(const Samples& samples, Index begin, Index end) {
  Index top = begin;
  for (Index i = begin; i < end; ++i) {
    if (std::fabs(samples[i]) > std::fabs(samples[top])) top = i;
  }
  return top;
}

// The onset's one-sigma uncertainty widened where a later, louder sound shares the candidate.
double WidenedOverLaterSound(const Candidate& candidate, double onset_index,
                             const DetectorFrames& frames, double sigma_s) {
  if (candidate.later_sound_frame < 0) return sigma_s;
  // Two sounds in one candidate, the later louder by the full threshold: the impact is either
  // the one picked or the later one (a precursor picked instead of its impact, 2-10 ms early,
  // was 5 and 60 stated sigmas off in bench/silent_wrong_sweep.py). Half their distance in
  // quadrature covers both.
  const double gap = static_cast<double>(candidate.later_sound_frame * frames.hop) - onset_index;
  if (gap > 0) return std::hypot(sigma_s, 0.5 * gap / frames.rate_hz);
  return sigma_s;
}

// Places the impact at the pick's timing reference where the picker placed one, at its start of
// contact otherwise, and states the uncertainty; returns the onset as a fractional sample index.
double PlaceOnset(const Candidate& candidate, const OnsetPick& pick, std::int64_t window_begin,
                  const DetectorFrames& frames, LocatedImpact& located) {
  Impact& impact = located.impact;
  const double start_index = static_cast<double>(window_begin) + pick.index;
  double onset_index = start_index;
  impact.onset_uncertainty_s = pick.sigma_samples / frames.rate_hz;
  if (std::isfinite(pick.reference_index)) {
    onset_index = static_cast<double>(window_begin) + pick.reference_index;
    impact.onset_uncertainty_s = pick.reference_sigma_samples / frames.rate_hz;
    located.by_reference = true;
    if (std::isfinite(pick.edge_amplitude)) {
      located.reference_lead_s = (pick.reference_index - pick.index) / frames.rate_hz;
    }
  }
  impact.onset_uncertainty_s =
      WidenedOverLaterSound(candidate, onset_index, frames, impact.onset_uncertainty_s);
  impact.onset_s = onset_index / frames.rate_hz;
  return onset_index;
}

}  // namespace

std::size_t OnsetLocator::HistorySamples(int sample_rate_hz) {
  return static_cast<std::size_t>(std::ceil(kHistoryS * sample_rate_hz));
}

OnsetLocator::OnsetLocator(const DetectorFrames& frames, const DetectorOptions& options,
                           BandEnvelopes& bands, const RingingResidualNovelty& residual,
                           const SampleHistory<float>& raw)
    : frames_(frames),
      rise_threshold_db_(options.rise_threshold_db),
      min_snr_db_(options.min_snr_db),
      bands_(bands),
      residual_(residual),
      raw_(raw) {}

std::size_t OnsetLocator::PickBand(std::size_t rising_band) const {
  // A band that holds too little of the recording's content (UsableBands, novelty_sources.h)
  // hands the pick to the highest one that holds enough.
  return std::min(rising_band, UsableBands(bands_, residual_.content_edge_hz()) - 1);
}

std::optional<OnsetLocator::SnrGate> OnsetLocator::CheckSnr(const Candidate& candidate) const {
  // SNR in the band that rose most: its loudest frame of the candidate against its floor.
  const EnvelopeBand& band = bands_.band(candidate.band);
  const double snr_db = LoudestDb(band, candidate) - band.FloorDb(candidate.closed_in_block);
  // Under continuous ringing the minimum-statistics floor of every band is the ringing, not the
  // noise; the ringing residual's floor stays at the noise, so passing in it also counts.
  // snr_db itself stays the band's, so the channel choice compares like with like.
  const bool in_band = snr_db >= min_snr_db_;
  if (!in_band && residual_.SnrDb(LoudestDb(bands_.band(0), candidate)) < min_snr_db_) {
    return std::nullopt;
  }
  return SnrGate{snr_db, in_band};
}

std::int64_t OnsetLocator::SearchFrom(const Candidate& candidate, bool in_ringing) const {
  const std::int64_t hop = frames_.hop;
  std::int64_t search_from = (candidate.frame - 2 * frames_.skip) * hop;
  if (in_ringing) {
    // The residual's frame that fired ended by the frame that opened the candidate, and the
    // onset lies inside that frame's window (its Hann taper hides a new sound at the window's
    // end, so the novelty may rise a few ms after the onset): search from the window's start.
    search_from =
        std::min(search_from, (candidate.opened_at + 1) * hop - residual_.window_samples());
  }
  return search_from;
}

std::int64_t OnsetLocator::SamplesBeforeSearch(bool in_ringing) const {
  std::int64_t noise_samples = frames_.Samples(kPickerNoiseMs * 1e-3);
  if (in_ringing) {
    noise_samples = std::max<std::int64_t>(noise_samples,
                                           kInnovationFitSamplesPerCoefficient * kInnovationOrder);
  }
  return noise_samples;
}

OnsetLocator::PickWindow OnsetLocator::FillPickWindow(const Candidate& candidate,
                                                      const SampleHistory<float>& samples,
                                                      bool in_ringing) {
  const std::int64_t hop = frames_.hop;
  PickWindow window;
  window.search_begin = std::max(samples.begin(), SearchFrom(candidate, in_ringing));
  // The window ends at the impact's largest sample.
  const std::int64_t peak_end = std::min(
      samples.end(), (std::max(candidate.peak_frame, candidate.band_peak_frame) + 1) * hop);
  window.peak = LargestSampleIndex(samples, window.search_begin, peak_end);
  window.begin = std::max({samples.begin(), window.search_begin - SamplesBeforeSearch(in_ringing),
                           pick_floor_sample_ + 1});
  window.search_offset =
      static_cast<std::size_t>(std::max<std::int64_t>(0, window.search_begin - window.begin));
  std::int64_t window_end = std::min(samples.end(), window.peak + 2);
  if (in_ringing) {
    // The largest sample is the tail's: the onset is picked on the innovation, up to its
    // largest innovation sample within the candidate.
    window_end = std::min(samples.end(), (candidate.peak_frame + frames_.peak + 1) * hop);
  }
  window_.clear();
  for (std::int64_t i = window.begin; i < window_end; ++i) window_.push_back(samples[i]);
  return window;
}

void OnsetLocator::SwitchToInnovation(PickWindow& window) {
  auto innovation = PredictionInnovation(window_, window.search_offset, kInnovationOrder);
  // The innovation leaves out the predictor's first samples; an unchanged length means the
  // predictor could not be fitted, and a search that starts among the left-out samples would
  // lose its start.
  const std::size_t skipped = window_.size() - innovation.size();
  if (skipped > 0 && window.search_offset > skipped) {
    window_ = std::move(innovation);
    window.begin += static_cast<std::int64_t>(skipped);
    window.search_offset -= skipped;
    const std::size_t top = LargestSampleIndex(window_, window.search_offset, window_.size());
    window.peak = window.begin + static_cast<std::int64_t>(top);
    window.innovation = true;
  }
}

double OnsetLocator::PeakDbfsAfter(double onset_index) const {
  const std::int64_t level_begin =
      std::max<std::int64_t>(raw_.begin(), std::llround(std::floor(onset_index)));
  const std::int64_t level_end =
      std::min(raw_.end(), level_begin + frames_.Samples(kPeakLevelMs * 1e-3));
  double peak_abs = 0;
  for (std::int64_t i = level_begin; i < level_end; ++i) {
    peak_abs = std::max(peak_abs, double{std::fabs(raw_[i])});
  }
  return 20.0 * std::log10(std::max(peak_abs, 1e-7));
}

std::optional<LocatedImpact> OnsetLocator::Locate(const Candidate& candidate) {
  const std::optional<SnrGate> gate = CheckSnr(candidate);
  if (!gate) return std::nullopt;
  const std::int64_t floor_before = pick_floor_sample_;
  // The onset is picked in the same band, where the impact stands out most from what was there
  // before (unless the recording holds too little of that band, PickBand).
  // A sound that rose by the full threshold only in the low band (band 0 low-passed,
  // BandEnvelopes::is_low_band), and clearly more there than in any other band, is a bounce whose
  // higher bands something louder filled just before it: zaky-ptv's first bounce, the file's
  // loudest sound, rose 9.1 dB in the bands while speech's sibilants filled its 12 ms lookback
  // above 2 kHz, and the drop's sequence began at its second bounce (docs/codecs.md). Its edge
  // is picked in band 0, which holds the low band. "Clearly": by a quarter of the threshold
  // (2.5 dB), as much as a rise moves with where the 0.25 ms frames fall (docs/codecs.md, "Where
  // the file starts"). Without it a weak sound that rose as much above 2 kHz counted too (the zaky
  // clip low-passed at 3 kHz: a sound at 0.608 s, 10.0 dB in the bands and 10.8 below 2 kHz, broke
  // the drop's sequence); with half the threshold the sweep's files gained 8 fewer eta-bars.
  // And like an impact: it rose in the other bands too, by half the threshold (a contact is
  // broadband; the bounce rose 9.1 dB there), and peaked before its candidate closed (a contact's
  // force is over in a millisecond). Voiced speech does neither: the detector suite's
  // knock_speech_before as Vorbis at 16 kHz had two of its sounds band-detected (0.2 and 6.4 dB
  // above 2 kHz, 13.3 and 11.5 below; the second still rising after 12 ms), and its drop then
  // formed no sequence.
  const bool rose_in_low_band =
      candidate.rise_db < rise_threshold_db_ &&
      candidate.rise_db >= kSecondaryRiseFraction * rise_threshold_db_ &&
      !candidate.closed_rising && candidate.low_band_rise_db >= rise_threshold_db_ &&
      candidate.low_band_rise_db >= candidate.rise_db + kLowBandLeadFraction * rise_threshold_db_;
  const double band_rise_db = rose_in_low_band ? candidate.low_band_rise_db : candidate.rise_db;
  const std::size_t rising_band = rose_in_low_band ? 0 : candidate.band;
  const SampleHistory<float>& samples = bands_.band(PickBand(rising_band)).samples;
  // Where no band rose by the full threshold the impact sits in a tail louder than itself, so
  // the band's largest sample and its AIC edge are the tail's: the onset is picked on the
  // prediction innovation instead (measured on the free plate: 61.9 us median against 68.6 us
  // when only rises under half the threshold took this path; the sample steel_ball_h0.2m.wav's
  // 5th impact 0.6 ms instead of 1.5 ms early).
  const bool in_ringing = band_rise_db < rise_threshold_db_;
  PickWindow window = FillPickWindow(candidate, samples, in_ringing);
  if (in_ringing) SwitchToInnovation(window);
  const auto end_offset =
      static_cast<std::size_t>(std::max<std::int64_t>(0, window.peak + 1 - window.begin));
  const OnsetPick pick =
      window.innovation
          ? PickOnsetInInnovation(window_, window.search_offset, end_offset - 1,
                                  static_cast<std::size_t>(frames_.Samples(kInnovationBurstS)),
                                  kMinChangePointAicExcess)
          : PickOnset(window_, window.search_offset, end_offset);
  // The rest of a sound whose candidate closed while rising cannot pick an onset before that
  // candidate's peak: when its search starts before that peak its onset is not trusted.
  const bool continuation = candidate.continues && window.search_begin <= last_peak_sample_;
  last_peak_sample_ = window.peak;
  // A candidate that rose by the full threshold and closed while its band was still rising, whose
  // onset lies within a reference horizon of its window's end, found the start of a sound whose
  // first lobe its window cut off: the next candidate, the rest of that sound, picks its onset in
  // its own search, which may begin before that end. Held back there, a soft ball's impact in a
  // table's low ringing (band 0 stayed under the tail's last swing for a millisecond and closed the
  // candidate opened just before the impact, 3 samples into it, as the impact rose in the 2 kHz
  // band) was picked after that candidate's last sample, and the merger kept that later, louder
  // part: the onset 1.2 ms late at a stated 53 us (detector_ground_truth_test.cc,
  // ASoftBallsImpactRisingInASubBandIsNotSplitFromItsFirstMillisecond). Where the onset lies
  // further back, the candidate held a rising sound of its own and the next one's search stays
  // after it (zaky-ptv-pingpong, a WAV decoded from a video's AAC track: a rise 2.4-2.5 ms, a
  // transform block's pre-echo, before its 4th and 5th bounces; unbounded, the bounces were timed
  // on it and eta-bar(1-3) moved from 0.2989 to 0.2968). Inside ringing (no full rise) the band's
  // loudest frame is mostly the tail's, not an edge, and the onset the innovation's.
  const double start_index = static_cast<double>(window.begin) + pick.index;
  const bool edge_cut_off = candidate.closed_rising && !in_ringing &&
                            static_cast<double>(window.peak) - start_index <
                                static_cast<double>(kReferenceHorizonSamples);
  // An in-ringing window ends at its largest innovation sample, which can be the next sound's
  // first lobe: bounded there, a bounce after a precursor in the previous tail kept 0.15 ms before
  // it and was picked 1.36 ms late at a stated 54 us (silent_wrong_sweep.py seed 11 #146). Such a
  // candidate bounds the next pick at its own onset.
  const bool search_cut_by_rising = pick_floor_rising_ && pick_floor_sample_ >= window.search_begin;
  if (!edge_cut_off) {
    pick_floor_sample_ =
        in_ringing ? static_cast<std::int64_t>(std::ceil(start_index)) : window.peak;
    pick_floor_rising_ = candidate.closed_rising;
  }

  // Opened by the residual alone, and only by the bands a transform codec left out and coded
  // again (RingingResidual::CodecNoveltyDb): no new sound, and no event. It still bounds the next
  // pick (above): a codec's pre-echo that opens such a candidate a few ms before a bounce fences
  // the bounce's own pick off from the pre-echo's start (without that the detector suite's stereo
  // as Vorbis q4 picked its 2nd and 3rd bounces 0.8 and 1.8 ms early). A candidate that rose
  // elsewhere too keeps all of its rise: a weak bounce in a coded tail makes the codec code the
  // bands it had left out as well, and counting only the rest lost 14 of the 628 sequences of the
  // random-impairment sweep's lossy files (this rule alone: 8, and 6 gained).
  const double secondary_threshold_db = kSecondaryRiseFraction * rise_threshold_db_;
  if (band_rise_db < secondary_threshold_db &&
      candidate.residual_rise_db >= secondary_threshold_db &&
      candidate.residual_codec_rise_db < secondary_threshold_db) {
    return std::nullopt;
  }

  // Re-armed by the window alone, and picked against the bound the last candidate set: it found
  // that candidate's rise again, not a sound of its own (the detector suite's noise_snr12 as
  // Vorbis q4: a second candidate in a pre-echo 15 ms before the 4th bounce, picked 30 us after
  // the first one's onset, made the pair a full rise and a stray impact).
  if (candidate.armed_past_window &&
      start_index <= static_cast<double>(floor_before) + kFloorHugSamples) {
    return std::nullopt;
  }

  LocatedImpact located;
  const double onset_index = PlaceOnset(candidate, pick, window.begin, frames_, located);
  Impact& impact = located.impact;
  impact.rise_db = band_rise_db;
  // The residual's rise is kept scaled to the band threshold for the decisions; reported in its
  // own unit.
  impact.ringing_novelty_db = std::isfinite(candidate.residual_rise_db)
                                  ? residual_.NoveltyDb(candidate.residual_rise_db)
                                  : std::numeric_limits<double>::quiet_NaN();
  impact.snr_db = gate->snr_db;
  impact.residual_only = !gate->in_band;
  impact.peak_dbfs = PeakDbfsAfter(onset_index);
  located.band = rising_band;
  located.onset_sample = onset_index;
  located.span_end_sample = (candidate.closed_at + 1) * frames_.hop;
  located.rise_db = std::max(band_rise_db, candidate.residual_rise_db);
  located.band_rise_db = band_rise_db;
  located.band_rose = !in_ringing;
  located.continuation = continuation;
  located.change_point_found = pick.start_aic_excess >= kMinChangePointAicExcess;
  if (!located.change_point_found) {
    // The change point did not stand out of the search's start: the whole search looked alike
    // and the onset sits near its start, while the impact may have begun anywhere up to the
    // window's peak. Half the search states it (the 16 kHz rubber ball on a table, seed 3: its 9th
    // bounce 3.5 ms early at a stated residual hop of 1.3 ms, in a search of 5.3 ms).
    impact.onset_uncertainty_s =
        std::max(impact.onset_uncertainty_s,
                 0.5 * static_cast<double>(window.peak - window.search_begin) / frames_.rate_hz);
  }
  if (search_cut_by_rising) {
    // The floor cut this search, and the candidate that set it closed while still rising: the
    // sound it rose into may be this one, begun before the floor where the picker could not look,
    // and what the picker found after the floor had the end of that rise before it, not noise. The
    // onset may lie anywhere from the search's start on. A 0.8-1 ms contact after a precursor was
    // picked 1.6-2.4 ms late at a stated 23-106 us this way (silent_wrong_sweep.py seed 808 #121,
    // eta-bar 4.4 sigmas off; seed 23 #93).
    impact.unsearched_span_s =
        0.5 * (onset_index - static_cast<double>(window.search_begin)) / frames_.rate_hz;
  }
  // Clipped right up to the onset, the impact may have begun anywhere in the clipped stretch
  // (ClippedSamplesBefore). The detector suite's handling_thumps 20 dB louder, its 4th bounce in
  // a low thump clipped for 1.6 ms before it: picked where the clipping let go, 0.61 ms late at a
  // stated 31 us, eta-bar 7.8 combined sigmas from the WAV's.
  const std::int64_t clipped =
      ClippedSamplesBefore(raw_, static_cast<std::int64_t>(std::floor(onset_index)),
                           frames_.Samples(kClippedBridgeS), frames_.Samples(kClippedReachS));
  if (clipped > 0) {
    impact.unsearched_span_s =
        std::max(impact.unsearched_span_s, 0.5 * static_cast<double>(clipped) / frames_.rate_hz);
  }
  // A clipped lobe ahead of the onset's own set the timing reference's level too low, and the
  // reference may belong on it (ClippedLobeAfter): the shared eeps ping-pong 20 dB louder timed a
  // bounce on the small waves 0.53 ms before its clipped spike, where the WAV times the spike, at
  // a stated 50 us (eta-bar 3.3 combined sigmas from the WAV's).
  const std::int64_t to_clipped_lobe =
      ClippedLobeAfter(raw_, static_cast<std::int64_t>(std::ceil(onset_index)),
                       2 * static_cast<std::int64_t>(kReferenceHorizonSamples),
                       static_cast<float>(kReferenceFraction) * kClippedLevel);
  if (to_clipped_lobe > 0) {
    impact.onset_uncertainty_s = std::hypot(
        impact.onset_uncertainty_s, 0.5 * static_cast<double>(to_clipped_lobe) / frames_.rate_hz);
  }
  return located;
}

double ReferenceToContactOffset(const std::vector<LocatedImpact>& impacts) {
  std::vector<double> leads;
  for (const LocatedImpact& located : impacts) {
    if (std::isfinite(located.reference_lead_s)) leads.push_back(located.reference_lead_s);
  }
  if (leads.empty()) return 0.0;
  const auto middle = leads.begin() + static_cast<std::ptrdiff_t>(leads.size() / 2);
  std::nth_element(leads.begin(), middle, leads.end());
  return *middle;
}

}  // namespace bouncecal::audio
