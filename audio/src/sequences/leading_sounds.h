#ifndef BOUNCECAL_AUDIO_SRC_SEQUENCES_LEADING_SOUNDS_H_
#define BOUNCECAL_AUDIO_SRC_SEQUENCES_LEADING_SOUNDS_H_

#include <cstddef>
#include <vector>

#include "bouncecal/audio/bounce_sequences.h"
#include "bouncecal/audio/impact_detector.h"

namespace bouncecal::audio {

// A knock, a thump, speech or the release before a drop can land where a bounce before the
// first would be, and a chain of bounces then starts at it: its first ratio, and so its eta-bar,
// is wrong at exit 0 (bench/knock_sweep.py). These judge a chain's first members (indices into
// `impacts`, in time order) against what its later bounces show, and return how many of them
// are such sounds; the chain starts after them.

// By timing: a leading ratio far off the line through the next 4-6 ratios.
std::size_t LeadingSoundsBeforeTheDrop(const std::vector<Impact>& impacts,
                                       const std::vector<int>& members);

// By timing, in a chain of 5 or 6 members (too few for that line): whether its first ratio r_0 =
// D_2 / D_1 (D_k the flight between members k - 1 and k) differs from the ball's restitution over
// its later flights, e = (D_L / D_2)^(1 / (L - 2)) (L its last flight, whose members are not
// D_2's), by more than a ball's step (0.12, the chain finder's default ratio_step_tolerance) plus
// 3 sigmas of the members' stated onsets propagated through both, each member once. A first
// flight over a bounce nobody heard reads e^2 / (1 + e), 0.39 for e = 0.855: zaky-ptv's ping-pong
// as G.711 at 8 kHz answered with such a chain of the ball's last bounces (0.4055, then 0.857 and
// 0.853), eta-bar 0.4579 +- 0.027 against the WAV's 0.2527. The chain then starts at its second
// member, which answers to the chance test as if found so (FindBounceSequences).
bool ShortChainsFirstFlightMisfits(const std::vector<Impact>& impacts,
                                   const std::vector<int>& members);

// By timing too, but choosing: a chain's first member is the loudest of the sounds that could start
// it (ChainFinder::Better breaks ties by loudness), and an impact's echo 12-30 ms after it (beyond
// the detector's merge gap) can be the louder. Where the first ratio misses the line through the
// next 4-6 ratios by more than 3 sigmas and another free band-detected sound within 30 ms of the
// first member gives a first ratio within 2 sigmas of it, the best fitting such sound is the first
// member. Returns the index into `impacts` of the member that starts the chain (members[0] where
// none fits better). Why: pingpong_table of the detector suite as AAC 128k started its sequence at
// a room reflection 15.7 ms after the first bounce, 1.5 dB louder than it (e_1 0.8925 against
// 0.8616, eta-bar 0.0181 off at 6 sigmas, exit 0).
int FirstMemberThatFitsTheDrop(const std::vector<Impact>& impacts, const std::vector<bool>& free,
                               const std::vector<int>& members);

// Choosing by timing and level together: a chain of sounds before a drop runs into the drop's
// later bounces over its first bounce, which then lies inside one of the chain's early flights,
// where no bounce can be while the ball is in the air. Where a free band-detected sound inside the
// flight after member k (k < 4) is louder than member k + 1 (a bounce before hits faster and
// sounds louder than the next), and the chain from it through members k + 1 on has its first
// ratio within 2 sigmas of the line through the next 4-6 ratios while the chain's own ratio at
// member k misses that line by more than 3, the best fitting such sound heads the chain in place
// of members 0..k. Returns how many leading members it replaces and the sound (0 and -1 where
// none). Why: bench/knock_sweep.py seed 1000 #287 (no drop height): two knocks 0.88 s apart,
// 14 dBFS, then the drop's 2nd bounce, its 1st (-5.0 dBFS, the loudest sound of the file)
// rejected as a stray sound in the flight from the 2nd knock; ratios 0.568, 0.577, then 0.687 on;
// eta-bar 0.6241 +- 0.00005 against the drop's 0.5280. It was also to be louder than every member
// it replaces (sounds before a drop that a ball's earlier bounces would have out-levelled), which
// kept #97's knock (-9 dBFS) ahead of the drop's first bounce (-11 dBFS, fitting) and seed 5000
// #0's sound at 0 dBFS (the bounce -5 dBFS): without it both knock sweeps have one confidently
// wrong start fewer (11 -> 10, 20 -> 19) and the 15200 files of silent_wrong_sweep.py no answer
// changed.
struct HeadInAnEarlyFlight {
  std::size_t replaced = 0;
  int impact = -1;
};
HeadInAnEarlyFlight LouderHeadInAnEarlyFlight(const std::vector<Impact>& impacts,
                                              const std::vector<bool>& free,
                                              const std::vector<int>& members);

// By level: a leading member much quieter than the next, where a bounce before it would have hit
// faster and so sounded louder. Never leaves fewer than `fewest_left` members.
std::size_t LeadingSoundsQuieterThanTheDrop(const std::vector<Impact>& impacts,
                                            const std::vector<int>& members,
                                            std::size_t fewest_left);

// Stating, not choosing: a leading ratio (of the first kLeadingRatiosJudged) that misses what the
// ratios after it show by more than Student's t of their scatter and its own stated timing
// together (the line through the next 4-6 at 1e-2 two-sided; the mean of the next 3, 2 degrees
// of freedom, at 1e-3; below them with an allowance for a ball's restitution falling with impact
// speed), where the rules above (at 1e-4, and on level) kept it. The members up to its middle one
// may be sounds before the drop, so every flight up to that member may be any length; bounces
// before it would have flown the next flight over the later ratios' value, once per bounce back.
// Each flight's distance from that is its uncertainty (Impact::incoming_flight_uncertainty_s of
// the member it ends at): the answer stays, and states the alternative one sigma away. Why:
// bench/knock_sweep.py seed 1000 (300 drops with knocks, thumps, speech and stray sounds before
// them, no drop height): 21 of 245 sequences began at such a sound with eta-bar off by more than
// 0.002 and 3 stated sigmas at exit 0, 10 of them with a leading ratio 5-87 of these sigmas off
// the later ones (#213: a stray sound, then a drop whose 6 later ratios read 0.716 but whose last
// member, stated +-5.7 ms, kept the line's scatter wide enough for the 1e-4 cut; 0.752 first;
// #222: two sounds, the second ratio 0.800 against 0.739); seed 5000: 23 -> 20. Over the 13200 +
// 2000 files of silent_wrong_sweep.py 2 of 7080 sequences have such a ratio: u_948 #20 (its
// second member 16 ms early at a stated 51 us) and 966p #37 (1.6 sigmas off, now 0.4). Run after
// the other doubts, on the members' final sigmas.
void DoubtLeadingFlightsOffTheLaterRatios(std::vector<Impact>& impacts,
                                          const std::vector<BounceSequence>& sequences);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_SEQUENCES_LEADING_SOUNDS_H_
