#include "bouncecal/audio/response_timing.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <span>
#include <utility>
#include <vector>

#include "detector/contact_duration.h"
#include "detector/correlation_sums.h"
#include "detector/envelope_alignment.h"
#include "detector/lag_dots.h"
#include "detector/later_attack.h"

namespace bouncecal::audio {
namespace {

// Below this rate a click's first lobe spans one or two samples (docs/codecs.md: the steel
// sample at 8 kHz is found only inside ringing, with one residual hop of uncertainty).
constexpr int kLowRateHz = 20000;

// Floor of an alignment's uncertainty: the contact lasts longer the slower the impact (v^-1/5), so
// a late bounce's response is a slightly different waveform from the loudest impact's, and its
// alignment is biased by a fraction of a sample (0.54 sample at the 8th bounce of the test's
// steel drop, response_timing_test.cc) where the contact durations are not determined (and
// corrected, contact_duration.h); the parabola adds up to a tenth of a sample.
constexpr double kMinSigmaSamples = 0.5;

// The template is chosen among this many of the loudest impacts, by how many of this many of the
// loudest align with each (ResponseTimer::ChooseTemplate): 4 x 16 alignments, a few ms.
constexpr std::size_t kTemplateCandidates = 4;
constexpr std::size_t kTemplateJudges = 16;

// Agreement between the detector's onset and the alignment's, in combined sigmas, beyond which
// the detector's onset is taken to have jumped.
constexpr double kAgreementSigmas = 3.0;

struct Alignment {
  bool usable = false;
  double response_sample = 0;  // the impact's response starts here, in the template's timing
  std::int64_t start = 0;      // index in the target where the best integer lag's window starts
  double fraction = 0;         // the peak's sub-sample part
  double sigma_samples = 0;
  double correlation = 0;
};

std::vector<float> FirstDifference(const std::vector<float>& samples) {
  std::vector<float> out(samples.size() > 0 ? samples.size() - 1 : 0);
  for (std::size_t i = 0; i + 1 < samples.size(); ++i) out[i] = samples[i + 1] - samples[i];
  return out;
}

// Normalised cross-correlation of templ[lead, lead + n) with target[lead + lag, lead + lag + n)
// for lags -search..search (lead: the onset's index in both). templ_sums: TemplateSums(templ,
// lead); prefix: EnergyPrefix(target), which give each lag's window energy in O(1). Both are
// summed by the caller, once per signal: a template meets every target, a judge several
// candidates.
Alignment Align(const std::vector<float>& templ, const TemplateSums& templ_sums,
                const std::vector<float>& target, std::span<const double> prefix, std::int64_t lead,
                std::int64_t search, std::int64_t n, std::int64_t onset_sample,
                const ResponseTimingOptions& options) {
  Alignment result;
  const double templ_energy = templ_sums.energy(n);
  const double templ_energy_squares = templ_sums.energy_squares(n);
  const double templ_slope = templ_sums.slope(n);
  if (templ_energy <= 0 || templ_slope <= 0) return result;
  const std::int64_t lags = 2 * search + 1;
  std::vector<double> correlation(static_cast<std::size_t>(lags), 0.0);
  const float* a = templ.data() + lead;
  const auto normalise = [&](std::int64_t k, float dot) {
    const std::int64_t start = lead + k - search;
    const double energy =
        prefix[static_cast<std::size_t>(start + n)] - prefix[static_cast<std::size_t>(start)];
    correlation[static_cast<std::size_t>(k)] =
        energy > 0 ? dot / std::sqrt(templ_energy * energy) : 0.0;
  };
  // 32 and 8 lags at a time (LagDots): this loop was 27 % of analysing an AAC copy (a
  // 10-minute file: 1.41 CPU s against its WAV's 0.56).
  std::int64_t k = 0;
  for (; k + 4 * kLagLanes <= lags; k += 4 * kLagLanes) {
    std::array<float, 4 * kLagLanes> dot{};
    ThirtyTwoLagDots(a, target.data() + (lead + k - search), n, dot.data());
    for (std::int64_t j = 0; j < 4 * kLagLanes; ++j) {
      normalise(k + j, dot[static_cast<std::size_t>(j)]);
    }
  }
  for (; k + kLagLanes <= lags; k += kLagLanes) {
    std::array<float, kLagLanes> dot{};
    EightLagDots(a, target.data() + (lead + k - search), n, dot.data());
    for (std::int64_t j = 0; j < kLagLanes; ++j) normalise(k + j, dot[static_cast<std::size_t>(j)]);
  }
  for (; k < lags; ++k) {
    const float* x = target.data() + (lead + k - search);
    float dot = 0;
    for (std::int64_t t = 0; t < n; ++t) dot += a[t] * x[t];
    normalise(k, dot);
  }
  const auto best_it = std::max_element(correlation.begin(), correlation.end());
  const std::int64_t best = best_it - correlation.begin();
  const double rho = *best_it;
  // The peak's own lobe: where the correlation keeps falling away from it.
  std::int64_t lo = best;
  while (lo > 0 && correlation[static_cast<std::size_t>(lo - 1)] <
                       correlation[static_cast<std::size_t>(lo)]) {
    --lo;
  }
  std::int64_t hi = best;
  while (hi + 1 < lags && correlation[static_cast<std::size_t>(hi + 1)] <
                              correlation[static_cast<std::size_t>(hi)]) {
    ++hi;
  }
  double rival = -1;
  for (std::int64_t k = 0; k < lags; ++k) {
    if (k < lo || k > hi) rival = std::max(rival, correlation[static_cast<std::size_t>(k)]);
  }
  // A peak at the edge of the search may lie beyond it.
  if (best == 0 || best == lags - 1) return result;
  const double left = correlation[static_cast<std::size_t>(best - 1)];
  const double right = correlation[static_cast<std::size_t>(best + 1)];
  const double curvature = left - 2 * rho + right;
  const double fraction = curvature < 0 ? 0.5 * (left - right) / curvature : 0.0;
  result.correlation = rho;
  result.start = lead + best - search;
  result.fraction = fraction;
  result.response_sample = static_cast<double>(onset_sample + best - search) + fraction;
  // Time-delay estimation (template and target equally noisy): var = 2 (1 - rho^2) /
  // (rho^2 n beta^2), beta^2 the template's mean squared slope per energy, with the residual
  // (the part of the target the template does not explain, 1 - rho^2 of its energy) spread over
  // the samples that hold the template's energy (their participation number), not over all n:
  // what the template does not explain is mostly a different mix of the same modes, the earlier
  // impacts' ringing and the codec's noise shaped like the response, not white noise.
  const double beta2 = templ_slope / templ_energy;
  const double r2 = std::clamp(rho * rho, 1e-6, 1.0);
  const double participation = templ_energy * templ_energy / templ_energy_squares;
  const double variance = 2.0 * (1.0 - r2) / (r2 * participation * beta2);
  result.sigma_samples = std::max(kMinSigmaSamples, std::sqrt(variance));
  result.usable = rho >= options.min_correlation && rho - rival >= options.min_peak_margin;
  return result;
}

// Median of values weighted by weights (both non-empty, same size).
double WeightedMedian(std::vector<std::pair<double, double>> values) {
  std::sort(values.begin(), values.end());
  double total = 0;
  for (const auto& v : values) total += v.second;
  double running = 0;
  for (const auto& v : values) {
    running += v.second;
    if (running >= 0.5 * total) return v.first;
  }
  return values.back().first;
}

// The share of each centroid shift (below) that the duration law may overstate. The law reads an
// impact's speed ratio from its impulse ratio, the ratio of the spectra's low-frequency levels
// (contact_duration.h); where a recording's loudness grows faster than the impulse, as v^p, it
// reads v^p for v and shifts p times too far, and no spectrum tells the exponents apart (fitting
// it was tried: likelihoods within 0.1-0.5, wrong picks on hard contacts). The independent
// generator's files scale loudness as v^1.2-1.5 and the synthesiser's rubber ball as v^1.5: a
// third (1 - 1/1.5) of the shift. detector_accuracy_bench's rubber on a table (48 kHz, 0.8 ms
// contact): within two stated sigmas 91 -> 96 % of the onsets, intervals 98 -> 99 %, no onset
// moved; a hard contact's shifts are a few us, and its sigmas barely move (chain-coverage bench,
// steel on an anvil: every row's coverage and trend claims the same, widths within 2 %).
constexpr double kLoudnessLawShare = 1.0 / 3.0;

// Moves each aligned onset from its contact force's centroid back to its start of contact
// (contact_duration.h) and adds the correction's own uncertainty to the alignment's: an error of
// the template's duration shifts every onset in proportion to how much longer its contact is,
// a smooth drift that the speed-trend test must not read as physics. Impacts in `informs` fix
// the durations; every usable alignment is corrected.
ContactDurations CorrectForContactDurations(const std::vector<std::vector<float>>& differences,
                                            const std::vector<std::int64_t>& lengths,
                                            std::size_t templ, std::int64_t template_start,
                                            const std::vector<bool>& informs,
                                            std::int64_t min_fit_samples, int sample_rate_hz,
                                            std::vector<Alignment>& alignments) {
  std::vector<AlignedResponse> responses;
  std::vector<std::size_t> windows;
  for (std::size_t w = 0; w < alignments.size(); ++w) {
    if (w == templ || !alignments[w].usable) continue;
    const std::int64_t n = std::min(lengths[w], lengths[templ]);
    AlignedResponse response;
    response.samples =
        std::span<const float>(differences[w])
            .subspan(static_cast<std::size_t>(alignments[w].start), static_cast<std::size_t>(n));
    response.fraction = alignments[w].fraction;
    response.informs_fit = informs[w];
    responses.push_back(response);
    windows.push_back(w);
  }
  const std::span<const float> template_response =
      std::span<const float>(differences[templ])
          .subspan(static_cast<std::size_t>(template_start),
                   static_cast<std::size_t>(lengths[templ]));
  ContactDurations durations = EstimateContactDurations(
      template_response, responses, sample_rate_hz, static_cast<std::size_t>(min_fit_samples));
  if (durations.template_s <= 0) return durations;
  const double rate = sample_rate_hz;
  for (std::size_t r = 0; r < responses.size(); ++r) {
    Alignment& alignment = alignments[windows[r]];
    const double lengthening_s = (durations.ratios[r] - 1) * durations.template_s;
    alignment.response_sample -= 0.5 * lengthening_s * rate;
    alignment.sigma_samples =
        std::hypot(alignment.sigma_samples,
                   0.5 * std::fabs(lengthening_s) *
                       std::hypot(durations.template_log_sd, kLoudnessLawShare) * rate);
  }
  return durations;
}

// Combines an impact's detector onset with an alignment's (aligned_onset, sigma_a); returns
// whether the two agreed (within kAgreementSigmas combined sigmas) and were combined, or the
// detector's onset had jumped and the alignment's replaced it. The detector's onset enters with
// the first lobe's error in quadrature, and only where weigh_detector.
bool Merge(Impact& impact, double aligned_onset, double sigma_a, double first_lobe_sigma_s,
           bool weigh_detector) {
  const double sigma_d = std::hypot(impact.onset_uncertainty_s, first_lobe_sigma_s);
  // Two measurements of one onset that differ by d leave d / 2 unexplained whichever is
  // right: a codec's pre-echo moves the detector's, but a response unlike the template's (a
  // real ball's spin or contact point) can lock the alignment a ring period away, and a
  // stated 11 us against a 2.7 ms slip would be a silent wrong answer (rubber ball, AAC 128k,
  // impact at 4.49 s, against the WAV's onset and its neighbours' ratios).
  const double disagreement_s = 0.5 * std::fabs(aligned_onset - impact.onset_s);
  if (std::fabs(aligned_onset - impact.onset_s) <=
      kAgreementSigmas * std::hypot(sigma_a, sigma_d)) {
    const double wa = 1.0 / (sigma_a * sigma_a);
    const double wd = sigma_d > 0 && weigh_detector ? 1.0 / (sigma_d * sigma_d) : 0.0;
    impact.onset_s = (wa * aligned_onset + wd * impact.onset_s) / (wa + wd);
    impact.onset_uncertainty_s = std::hypot(1.0 / std::sqrt(wa + wd), disagreement_s);
    return true;
  }
  impact.onset_s = aligned_onset;
  impact.onset_uncertainty_s = std::hypot(sigma_a, disagreement_s);
  return false;
}

// The envelopes' constant (response start minus onset) near an onset, and its scatter: the
// weighted median over the kLocalImpacts impacts nearest in time whose envelopes align, and
// 1.4826 times their median absolute deviation from it (a standard deviation robust to the few
// onsets that jumped). Local, not the recording's: an envelope rises with the contact force,
// whose duration grows as the impacts slow (tau ~ v^-1/5), so envelope and first lobe drift
// apart over a drop (ub-mth337 pingpong.wav as AAC 128k: +50 us over its first 23 bounces, +300
// us over its last 30), and an impact's jump must be told from that drift. The scatter is how
// well the envelopes reproduce the first lobe's timing in this recording, impact to impact: a
// real ball's different contact spots and a long contact (Fr4nci's ball: 0.4 ms) reshape the
// envelope's rise more than the correlation alone shows. offsets: (onset, constant, weight), by
// onset.
constexpr std::size_t kLocalImpacts = 9;
std::pair<double, double> LocalOffset(const std::vector<std::array<double, 3>>& offsets,
                                      double onset_s) {
  std::size_t hi = static_cast<std::size_t>(
      std::lower_bound(offsets.begin(), offsets.end(), onset_s,
                       [](const std::array<double, 3>& o, double t) { return o[0] < t; }) -
      offsets.begin());
  std::size_t lo = hi;
  while (hi - lo < std::min(kLocalImpacts, offsets.size())) {
    if (lo == 0 ||
        (hi < offsets.size() && offsets[hi][0] - onset_s < onset_s - offsets[lo - 1][0])) {
      ++hi;
    } else {
      --lo;
    }
  }
  std::vector<std::pair<double, double>> near;
  for (std::size_t k = lo; k < hi; ++k) near.emplace_back(offsets[k][1], offsets[k][2]);
  const double median = WeightedMedian(near);
  std::vector<double> deviations;
  for (const auto& n : near) deviations.push_back(std::fabs(n.first - median));
  std::nth_element(deviations.begin(), deviations.begin() + deviations.size() / 2,
                   deviations.end());
  return {median, 1.4826 * deviations[deviations.size() / 2]};
}

// An impact's detector onset checked against its envelopes' (onset_s, sigma_s), which resolve no
// better than tens of us but do not jump. Where the two agree within kAgreementSigmas combined
// sigmas (the detector's own, without the codec's, and the envelopes'), they are combined by
// their variances, the detector's with the first lobe's error in quadrature as in Merge: with
// its own sigma alone (+-30 us) a pre-echo-shifted first lobe outweighed envelopes that agree
// with the WAV (eeps-pingpong.wav as Vorbis q4, first bounce: detector 60-750 us early, envelopes
// 6 us from the WAV's onset; docs/codecs.md). Where they do not agree, the detector's onset
// jumped and the envelopes' replaces it. Either way the onset is stated with at least the
// envelopes' sigma (a pre-echo shift smaller than that goes unseen), and half of the distance
// that the detector's own uncertainty does not explain is added in quadrature, as for the
// waveform (Merge): a pre-echo merge already states its doubt (codecs.md), and a first lobe the
// envelopes move by 3.9 ms with a stated 2 ms (ub-mth337 pingpong.wav as Opus 64k, impact 5; the
// WAV agrees with the envelopes within 2 us) leaves nothing unexplained. Returns whether they
// agreed.
bool ConfirmOrReplace(Impact& impact, double onset_s, double sigma_s, double first_lobe_sigma_s) {
  const double own = impact.onset_uncertainty_s;
  const double distance = std::fabs(onset_s - impact.onset_s);
  const double unexplained = 0.5 * std::max(0.0, distance - 2 * own);
  const bool agree = distance <= kAgreementSigmas * std::hypot(sigma_s, own);
  if (agree) {
    const double sigma_d = std::hypot(own, first_lobe_sigma_s);
    const double wa = 1.0 / (sigma_s * sigma_s);
    const double wd = sigma_d > 0 ? 1.0 / (sigma_d * sigma_d) : 0.0;
    impact.onset_s = (wa * onset_s + wd * impact.onset_s) / (wa + wd);
  } else {
    impact.onset_s = onset_s;
  }
  impact.onset_uncertainty_s = std::hypot(sigma_s, unexplained);
  return agree;
}

// The sounds the merger set aside name the impact they lost to by its onset (MergedEvent::
// winner_s), which is how the bounce sequence later offers them as the member's other sound
// (merged_alternatives.h). A retimed impact takes its merged sounds along: left at the detector's
// onset, they belonged to no impact, and a sequence whose members were aligned on their bounces
// never saw the clicks merged into them (silent_wrong_sweep.py --precursors seed 923 #83, a 22
// kHz WAV: five members aligned, each 5-63 us from its detector onset, with a click 7.8 ms before
// it merged; the 2nd on its click at +-47 us, its bounce its later sound; whole-sequence weighing
// found 2 pairs instead of 6 and left it there, eta-bar 60 sigmas off). `detected_onsets`: the
// impacts' onsets before the retiming, in the impacts' order (Retime keeps it).
void FollowRetimedWinners(const std::vector<double>& detected_onsets, DetectionResult& detection) {
  std::vector<std::pair<double, double>> moved;  // (detected, retimed), by detected onset
  for (std::size_t i = 0; i < detected_onsets.size(); ++i) {
    if (detection.impacts[i].onset_s != detected_onsets[i]) {
      moved.emplace_back(detected_onsets[i], detection.impacts[i].onset_s);
    }
  }
  if (moved.empty()) return;
  std::sort(moved.begin(), moved.end());
  for (MergedEvent& event : detection.merged) {
    const auto at =
        std::lower_bound(moved.begin(), moved.end(),
                         std::pair{event.winner_s, -std::numeric_limits<double>::infinity()});
    if (at != moved.end() && at->first == event.winner_s) event.winner_s = at->second;
  }
}

}  // namespace

bool TransformCodec(const RecordingInfo& info) {
  if (!info.lossy) return false;
  const std::string& codec = info.codec;
  const bool sample_by_sample = codec == "pcm_mulaw" || codec == "pcm_alaw" ||
                                codec == "adpcm_ima" || codec == "adpcm_ima_wav" ||
                                codec == "adpcm_ms";
  return !sample_by_sample;
}

bool FirstLobeUnreliable(const RecordingInfo& info) {
  return info.sample_rate_hz < kLowRateHz || TransformCodec(info);
}

ResponseTimingOptions ResponseTimingFor(const RecordingInfo& info) {
  ResponseTimingOptions options;
  options.require_contact_durations = !FirstLobeUnreliable(info);
  options.envelope_alignment = TransformCodec(info);
  options.pre_echo = FirstLobeUnreliable(info);
  if (FirstLobeUnreliable(info)) options.confirming_correlation = options.min_correlation;
  return options;
}

std::int64_t ResponseTimer::SamplesBeforeOnset(int sample_rate_hz,
                                               const ResponseTimingOptions& options) {
  // One sample more before (the first difference) and one for the parabola's neighbour.
  return static_cast<std::int64_t>(std::ceil(options.search_s * sample_rate_hz)) + 2;
}

std::int64_t ResponseTimer::SamplesAfterOnset(int sample_rate_hz,
                                              const ResponseTimingOptions& options) {
  const double rate = sample_rate_hz;
  return static_cast<std::int64_t>(std::ceil(options.search_s * rate)) +
         static_cast<std::int64_t>(std::ceil(options.response_s * rate)) + 2;
}

ResponseTimer::ResponseTimer(const DetectionResult& detection, const ResponseTimingOptions& options)
    : options_(options), sample_rate_hz_(detection.sample_rate_hz) {
  const double rate = sample_rate_hz_;
  lead_ = SamplesBeforeOnset(sample_rate_hz_, options_);
  length_ = lead_ + SamplesAfterOnset(sample_rate_hz_, options_);
  for (bool tentative : {false, true}) {
    const auto& impacts = tentative ? detection.tentative : detection.impacts;
    for (std::size_t i = 0; i < impacts.size(); ++i) {
      Window window;
      window.tentative = tentative;
      window.index = i;
      window.begin = static_cast<std::int64_t>(std::llround(impacts[i].onset_s * rate)) - lead_;
      window.samples.assign(static_cast<std::size_t>(length_), 0.0f);
      windows_.push_back(std::move(window));
    }
  }
  std::stable_sort(windows_.begin(), windows_.end(),
                   [](const Window& a, const Window& b) { return a.begin < b.begin; });
}

void ResponseTimer::Process(std::span<const float> samples) {
  Fill(position_, samples);
  position_ += static_cast<std::int64_t>(samples.size());
}

void ResponseTimer::Process(const SampleStretch& stretch) { Fill(stretch.begin, stretch.samples); }

void ResponseTimer::Fill(std::int64_t begin, std::span<const float> samples) {
  const std::int64_t end = begin + static_cast<std::int64_t>(samples.size());
  // Windows are sorted by begin and have one length: those overlapping the samples are a run.
  const auto first =
      std::lower_bound(windows_.begin(), windows_.end(), begin - length_ + 1,
                       [](const Window& w, std::int64_t at) { return w.begin < at; });
  for (auto window = first; window != windows_.end() && window->begin < end; ++window) {
    const std::int64_t from = std::max(window->begin, begin);
    const std::int64_t to = std::min(window->begin + length_, end);
    std::copy(samples.begin() + (from - begin), samples.begin() + (to - begin),
              window->samples.begin() + (from - window->begin));
  }
}

ResponseTimingSummary ResponseTimer::Apply(DetectionResult& detection,
                                           double first_lobe_sigma_s) const {
  // Impacts whose stated sigma is the alignment's own; every other onset still carries the
  // first lobe's error.
  std::vector<bool> own(windows_.size(), false);
  std::vector<double> detected_onsets;
  for (const Impact& impact : detection.impacts) detected_onsets.push_back(impact.onset_s);
  const ResponseTimingSummary summary = Retime(detection, first_lobe_sigma_s, own);
  FollowRetimedWinners(detected_onsets, detection);
  // Where the next impact's onset lies, for the pre-echo's later attack: not past it.
  std::vector<std::int64_t> impact_starts;
  for (const auto& w : windows_) {
    if (!w.tentative) impact_starts.push_back(w.begin + lead_);
  }
  std::sort(impact_starts.begin(), impact_starts.end());
  for (std::size_t w = 0; w < windows_.size(); ++w) {
    Impact& impact = windows_[w].tentative ? detection.tentative[windows_[w].index]
                                           : detection.impacts[windows_[w].index];
    const std::int64_t onset = windows_[w].begin + lead_;
    const auto next = std::upper_bound(impact_starts.begin(), impact_starts.end(), onset);
    auto available = static_cast<std::int64_t>(windows_[w].samples.size()) - lead_;
    if (next != impact_starts.end()) available = std::min(available, *next - onset);
    const std::span<const float> after_onset(
        windows_[w].samples.data() + lead_,
        static_cast<std::size_t>(std::max<std::int64_t>(available, 0)));
    if (!windows_[w].tentative) {
      if (const auto later = LaterSoundOnsetS(after_onset, sample_rate_hz_)) {
        impact.later_onset_s = static_cast<double>(onset) / sample_rate_hz_ + *later;
        impact.later_sound_over_onset_db = PeakOverFirstMillisecondDb(after_onset, sample_rate_hz_);
      }
      if (const auto rise = SharpestLaterRise(after_onset, sample_rate_hz_)) {
        impact.later_rise_s = static_cast<double>(onset) / sample_rate_hz_ + rise->after_onset_s;
        impact.later_rise_db = rise->rise_db;
      }
    }
    if (own[w]) continue;
    impact.onset_uncertainty_s = std::hypot(impact.onset_uncertainty_s, first_lobe_sigma_s);
    if (options_.pre_echo) {
      impact.onset_uncertainty_s =
          std::hypot(impact.onset_uncertainty_s, 0.5 * LaterAttackS(after_onset, sample_rate_hz_));
    }
  }
  const auto by_onset = [](const Impact& a, const Impact& b) { return a.onset_s < b.onset_s; };
  std::stable_sort(detection.impacts.begin(), detection.impacts.end(), by_onset);
  std::stable_sort(detection.tentative.begin(), detection.tentative.end(), by_onset);
  return summary;
}

std::size_t ResponseTimer::ChooseTemplate(
    const DetectionResult& detection, const std::vector<std::int64_t>& lengths,
    const std::vector<std::vector<float>>& differences) const {
  const auto full = static_cast<std::int64_t>(std::ceil(options_.response_s * sample_rate_hz_));
  const auto shortest =
      static_cast<std::int64_t>(std::ceil(options_.min_response_s * sample_rate_hz_));
  const auto peak_of = [&](std::size_t w) {
    const Window& window = windows_[w];
    return (window.tentative ? detection.tentative : detection.impacts)[window.index].peak_dbfs;
  };
  const auto residual_only = [&](std::size_t w) {
    const Window& window = windows_[w];
    return (window.tentative ? detection.tentative : detection.impacts)[window.index].residual_only;
  };
  // Impacts, loudest first; those with the full response before the others. Only a
  // band-detected one can be the template; every one can judge it.
  std::vector<std::size_t> judges;
  for (std::size_t w = 0; w < windows_.size(); ++w) {
    if (!windows_[w].tentative && lengths[w] >= shortest) judges.push_back(w);
  }
  std::stable_sort(judges.begin(), judges.end(), [&](std::size_t a, std::size_t b) {
    const bool a_full = lengths[a] >= full;
    const bool b_full = lengths[b] >= full;
    if (a_full != b_full) return a_full;
    return peak_of(a) > peak_of(b);
  });
  std::vector<std::size_t> eligible;
  for (std::size_t w : judges) {
    if (!residual_only(w)) eligible.push_back(w);
  }
  if (eligible.size() <= 1) return eligible.empty() ? windows_.size() : eligible.front();
  // The loudest sound need not be an impact of the ball: a reflection that a codec made rise
  // like one, a knock, a thump. The template is the loudest of the few loudest with which at
  // least half of the other loud impacts align (a drop's bounces resemble each other; a stray
  // sound resembles nothing), or where none has that many, the one with the most. The suite's
  // pingpong_table as AAC 128k: a table reflection 14.5 ms after the first bounce, 1.5 dB
  // louder than it, was the template, every bounce correlated with it at rho 0.50-0.60 and 30
  // of 33 kept the codec table's +-967 us, where the WAV's bounces align at 0.95-0.99. Not the
  // most resembled outright: a long contact's loudest bounce resembles the later, slower ones
  // a little less (an anvil drop with 150 us contacts: 10 of 12 against a middle bounce's 11),
  // and the loudest response is the one least buried in noise.
  const std::size_t candidates = std::min(kTemplateCandidates, eligible.size());
  judges.resize(std::min(kTemplateJudges, judges.size()));
  const std::int64_t search = lead_ - 2;
  std::vector<std::vector<double>> prefixes;
  for (std::size_t judge : judges) prefixes.push_back(EnergyPrefix(differences[judge]));
  std::size_t best = eligible.front();
  std::size_t best_aligned = 0;
  for (std::size_t c = 0; c < candidates; ++c) {
    const std::size_t candidate = eligible[c];
    const TemplateSums sums(differences[candidate], static_cast<std::size_t>(lead_ - 1));
    std::size_t others = 0;
    std::size_t aligned = 0;
    for (std::size_t j = 0; j < judges.size(); ++j) {
      const std::size_t judge = judges[j];
      if (judge == candidate) continue;
      ++others;
      const std::int64_t n = std::min(lengths[judge], lengths[candidate]);
      const Alignment alignment =
          Align(differences[candidate], sums, differences[judge], prefixes[j], lead_ - 1, search, n,
                windows_[judge].begin + lead_, options_);
      if (alignment.usable) ++aligned;
    }
    if (2 * aligned >= others) return candidate;
    if (aligned > best_aligned) {
      best = candidate;
      best_aligned = aligned;
    }
  }
  return best;
}

ResponseTimingSummary ResponseTimer::Retime(DetectionResult& detection, double first_lobe_sigma_s,
                                            std::vector<bool>& own) const {
  ResponseTimingSummary summary;
  summary.considered = static_cast<int>(windows_.size());
  if (windows_.size() < 2) return summary;
  const double rate = sample_rate_hz_;
  const std::int64_t search = lead_ - 2;
  const auto full = static_cast<std::int64_t>(std::ceil(options_.response_s * rate));
  const auto shortest = static_cast<std::int64_t>(std::ceil(options_.min_response_s * rate));
  const auto impact_of = [&](const Window& w) -> Impact& {
    return w.tentative ? detection.tentative[w.index] : detection.impacts[w.index];
  };
  // The response compared ends where the next impact could begin at the largest lag.
  std::vector<std::int64_t> impact_starts;
  for (const auto& w : windows_) {
    if (!w.tentative) impact_starts.push_back(w.begin + lead_);
  }
  std::sort(impact_starts.begin(), impact_starts.end());
  std::vector<std::int64_t> lengths;
  std::vector<std::vector<float>> differences;
  for (const auto& w : windows_) {
    const std::int64_t onset = w.begin + lead_;
    const auto next = std::upper_bound(impact_starts.begin(), impact_starts.end(), onset);
    std::int64_t n = full;
    if (next != impact_starts.end()) n = std::min(n, *next - onset - search);
    lengths.push_back(n);
    differences.push_back(FirstDifference(w.samples));
  }
  const std::size_t templ = ChooseTemplate(detection, lengths, differences);
  if (templ == windows_.size()) return summary;
  summary.template_onset_sample = windows_[templ].begin + lead_;
  std::vector<Alignment> alignments(windows_.size());
  const TemplateSums templ_sums(differences[templ], static_cast<std::size_t>(lead_ - 1));
  for (std::size_t w = 0; w < windows_.size(); ++w) {
    const std::int64_t n = std::min(lengths[w], lengths[templ]);
    if (n < shortest) continue;
    // Difference signals start one sample later than the windows: lead - 1 samples before
    // the onset sample, so the parabola's neighbour at the largest lag stays inside.
    alignments[w] =
        Align(differences[templ], templ_sums, differences[w], EnergyPrefix(differences[w]),
              lead_ - 1, search, n, windows_[w].begin + lead_, options_);
  }
  std::vector<bool> informs(windows_.size(), false);
  for (std::size_t w = 0; w < windows_.size(); ++w) {
    informs[w] = !windows_[w].tentative && !impact_of(windows_[w]).residual_only;
  }
  const ContactDurations durations = CorrectForContactDurations(
      differences, lengths, templ, lead_ - 1, informs, full / 2, sample_rate_hz_, alignments);
  summary.contact_duration_s = durations.template_s;
  summary.contact_duration_log_sd = durations.template_log_sd;
  const bool corrected = durations.template_s > 0;
  if (!corrected && options_.require_contact_durations) return summary;
  // Only relative times matter: the response start and the onset differ by one constant for the
  // recording, taken as the median over the impacts weighted by their detector precision, the
  // first lobe's error included: in a lossy file a template whose onset a pre-echo moved, stated
  // with its clean lobe's tens of us, outweighed every other impact and set the constant alone
  // (silent_wrong_sweep.py seed 9 #27's drop as MP3 64k: the aligned bounces 1.3 ms off the ones
  // left on their detector onsets, eta-bar 0.3616 +- 0.0069 against 0.3455).
  std::vector<std::pair<double, double>> offsets;
  for (std::size_t w = 0; w < windows_.size(); ++w) {
    if (!alignments[w].usable || windows_[w].tentative) continue;
    const Impact& impact = impact_of(windows_[w]);
    const double sigma =
        std::max(std::hypot(impact.onset_uncertainty_s, first_lobe_sigma_s), 1.0 / rate);
    offsets.emplace_back(impact.onset_s - alignments[w].response_sample / rate,
                         1.0 / (sigma * sigma));
  }
  // The detector's onsets as they were, for the envelope stage's own constant below.
  std::vector<std::pair<double, double>> detected(windows_.size());
  for (std::size_t w = 0; w < windows_.size(); ++w) {
    const Impact& impact = impact_of(windows_[w]);
    detected[w] = {impact.onset_s, impact.onset_uncertainty_s};
  }
  if (offsets.size() >= 2) {
    const double offset = WeightedMedian(std::move(offsets));
    for (std::size_t w = 0; w < windows_.size(); ++w) {
      const Alignment& alignment = alignments[w];
      if (!alignment.usable) continue;
      ++summary.aligned;
      Impact& impact = impact_of(windows_[w]);
      // A response this much like the template's, with the ringing before it removed, is an
      // impact of the same ball on the same surface, not speech or handling noise: the evidence
      // that residual_only stands for is no longer weak (confirming_correlation).
      if (impact.residual_only && alignment.correlation >= options_.confirming_correlation) {
        impact.residual_only = false;
        impact.confirmed_by_response = true;
      }
      // The alignment's sigma covers its own error (codec bench: 100 % of the errors within
      // 1.96 sigma at AAC 128k, Opus 64k, MP3 128k and Vorbis q4, docs/codecs.md), so an
      // aligned impact's onset is stated with it; the detector's onset enters with the first
      // lobe's error, which leaves it little weight where that error is a codec's.
      own[w] = true;
      impact.timed_from_response = true;
      ++summary.own_sigma;
      // Corrected alignments are not combined with the detector's onset: a first lobe's pick
      // drifts with the contact's duration too (+30 to +80 us over 8 bounces of a steel ball on
      // an anvil, where the corrected alignments stay within 1 us), and even the tenth of the
      // weight it would get passed 3 us of that drift on, a 2.6 sigma speed trend over five
      // such recordings.
      if (Merge(impact, alignment.response_sample / rate + offset, alignment.sigma_samples / rate,
                first_lobe_sigma_s, !corrected)) {
        ++summary.combined;
      } else {
        ++summary.replaced;
      }
    }
  }
  if (!options_.envelope_alignment) return summary;
  // Where every impact's waveform aligned, the envelopes would only be references: nothing to do.
  bool unaligned = false;
  for (std::size_t w = 0; w < windows_.size() && !unaligned; ++w) {
    unaligned = !own[w] && std::min(lengths[w], lengths[templ]) >= shortest;
  }
  if (!unaligned) return summary;
  // The impacts whose waveform did not align, from their band envelopes (envelope_alignment.h).
  const EnvelopeAligner aligner(sample_rate_hz_, windows_[templ].samples, lead_, search - 1);
  std::vector<EnvelopeAlignment> envelopes(windows_.size());
  // (onset, envelope's constant, weight) of every impact whose envelopes align, by onset.
  std::vector<std::array<double, 3>> envelope_offsets;
  for (std::size_t w = 0; w < windows_.size(); ++w) {
    const std::int64_t n = std::min(lengths[w], lengths[templ]);
    if (n < shortest) continue;
    envelopes[w] = aligner.Align(windows_[w].samples, n);
    if (!envelopes[w].usable || windows_[w].tentative) continue;
    const double sigma = std::max(detected[w].second, 1.0 / rate);
    envelope_offsets.push_back({detected[w].first,
                                detected[w].first -
                                    static_cast<double>(windows_[w].begin + lead_) / rate -
                                    envelopes[w].lag_samples / rate,
                                1.0 / (sigma * sigma)});
  }
  // Three at least: with two, the median is one of them and a jumped onset would set it.
  if (envelope_offsets.size() < 3) return summary;
  for (std::size_t w = 0; w < windows_.size(); ++w) {
    if (own[w] || !envelopes[w].usable) continue;
    const auto [offset, scatter] = LocalOffset(envelope_offsets, detected[w].first);
    const double envelope_onset =
        (static_cast<double>(windows_[w].begin + lead_) + envelopes[w].lag_samples) / rate + offset;
    const double envelope_sigma = std::hypot(envelopes[w].sigma_samples / rate, scatter);
    ++summary.envelope_aligned;
    own[w] = true;
    impact_of(windows_[w]).timed_from_response = true;
    ++summary.own_sigma;
    Impact& impact = impact_of(windows_[w]);
    const bool agreed =
        ConfirmOrReplace(impact, envelope_onset, envelope_sigma, first_lobe_sigma_s);
    // A sound heard only in the ringing keeps at least the sigma the detector stated for it: its
    // envelopes are mostly the ringing's, and where they lock on the ringing's rise instead of
    // its own, nothing in the alignment shows it. The suite's 360 codec copies (both settings of
    // shared_codec_eta.py) held 98 such sequence members: median error 80 us, but p95 3.1 ms
    // against a median stated 173 us, 89.8 % within 1.96 sigmas and 7 beyond 3 (very_high_e as
    // AAC at 22 kHz +5.0 ms at +-550 us, multi_drop_30s as AAC and MP3 at 16 kHz -2.6 ms at
    // +-217-240 us). Floored so: 94.9 % and 1; no onset moves.
    if (impact.residual_only) {
      impact.onset_uncertainty_s = std::max(impact.onset_uncertainty_s, detected[w].second);
    }
    if (agreed) {
      ++summary.combined;
    } else {
      ++summary.replaced;
    }
  }
  return summary;
}

ResponseTimingSummary RetimeFromResponses(DetectionResult& detection,
                                          std::span<const float> samples, double first_lobe_sigma_s,
                                          const ResponseTimingOptions& options) {
  ResponseTimer timer(detection, options);
  timer.Process(samples);
  return timer.Apply(detection, first_lobe_sigma_s);
}

}  // namespace bouncecal::audio
