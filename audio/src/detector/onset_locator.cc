#include "detector/onset_locator.h"

#include <algorithm>
#include <cmath>

#include "detector/onset_picker.h"
#include "detector/prediction_innovation.h"

namespace bouncecal::audio {
namespace {

// Noise before the onset that the AIC picker sees (bounded by the previous impact's peak).
constexpr double kPickerNoiseMs = 4.0;
// Window after the onset in which peak_dbfs is measured.
constexpr double kPeakLevelMs = 5.0;
// Order of the linear predictor that removes ringing before picking an onset inside it: two
// coefficients per mode, so up to 12 modes in the band (a plate's strong low modes).
constexpr int kInnovationOrder = 24;
// Samples per predictor coefficient in the stretch before the search it is fitted on. The
// picker's kPickerNoiseMs give 8 at 48 kHz, where the innovation was measured; at a lower rate
// the same milliseconds hold fewer samples (64 at 16 kHz, under the 4 per coefficient below which
// PredictionInnovation refuses to fit), so the innovation was skipped and the onset picked on the
// tail itself. The fit spans at least this many samples per coefficient at every rate.
constexpr int kInnovationFitSamplesPerCoefficient = 8;
// History kept for the picker and the peak level; longer than every window above together.
constexpr double kHistoryS = 0.1;

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

std::optional<LocatedImpact> OnsetLocator::Locate(const Candidate& candidate) {
  const EnvelopeBand& band = bands_.band(candidate.band);
  const std::int64_t hop = frames_.hop;
  // SNR in the band that rose most: its loudest frame of the candidate against its floor.
  double band_peak_db = band.Db(candidate.frame);
  for (std::int64_t i = candidate.frame + 1; i <= candidate.closed_at; ++i) {
    band_peak_db = std::max(band_peak_db, band.Db(i));
  }
  const double snr_db = band_peak_db - band.FloorDb(candidate.closed_in_block);
  // Under continuous ringing the minimum-statistics floor of every band is the ringing, not the
  // noise; the ringing residual's floor stays at the noise, so passing in it also counts.
  // snr_db itself stays the band's, so the channel choice compares like with like.
  const bool band_snr_ok = snr_db >= min_snr_db_;
  if (!band_snr_ok) {
    const EnvelopeBand& level = bands_.band(0);
    double peak_db = level.Db(candidate.frame);
    for (std::int64_t i = candidate.frame + 1; i <= candidate.closed_at; ++i) {
      peak_db = std::max(peak_db, level.Db(i));
    }
    if (residual_.SnrDb(peak_db) < min_snr_db_) return std::nullopt;
  }
  // The onset is picked in the same band, where the impact stands out most from what was there
  // before (unless the recording holds too little of that band, below); the window ends at the
  // impact's largest sample.
  const SampleHistory<float>& samples = bands_.band(PickBand(candidate.band)).samples;
  // Where no band rose by the full threshold the impact sits in a tail louder than itself, so
  // the band's largest sample and its AIC edge are the tail's: the onset is picked on the
  // prediction innovation instead (measured on the free plate: 61.9 us median against 68.6 us
  // when only rises under half the threshold took this path; the sample steel_ball_h0.2m.wav's
  // 5th impact 0.6 ms instead of 1.5 ms early).
  const bool in_ringing = candidate.rise_db < rise_threshold_db_;
  std::int64_t search_from = (candidate.frame - 2 * frames_.skip) * hop;
  if (in_ringing) {
    // The residual's frame that fired ended by the frame that opened the candidate, and the
    // onset lies inside that frame's window (its Hann taper hides a new sound at the window's
    // end, so the novelty may rise a few ms after the onset): search from the window's start.
    search_from =
        std::min(search_from, (candidate.opened_at + 1) * hop - residual_.window_samples());
  }
  const std::int64_t search_begin = std::max(samples.begin(), search_from);
  const std::int64_t peak_end = std::min(
      samples.end(), (std::max(candidate.peak_frame, candidate.band_peak_frame) + 1) * hop);
  std::int64_t peak = search_begin;
  for (std::int64_t i = search_begin; i < peak_end; ++i) {
    if (std::fabs(samples[i]) > std::fabs(samples[peak])) peak = i;
  }
  std::int64_t noise_samples = frames_.Samples(kPickerNoiseMs * 1e-3);
  if (in_ringing) {
    noise_samples = std::max<std::int64_t>(noise_samples,
                                           kInnovationFitSamplesPerCoefficient * kInnovationOrder);
  }
  const std::int64_t window_begin =
      std::max({samples.begin(), search_begin - noise_samples, last_peak_sample_ + 1});
  std::int64_t window_end = std::min(samples.end(), peak + 2);
  const auto begin_offset =
      static_cast<std::size_t>(std::max<std::int64_t>(0, search_begin - window_begin));
  if (in_ringing) {
    // The largest sample is the tail's: the onset is picked on the innovation, up to its
    // largest innovation sample within the candidate.
    window_end = std::min(samples.end(), (candidate.peak_frame + frames_.peak + 1) * hop);
  }
  window_.clear();
  for (std::int64_t i = window_begin; i < window_end; ++i) window_.push_back(samples[i]);
  std::int64_t pick_begin = window_begin;
  std::size_t pick_offset = begin_offset;
  if (in_ringing) {
    auto innovation = PredictionInnovation(window_, begin_offset, kInnovationOrder);
    const std::size_t skipped = window_.size() - innovation.size();
    if (skipped > 0 && begin_offset > skipped) {
      window_ = std::move(innovation);
      pick_begin += static_cast<std::int64_t>(skipped);
      pick_offset -= skipped;
      std::size_t top = pick_offset;
      for (std::size_t i = pick_offset; i < window_.size(); ++i) {
        if (std::fabs(window_[i]) > std::fabs(window_[top])) top = i;
      }
      peak = pick_begin + static_cast<std::int64_t>(top);
      window_.resize(std::min(window_.size(), top + 2));
    }
  }
  const auto end_offset =
      static_cast<std::size_t>(std::max<std::int64_t>(0, peak + 1 - pick_begin));
  const OnsetPick pick = PickOnset(window_, pick_offset, end_offset);
  // The rest of a sound whose candidate closed while rising cannot pick an onset before that
  // candidate's peak: when its search starts before that peak its onset is not trusted.
  const bool continuation = candidate.continues && search_begin <= last_peak_sample_;
  last_peak_sample_ = peak;

  LocatedImpact located;
  Impact& impact = located.impact;
  const double start_index = static_cast<double>(pick_begin) + pick.index;
  double onset_index = start_index;
  impact.onset_uncertainty_s = pick.sigma_samples / frames_.rate_hz;
  if (std::isfinite(pick.reference_index)) {
    onset_index = static_cast<double>(pick_begin) + pick.reference_index;
    impact.onset_uncertainty_s = pick.reference_sigma_samples / frames_.rate_hz;
    located.by_reference = true;
    if (std::isfinite(pick.edge_amplitude)) {
      located.reference_lead_s = (pick.reference_index - pick.index) / frames_.rate_hz;
    }
  }
  if (candidate.later_sound_frame >= 0) {
    // Two sounds in one candidate, the later louder by the full threshold: the impact is either
    // the one picked or the later one (a precursor picked instead of its impact, 2-10 ms early,
    // was 5 and 60 stated sigmas off in bench/silent_wrong_sweep.py). Half their distance in
    // quadrature covers both.
    const double gap = static_cast<double>(candidate.later_sound_frame * hop) - onset_index;
    if (gap > 0) {
      impact.onset_uncertainty_s =
          std::hypot(impact.onset_uncertainty_s, 0.5 * gap / frames_.rate_hz);
    }
  }
  impact.onset_s = onset_index / frames_.rate_hz;
  impact.rise_db = candidate.rise_db;
  // The residual's rise is kept scaled to the band threshold for the decisions; reported in its
  // own unit.
  impact.ringing_novelty_db = std::isfinite(candidate.residual_rise_db)
                                  ? residual_.NoveltyDb(candidate.residual_rise_db)
                                  : std::numeric_limits<double>::quiet_NaN();
  impact.snr_db = snr_db;
  impact.residual_only = !band_snr_ok;
  const std::int64_t level_begin =
      std::max<std::int64_t>(raw_.begin(), std::llround(std::floor(onset_index)));
  const std::int64_t level_end =
      std::min(raw_.end(), level_begin + frames_.Samples(kPeakLevelMs * 1e-3));
  double peak_abs = 0;
  for (std::int64_t i = level_begin; i < level_end; ++i) {
    peak_abs = std::max(peak_abs, double{std::fabs(raw_[i])});
  }
  impact.peak_dbfs = 20.0 * std::log10(std::max(peak_abs, 1e-7));
  located.band = candidate.band;
  located.onset_sample = onset_index;
  located.span_end_sample = (candidate.closed_at + 1) * hop;
  located.rise_db = std::max(candidate.rise_db, candidate.residual_rise_db);
  located.band_rise_db = candidate.rise_db;
  located.band_rose = !in_ringing;
  located.continuation = continuation;
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
