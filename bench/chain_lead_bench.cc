// How early a recording chain puts an impact's energy before its contact (issue 16): the table
// of docs/synthesis.md. For one impact at the reference speed (so its contact lasts exactly
// contact_duration_s) on the default steel plate or the counter top, with the contact click at
// click_gain 0.2, it prints, for 16, 44.1 and 48 kHz, 35 and 70 us contacts and each filter,
// the time relative to the true onset at which |x| first exceeds 1 % and 5 % of the impact's
// peak: the earliest and the median over 16 sub-sample positions of the onset (the filter's
// ringing depends on where the contact falls between samples).
// Usage: chain_lead_bench
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "bouncecal/audio/synthesize.h"

namespace {

using bouncecal::audio::AdcFilterPhase;
using bouncecal::audio::PlateMode;
using bouncecal::audio::RecordingChain;
using bouncecal::audio::SynthesisOptions;

constexpr int kPositions = 16;

// First time |x| exceeds fraction x peak, relative to the onset (s).
double Crossing(const std::vector<float>& x, double rate, double onset_s, double peak,
                double fraction) {
  for (size_t i = 0; i < x.size(); ++i) {
    if (std::abs(x[i]) > fraction * peak) return static_cast<double>(i) / rate - onset_s;
  }
  return NAN;
}

struct Summary {
  double earliest_us;
  double median_us;
};

Summary Summarise(std::vector<double> times_s) {
  std::sort(times_s.begin(), times_s.end());
  const double median = 0.5 * (times_s[(times_s.size() - 1) / 2] + times_s[times_s.size() / 2]);
  return {times_s.front() * 1e6, median * 1e6};
}

}  // namespace

int main() {
  std::printf(
      "| surface | rate (Hz) | contact (us) | filter | 1 %%: earliest / median (us) | "
      "5 %%: earliest / median (us) |\n|---|---|---|---|---|---|\n");
  const std::pair<const char*, std::vector<PlateMode>> surfaces[] = {
      {"steel plate", bouncecal::audio::SteelPlateModes()},
      {"counter top", bouncecal::audio::CounterTopModes()}};
  for (const auto& [surface, modes] : surfaces) {
    for (int rate : {16000, 44100, 48000}) {
      for (double contact_s : {35e-6, 70e-6}) {
        for (const std::optional<AdcFilterPhase> phase :
             {std::optional(AdcFilterPhase::kLinear), std::optional(AdcFilterPhase::kMinimum),
              std::optional<AdcFilterPhase>()}) {
          std::vector<double> one, five;
          for (int k = 0; k < kPositions; ++k) {
            SynthesisOptions options;
            options.sample_rate_hz = rate;
            const double onset_s = 0.1 + (k + 0.5) / kPositions / rate;
            options.impacts = {{onset_s, options.reference_speed_mps}};
            options.duration_s = 0.15;
            options.contact_duration_s = contact_s;
            options.click_gain = 0.2;
            options.modes = modes;
            if (phase) options.chain = RecordingChain{.phase = *phase};
            const auto recording = bouncecal::audio::SynthesizeBounces(options);
            const double peak = recording.events[0].peak_amplitude;
            one.push_back(Crossing(recording.channels[0].samples, rate, onset_s, peak, 0.01));
            five.push_back(Crossing(recording.channels[0].samples, rate, onset_s, peak, 0.05));
          }
          const Summary a = Summarise(one), b = Summarise(five);
          std::printf("| %s | %d | %.0f | %s | %+.0f / %+.0f | %+.0f / %+.0f |\n", surface, rate,
                      contact_s * 1e6,
                      phase ? std::string(ToString(*phase)).c_str() : "none (no chain)",
                      a.earliest_us, a.median_us, b.earliest_us, b.median_us);
        }
      }
    }
  }
  return 0;
}
