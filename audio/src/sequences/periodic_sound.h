#ifndef BOUNCECAL_AUDIO_SRC_SEQUENCES_PERIODIC_SOUND_H_
#define BOUNCECAL_AUDIO_SRC_SEQUENCES_PERIODIC_SOUND_H_

#include <cstddef>
#include <optional>
#include <vector>

#include "bouncecal/audio/impact_detector.h"

namespace bouncecal::audio {

// A sound that repeats at a fixed period puts detected events on a lattice t0 + k P: mains hum
// heard as impacts (the detector suite's hum_dc as 8 kHz mu-law: 60 Hz peaks every 16.7 ms), a
// motor, a ticking clock. Chains along a lattice time perfectly, with any ratio the rounding of
// their flights to multiples of P allows (1.000, or halving flights), and the chance test, which
// models random events as Poisson, cannot tell them from a ball.
struct PeriodicSound {
  double period_s = 0;
  // How far from a multiple of the period an interval of two of its events may lie: kHalfWidthS,
  // or where the lattice's own intervals scatter more, kJitterWidths of their robust sd (up to a
  // tenth of the period).
  double half_width_s = 0;
  // Pairs of events (each event with its next kNeighbours) a whole number of periods apart, up
  // to kMultiples (within kHalfWidthS).
  int lattice_pairs = 0;
  // Per impact: another event lies one or two periods away (within half_width_s).
  std::vector<bool> on_lattice;
};

// The period of the file's events, where their pairwise intervals fall on multiples of one period
// in [min_period_s, max_period_s] far more often than intervals at random would (a binomial tail
// below kPeriodChance over the periods tried); nullopt where none does. `impacts` sorted by onset.
std::optional<PeriodicSound> FindPeriodicSound(const std::vector<Impact>& impacts,
                                               double min_period_s, double max_period_s);

// The probability that at least as many of a chain's flights as lie on multiples of the period
// would if the flights fell at random relative to it, "on" meaning within half_width_s or, in a
// second count, within twice the two members' combined sigma where that is wider (twice the
// smaller chance). A bouncing ball's flights do not care about the period; a chain along the
// lattice has all of them there. `members` in time order.
double ChanceOfFlightsOnTheLattice(const std::vector<Impact>& impacts,
                                   const std::vector<int>& members, const PeriodicSound& sound);

// How many of a chain's first members are events of the periodic sound before the drop: each
// with an event of the file one or two periods before or after it, not much quieter than itself,
// while the two members after them are on no lattice slot (PeriodicSound::on_lattice). A sound
// that repeats before a drop has events wherever the chain finder looks for a bounce before the
// first, and one whose ratio fits by chance can begin the sequence: hum events 20 ms apart offer
// first ratios 0.03 apart for a first flight of 0.5 s, so the ratio cannot tell them. A first
// bounce lies so by chance a few times in a hundred where the sound is as loud as the bounce (a
// limiter's ceiling), and is then lost from the sequence, not misread. Never leaves fewer than
// `fewest_left` members (at least 3).
std::size_t LeadingEventsOfThePeriodicSound(const std::vector<Impact>& impacts,
                                            const std::vector<int>& members,
                                            const PeriodicSound& sound, std::size_t fewest_left);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SEQUENCES_PERIODIC_SOUND_H_
