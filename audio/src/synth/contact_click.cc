#include "synth/contact_click.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "synth/modal_impact.h"

namespace bouncecal::audio {

void AddContactClicks(std::span<const ContactClick> clicks, double sample_rate_hz,
                      std::int64_t first_index, std::span<float> out) {
  const std::int64_t end = first_index + static_cast<std::int64_t>(out.size());
  for (const ContactClick& click : clicks) {
    const std::int64_t start =
        std::max(first_index, FirstSampleAtOrAfter(click.arrival_s, sample_rate_hz));
    const std::int64_t stop =
        std::min(end, FirstSampleAtOrAfter(click.arrival_s + click.contact_s, sample_rate_hz));
    for (std::int64_t index = start; index < stop; ++index) {
      const double t_s = static_cast<double>(index) / sample_rate_hz - click.arrival_s;
      out[static_cast<size_t>(index - first_index)] +=
          static_cast<float>(click.peak * std::sin(std::numbers::pi * t_s / click.contact_s));
    }
  }
}

}  // namespace bouncecal::audio
