#include "sequences/merged_alternatives.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace bouncecal::audio {
namespace {

// ln of an interval ratio scatters by the restitution's relative scatter, which the sequence's
// other ratios show: twice their median absolute deviation about the line, 1.35 times the sd it
// estimates (1.4826 MAD), since that sd from 6-12 ratios is uncertain by about 40 % and an
// underestimate is what lets a precursor take a bounce's onset; never below 1 %, since a few
// ratios can agree by chance.
constexpr double kMinLnRatioScatter = 0.01;
constexpr double kScatterOverMad = 2.0;
// How much better (in the sum of squared misfits over the scatter squared) the merged sound must
// continue the ratios: a likelihood ratio of e^6 between the two onsets. With 3 % scatter of e a
// precursor 3 ms before a bounce, or an echo 3 ms after it, then takes its onset in 1.5 % of drops
// (the ball's own scatter at that bounce is what the other sound smooths;
// merged_alternatives_test.cc).
constexpr double kRequiredImprovement = 12.0;
// A merged sound more than this much quieter than the member over the same span (two of the
// detector's 10 dB rise thresholds, a hundredfold in power) is no alternative: a precursor rings
// into its bounce and keeps their candidate together only while the bounce rises less than one
// threshold above it (docs/detector.md), and levels differ from bounce to bounce by a few dB, so
// a sound that faint is not what another member could have been timed on. With 3 % scatter of e
// the ratios of a 7-bounce drop alone preferred a sound 38 dB under the second bounce, 10.9 ms
// before it (the coverage suite's copper_e065_j3_s3113).
constexpr double kMaxQuieterDb = 20.0;
// Ratios on each side of the member that the reference line is fitted on.
constexpr int kReferenceReach = 6;
// The second and third members, and the last two but one, have reference ratios on one side
// only: the line is extrapolated to the ratios they move, and one of those few reference members
// a few ms off (on an echo or a click of its own) tilts it by more than the ball's scatter. There
// the neighbours weigh only a merged sound within one rise threshold of the member. In
// silent_wrong_sweep.py's 8516 files (stop 67) such members took sounds 10.8-17.8 dB under them
// in 10 files, each member within 0.9 ms of its bounce and moved 2.4-10 ms early onto a click;
// in 9 the other members were on their bounces, with a reference member 1.7 ms or more off in 8
// (seed 927 #101: eta-bar 0.0125 off). Without these moves eta-bar came 0.0022-0.0104 closer to
// the truth in 7 files and went 0.0020-0.0022 further in 2, to 0.2 and 0.3 sigmas (in 923p #155
// the other members were on their clicks). The coverage suite's copper_e065_j3_s3113
// resampled to 44.1 kHz moved its second bounce onto a noise sound 19.8 dB under it, 6 ms early,
// and read eta-bar 12 sigmas off. Members with ratios on both sides keep kMaxQuieterDb: a click
// 10-14 dB under its bounce is the precursor pattern.
constexpr double kMaxQuieterExtrapolatedDb = 10.0;

// Whether the reference ratios of member k (Misfit) lie on one side of the two it moves.
bool ReferenceOnOneSide(int k, int members) { return k - 2 < 1 || k + 2 > members - 2; }

// A sound before a band-detected member that it out-levelled by less than this (the detector's
// default rise threshold) may have been the start of the member's own sound.
constexpr double kCloseLevelDb = 10.0;

struct RatioFit {
  double misfit = 0;   // sum of squared misfits in ln of the ratios member k moves
  double scatter = 0;  // robust sd of the other ratios about the line
};

// The upper median (values is reordered).
double Median(std::vector<double>& values) {
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// ln_ratio[j] = ln((t[j+1] - t[j]) / (t[j] - t[j-1])), j = 1 .. n-2 (0 at the ends).
std::vector<double> LnRatios(const std::vector<double>& times) {
  std::vector<double> ln_ratio(times.size(), 0.0);
  for (std::size_t j = 1; j + 1 < times.size(); ++j) {
    ln_ratio[j] = std::log((times[j + 1] - times[j]) / (times[j] - times[j - 1]));
  }
  return ln_ratio;
}

// The squared misfits of the ratios `scored` summed about the Theil-Sen line through the ratios
// `reference`, and the robust scatter of those about it. Theil-Sen: the median of the pairwise
// slopes, then of the intercepts. A chain's last ratios (chatter, in-ringing members) can be far
// off, and a least-squares line would tilt to them.
RatioFit FitAgainstLine(const std::vector<double>& ln_ratio, const std::vector<int>& reference,
                        const std::vector<int>& scored) {
  const auto at = [&](int j) { return ln_ratio[static_cast<std::size_t>(j)]; };
  std::vector<double> slopes;
  for (std::size_t a = 0; a < reference.size(); ++a) {
    for (std::size_t b = a + 1; b < reference.size(); ++b) {
      slopes.push_back((at(reference[b]) - at(reference[a])) / (reference[b] - reference[a]));
    }
  }
  const double slope = Median(slopes);
  std::vector<double> intercepts;
  for (int j : reference) intercepts.push_back(at(j) - slope * j);
  const double intercept = Median(intercepts);
  RatioFit fit;
  for (int j : scored) {
    const double d = at(j) - (intercept + slope * j);
    fit.misfit += d * d;
  }
  std::vector<double> deviations;
  for (int j : reference) deviations.push_back(std::fabs(at(j) - (intercept + slope * j)));
  fit.scatter = std::max(kMinLnRatioScatter, kScatterOverMad * Median(deviations));
  return fit;
}

// Sum over the ratios that member k's onset moves of their squared misfit in ln against the line
// through the others within kReferenceReach; nullopt without 3 such others.
std::optional<RatioFit> Misfit(const std::vector<double>& times, int k) {
  const int n = static_cast<int>(times.size());
  std::vector<int> reference, moved;
  for (int j = std::max(1, k - 1 - kReferenceReach); j <= std::min(n - 2, k + 1 + kReferenceReach);
       ++j) {
    if (j < k - 1 || j > k + 1) reference.push_back(j);
  }
  if (reference.size() < 3) return std::nullopt;
  for (int j = std::max(1, k - 1); j <= std::min(n - 2, k + 1); ++j) moved.push_back(j);
  return FitAgainstLine(LnRatios(times), reference, moved);
}

// The merged sound becomes the member and the onset the merger kept becomes the merged sound, so
// what the recording reports as set aside is what was.
void SwapWithTheMember(MergedEvent& event, double kept_s, const char* why) {
  const double taken_s = event.time_s;
  char text[512];
  std::snprintf(text, sizeof text,
                "the merger's onset for the impact now at %.5f s, %.1f ms %s it: %s", taken_s,
                std::fabs(taken_s - kept_s) * 1e3, kept_s < taken_s ? "before" : "after", why);
  event.time_s = kept_s;
  event.winner_s = taken_s;
  event.reason = text;
  event.rest_of_sound = false;
  event.level_difference_db = -event.level_difference_db;
}

// Two sounds of one bounce (a click and the bounce, or the bounce and its echo) lie the same
// distance apart at every bounce, within this (the detector's onsets of a sound in ringing scatter
// by a few hundred us; a few percent more for a lead that changes with the ball's speed).
constexpr double kPairToleranceS = 0.5e-3;
constexpr double kPairToleranceFraction = 0.15;
// Sounds closer than this may be parts of one impact (a soft contact's first touch and its body a
// millisecond later, lobes of one sound, a rise split in two), which each member's neighbours
// weigh (below), not pairs: a later sound is looked for only past the onset's first millisecond
// (later_attack.h), and a soft ball's contact lasts about that long again (the shared rubber
// ball's copies had "pairs" 1.55 ms apart). Four tolerances, so a pair's two sounds are not
// mistaken for each other either.
constexpr double kMinPairSpacingS = 4 * kPairToleranceS;
// Members timed on one sound of such a pair that show the pair's spacing: fewer could be a
// coincidence of two unrelated sounds.
constexpr int kMinPairedMembers = 3;

// The line through a sequence's ln ratios takes two of them, so four members (two ratios) fit
// any choice exactly. Five leave one ratio to judge by: in silent_wrong_sweep.py --precursors
// seeds 7 and 8, seven five-member drops read closer to the truth (8 #32: -1.5 -> -0.1 sigmas),
// and seed 23 #183 (five members in reverb, their onsets 0.1-3.9 ms off) moved its first to a
// sound 7.5 ms before it, 0.0095 -> 0.0142 off at 0.7 sigmas; six as the least kept the seven
// where they were.
constexpr int kMinMembersToWeighWhole = 5;

double PairTolerance(double spacing_s) {
  return std::max(kPairToleranceS, kPairToleranceFraction * spacing_s);
}

// Another sound a member could be timed on: one merged into it, or the louder later sound in its
// own first milliseconds (Impact::later_onset_s, event null).
struct OtherSound {
  double time_s = 0;
  MergedEvent* event = nullptr;
};

// Sum of squared misfits of the ln ratios `scored` about the Theil-Sen line through all of them,
// and the robust scatter of all about it (as Misfit).
RatioFit WholeSequenceMisfit(const std::vector<double>& times, const std::vector<bool>& scored) {
  const int n = static_cast<int>(times.size());
  for (int k = 1; k < n; ++k) {
    // Two moves that would cross are no choice at all.
    if (!(times[static_cast<std::size_t>(k)] > times[static_cast<std::size_t>(k - 1)])) {
      return {std::numeric_limits<double>::infinity(), kMinLnRatioScatter};
    }
  }
  std::vector<int> all, touched;
  for (int j = 1; j + 1 < n; ++j) {
    all.push_back(j);
    if (scored[static_cast<std::size_t>(j)]) touched.push_back(j);
  }
  return FitAgainstLine(LnRatios(times), all, touched);
}

// Whether member k is the earlier sound of its pair (a click with its bounce as its later sound)
// while most other paired members are the later sound of theirs (bounces with their clicks merged
// into them): a member on the other sound than the sequence, as its pairs show it. Not the
// reverse: a real ball's bounces have a louder sound a few ms after their first touch, which
// makes most members the earlier sound of a "pair" whatever an end member is on (ub-mth337's
// basketball.wav: its first member, with an earlier sound merged, would have stated half of a 9.1
// ms spacing, eta-bar +-0.00033 -> 0.00346, where its 16 kHz copy agrees within 0.0001 at
// +-0.00023).
bool OnAClickWhereMostAreOnTheirBounces(const std::vector<std::pair<int, const OtherSound*>>& pairs,
                                        int k) {
  int on_earlier = 0, on_later = 0;
  for (std::size_t j = 0; j < pairs.size(); ++j) {
    if (static_cast<int>(j) == k) continue;
    if (pairs[j].first > 0) ++on_earlier;
    if (pairs[j].first < 0) ++on_later;
  }
  return pairs[static_cast<std::size_t>(k)].first > 0 && on_later > on_earlier;
}

// Which sound of a member's pair is the quieter: the earlier one for a click before its bounce
// (or a ball's first touch before its louder build-up), the later one for an echo.
bool QuieterSoundIsTheEarlier(double offset_s, const OtherSound& other) {
  const bool other_louder = !other.event || other.event->level_difference_db < 0;
  return offset_s > 0 ? other_louder : !other_louder;
}

// Whether the quieter sound of most recorded pairs is the earlier one: a click before each bounce,
// not an echo after it.
bool MostPairsAreClicks(const std::vector<Impact>& impacts, const std::vector<int>& members,
                        const std::vector<std::pair<int, const OtherSound*>>& pairs) {
  int clicks = 0, echoes = 0;
  for (std::size_t k = 0; k < members.size(); ++k) {
    const OtherSound* other = pairs[k].second;
    if (!other) continue;
    const double offset = other->time_s - impacts[static_cast<std::size_t>(members[k])].onset_s;
    (QuieterSoundIsTheEarlier(offset, *other) ? clicks : echoes) += 1;
  }
  return clicks > echoes;
}

// Once members were moved to one sound of their pairs, a member with no pair recorded may still be
// on the other: a click that rings into its bounce keeps one candidate, and whether the detector
// then times the click or the bounce leaves no trace where the click is within 6 dB of the bounce.
// Inside the sequence such a member's switch moves two ratios and is part of what the choice was
// weighed on; the first or last member's moves one, and a few ms on the first flight is a percent
// of it, under the ratios' scatter (silent_wrong_sweep.py --precursors seed 8 #52: the first
// member on its click, 9 dB under the bounce, the next four moved to their bounces; eta-bar read
// 0.5242 +- 0.0010 against 0.5198). So where the quieter sound of most pairs is the earlier (a
// click before each bounce), a first or last member whose sound is not known, next to one whose
// sound is, states half the spacing (#52: +- 0.0023). Where it is the later (an echo), a member
// without a recorded pair is on its bounce (had the echo won, the bounce would be recorded as
// merged). Every member next to one of another or unknown sound stating it instead widened
// answers that were right 30-46 times (seed 53 #115 eta-bar sigma 0.0002 -> 0.0059, 29 #105
// 0.0002 -> 0.0092: their unknown members are on the same sound as the moved ones); and doing so
// also where no move was taken, the shared recordings' 3-24 times (basketball 0.00033 -> 0.0079),
// since a real ball's louder sound a few ms after its first touch pairs with its members as a
// click would. A switch too small for the ratios to show stays unstated (seed 8 #61, a 2.7 ms
// lead on 0.12 s flights).
void DoubtAnEndMemberOfUnknownSound(std::vector<Impact>& impacts, const std::vector<int>& members,
                                    const std::vector<std::pair<int, const OtherSound*>>& pairs,
                                    const std::vector<bool>& moved, double spacing_s) {
  if (!MostPairsAreClicks(impacts, members, pairs)) return;
  const int n = static_cast<int>(members.size());
  std::vector<int> sound(static_cast<std::size_t>(n), 0);  // +1 earlier, -1 later, 0 unknown
  for (int k = 0; k < n; ++k) {
    const auto& [role, other] = pairs[static_cast<std::size_t>(k)];
    if (other)
      sound[static_cast<std::size_t>(k)] = moved[static_cast<std::size_t>(k)] ? -role : role;
  }
  for (const auto& [end, neighbour] : {std::pair{0, 1}, std::pair{n - 1, n - 2}}) {
    if (sound[static_cast<std::size_t>(end)] != 0 ||
        sound[static_cast<std::size_t>(neighbour)] == 0) {
      continue;
    }
    Impact& member = impacts[static_cast<std::size_t>(members[end])];
    member.onset_uncertainty_s = std::hypot(member.onset_uncertainty_s, 0.5 * spacing_s);
  }
}

// Where the paired members are mostly the later sound of their pair, a quieter click merged
// before it (a bounce timed on itself), the second member among them, and no move is taken, a
// first member with no pair recorded may still sit on its click: a phone's AGC and limiter
// bring the drop's first, loudest bounce down towards its click's level, the click rings into the
// bounce and keeps one candidate, timed on the click, and neither a merged sound nor a later
// sound 6 dB over the click's first millisecond (later_attack.h) records the bounce, while each
// later, quieter bounce stays louder than its click and is timed on itself. Its move shifts one
// ratio by a percent of the first flight, which the ratios cannot judge (as for
// DoubtAnEndMemberOfUnknownSound), so it states half the spacing; not where a sound is merged
// before it at the spacing (its click, at any level: it is on its bounce), nor where the response
// timing timed it (its own evidence). bench/silent_wrong_sweep.py --limiter (stop 73): seed 957 #70
// (a counter drop through a 10-30 dB AGC, clicks 5.2 ms ahead) had its first member on its click at
// a stated 28 us, eta-bar 0.5263 +- 0.0001 against the exact 0.5225 (64 sigmas), now +- 0.0019;
// --precursors seed 957 #101 the same (7.2 ms, 68 sigmas; now +- 0.0031). Without the merged-click
// and response-timing conditions, 33 right answers of the sweep's 10782 earlier files widened, up
// to 69 times (their first, loudest bounce's click was merged 20.5 dB under it, beyond the level
// the pairs weigh); with them 6, by 1.1-1.5 times but one first member 3.9 sigmas off (4.9 times).
// Stop 79: a pair whose member is the earlier sound (a sound at the spacing after a bounce: an
// echo, the ringing's swell) no longer keeps the rule from running; --limiter --precursors seed
// 982 #164 (the first member on its click 4.9 ms early, the 2nd and 4th with their clicks merged,
// the 7th with a sound 5.2 ms after it) read 0.4492 +- 0.0012 against the exact 0.4450 (3.6
// sigmas), now +- 0.0024 (1.8). Its neighbour must be the later sound of its pair itself: where
// it is the earlier, the first member on its click is where its neighbour is (--limiter
// --precursors seed 958 #50, members 0-4 on their clicks with their bounces merged 6.9 ms after
// as echoes: right at +- 0.0002, widened 29 times without it).
void DoubtAFirstMemberOfUnknownSoundAmongBounces(
    std::vector<Impact>& impacts, const std::vector<MergedEvent>& merged,
    const std::vector<int>& members, const std::vector<std::pair<int, const OtherSound*>>& pairs,
    double spacing_s) {
  if (pairs[0].second || !pairs[1].second || pairs[1].first > 0) return;
  Impact& first = impacts[static_cast<std::size_t>(members[0])];
  if (first.timed_from_response || !MostPairsAreClicks(impacts, members, pairs)) return;
  for (const MergedEvent& event : merged) {
    if (event.winner_s == first.onset_s &&
        std::fabs(first.onset_s - event.time_s - spacing_s) <= PairTolerance(spacing_s)) {
      return;
    }
  }
  first.onset_uncertainty_s = std::hypot(first.onset_uncertainty_s, 0.5 * spacing_s);
}

// How much better the ratios fit (in scatters squared, as kRequiredImprovement) with members
// [from, to) of `times` moved by shift_s, judged on the ratios member k's own move touches; 0
// (no evidence) for fewer than four members, whose two ratios a line always fits.
double ImprovementOfAMove(const std::vector<double>& times, int k, int from, int to,
                          double shift_s) {
  const int n = static_cast<int>(times.size());
  if (n < 4) return 0;
  std::vector<bool> touched(static_cast<std::size_t>(n), false);
  for (int j = std::max(1, k - 1); j <= std::min(n - 2, k + 1); ++j) {
    touched[static_cast<std::size_t>(j)] = true;
  }
  std::vector<double> moved = times;
  for (int j = from; j < to; ++j) moved[static_cast<std::size_t>(j)] += shift_s;
  const RatioFit now = WholeSequenceMisfit(times, touched);
  const RatioFit fit = WholeSequenceMisfit(moved, touched);
  return (now.misfit - fit.misfit) / (fit.scatter * fit.scatter);
}

// Whether member k's move alone by shift_s, which fits the ratios `own` scatters squared better
// (ImprovementOfAMove), does so clearly (kRequiredImprovement) and better than moving every member
// after it, or every member before it, the other way: a run on the other sound, whose switch the
// member beside it shows too.
bool MovedAloneClearlyBetter(const std::vector<double>& times, int k, double shift_s, double own) {
  const int n = static_cast<int>(times.size());
  return own > kRequiredImprovement && ImprovementOfAMove(times, k, k + 1, n, -shift_s) < own &&
         ImprovementOfAMove(times, k, 0, k, -shift_s) < own;
}

// A member inside the sequence with no pair recorded can sit on the other sound of the pairs than
// its neighbours as well as an end member can (DoubtAnEndMemberOfUnknownSound): a click that
// sounds at the loud bounces and is lost under the quiet ones leaves a bounce timed on itself
// among members timed on their clicks, and no pair shows it. Its two intervals are then off by
// the spacing in opposite directions, which the ratios see as clearly as a paired member's move:
// where moving it alone by the spacing (either way, on the onsets as chosen) fits them better by
// kRequiredImprovement, and better than moving every member after it, or every member before it,
// the other way (a run on the other sound, whose switch the member beside it shows too), it
// states half the spacing. silent_wrong_sweep.py --precursors seed 931 #186 (22 kHz, clicks 3.0
// ms before each bounce): the first four members aligned on their clicks, three with the bounce as
// their later sound, the fifth on its bounce with nothing recorded (its click under the noise);
// its move fitted 59.8 scatters squared better, and eta-bar read 0.5944 +- 0.0004 against the
// exact 0.6018 (20 sigmas), now +- 0.0039 (1.9). In the sweep's 8516 files (bench/
// sweep_members.py): silent wrong 16 -> 14 (928p #143, 3.3 -> 1.7 sigmas, too), no onset moved,
// 26 eta-bar sigmas wider, by 1.00-1.56 times but those two (by 1.32 and 1.17 times the two within
// 0.001 of the truth); without the runs, right ones widened 2-20 times (926p #86: its 6th
// member on its bounce among clicks, and the 5th's move fitted 34.7 better too; 931p #167: members
// 6-7 on their clicks after five on their bounces, the 5th's move 74.6, the run's 119.9). The
// shared recordings and both suites, in every copy set, unchanged.
void DoubtAMiddleMemberOfUnknownSound(std::vector<Impact>& impacts, const std::vector<int>& members,
                                      const std::vector<std::pair<int, const OtherSound*>>& pairs,
                                      const std::vector<double>& times, double spacing_s) {
  const int n = static_cast<int>(members.size());
  for (int k = 1; k + 1 < n; ++k) {
    if (pairs[static_cast<std::size_t>(k)].second) continue;
    double own = 0;
    double shift = 0;
    for (const double s : {-spacing_s, spacing_s}) {
      if (const double gain = ImprovementOfAMove(times, k, k, k + 1, s); gain > own) {
        own = gain;
        shift = s;
      }
    }
    if (!MovedAloneClearlyBetter(times, k, shift, own)) continue;
    Impact& member = impacts[static_cast<std::size_t>(members[static_cast<std::size_t>(k)])];
    member.onset_uncertainty_s = std::hypot(member.onset_uncertainty_s, 0.5 * spacing_s);
  }
}

// Where the ratios could not tell a choice of sound for the paired members
// (TimeEveryPairOnOneSound), one paired member can still be the only one on its sound among
// neighbours on the other, which nothing recorded: the response timing aligns a limited drop's
// members on whichever sound the detector gave it, and an aligned member is its own evidence to the
// neighbour test.
// --limiter --precursors seed 975 #162 (32 kHz, clicks 5.2 ms ahead): members 0-2 and 4-5 aligned
// on their clicks with nothing recorded of their bounces, the 4th aligned on its bounce with its
// click merged 10.8 dB under, the rest on their bounces with their clicks merged; the pairs'
// choice moved the 4th with the rest, and the ratios could not take it (eta-bar 0.2815 +- 0.0001
// against the exact 0.2741, 144 sigmas). Its move alone onto its other sound fitted 13.5 scatters
// squared better. So, as for a member with no pair (DoubtAMiddleMemberOfUnknownSound), a paired
// middle member whose move alone onto its pair's other sound fits the ratios it touches better by
// kRequiredImprovement, and better than moving every member after it, or every member before it,
// the other way, states at least half the distance (#162: +- 0.0035, 2.1 sigmas). Over the 15200
// earlier sweep files with and without a limiter: one other eta-bar sigma wider, by 1.2 times.
void DoubtAPairedMemberTheRatiosMoveAlone(
    std::vector<Impact>& impacts, const std::vector<int>& members,
    const std::vector<std::pair<int, const OtherSound*>>& pairs, const std::vector<double>& times) {
  const int n = static_cast<int>(members.size());
  for (int k = 1; k + 1 < n; ++k) {
    const OtherSound* other = pairs[static_cast<std::size_t>(k)].second;
    if (!other) continue;
    const double shift = other->time_s - times[static_cast<std::size_t>(k)];
    if (!MovedAloneClearlyBetter(times, k, shift, ImprovementOfAMove(times, k, k, k + 1, shift))) {
      continue;
    }
    Impact& member = impacts[static_cast<std::size_t>(members[static_cast<std::size_t>(k)])];
    member.onset_uncertainty_s = std::max(member.onset_uncertainty_s, 0.5 * std::fabs(shift));
  }
}

// A leading run of `run` members that may all sit on other sounds than their bounces shifts as
// one, so its doubt is the flight after it (Impact::incoming_flight_uncertainty_s), which no ratio
// inside the run feels. Stated on the run's last member's onset, it also widened the flight into
// that member, which eta-bar feels wherever the run ends inside its first_n ratios (a right
// answer's sigma widened up to 53 times). The same switch stated by two rules counts once.
void DoubtTheFlightAfterALeadingRun(std::vector<Impact>& impacts, const std::vector<int>& members,
                                    std::size_t run, double spacing_s) {
  Impact& after = impacts[static_cast<std::size_t>(members[run])];
  after.incoming_flight_uncertainty_s =
      std::max(after.incoming_flight_uncertainty_s, 0.5 * spacing_s);
}

// A phone's limiter brings every loud bounce of a drop down towards its click, so the first few,
// loudest bounces can all be timed on their clicks, and timed alike (the response timing aligns
// them to one another, +-5-20 us), with nothing recorded of their bounces, while from the first
// bounce the limiter spares on, each is timed on itself with its click merged and the pairs put
// the sequence on the later sound. Inside the leading run every interval is right; the one from
// its last member to the first paired one is short by the spacing, and with it the ratio on each
// side. So where every paired member ends on the later sound of its pair with the quieter sound
// before it, and a leading run of two or more members has no pair recorded, the flight after the
// run states half the spacing if moving the whole run by the spacing fits the ratios it touches
// clearly better (kRequiredImprovement). bench/silent_wrong_sweep.py --limiter --precursors
// (stop 73): seed 959 #55 (96 kHz, clicks 7.0 ms ahead; the first four members on their clicks
// at +-5 us), eta-bar 0.3894 +- 0.0001 against the exact 0.4025 (224 sigmas), now +- 0.0070;
// 958 #178 the same (5.5 ms, 147 sigmas). The sweep's 10782 earlier files: no answer changes;
// the 1600 --limiter files: 7 sigmas wider, silent wrong 12 -> 10.
void DoubtTheEndOfALeadingRunOfUnknownSound(
    std::vector<Impact>& impacts, const std::vector<int>& members,
    const std::vector<std::pair<int, const OtherSound*>>& pairs, const std::vector<bool>& moved,
    const std::vector<double>& times, double spacing_s) {
  const int n = static_cast<int>(members.size());
  int on_earlier = 0;
  int run = -1;
  for (int k = 0; k < n; ++k) {
    const auto& [role, other] = pairs[static_cast<std::size_t>(k)];
    if (!other) continue;
    if (run < 0) run = k;
    const int sound = moved[static_cast<std::size_t>(k)] ? -role : role;
    on_earlier += sound > 0 ? 1 : 0;
  }
  if (run < 2 || on_earlier > 0 || !MostPairsAreClicks(impacts, members, pairs)) return;
  if (!(ImprovementOfAMove(times, run - 1, 0, run, spacing_s) > kRequiredImprovement)) return;
  DoubtTheFlightAfterALeadingRun(impacts, members, static_cast<std::size_t>(run), spacing_s);
}

// A sequence whose members are timed some on the earlier, some on the later sound of pairs a
// constant distance apart (a click 10-14 dB under each bounce rings into it and keeps one
// candidate, timed on the click, or the two stay apart and the bounce wins, bounce by bounce with
// their levels; an echo out-levels its bounce at some bounces): every interval across a switch is
// off by the spacing, milliseconds, while each member alone looks right. One member's neighbours
// cannot tell which sound is the bounce where they switch too (silent_wrong_sweep.py
// --precursors seed 7 #24: four members on their clicks, the next two on their bounces 7.9 ms
// later). So the sequence is weighed whole: all its paired members on the earlier sound, or all
// on the later, against the onsets as they stand, by the ratios the moves touch; the choice must
// fit better by kRequiredImprovement scatters squared. Since the intervals between members of one
// choice are the bounces' (a constant lead cancels), a member moved to its other sound is stated
// with the pairs' own scatter about their spacing added. Members timed from their response move
// too: the alignment times a click as well as its bounce, and #24's first four were aligned on
// their clicks (the single-member rule below leaves them, for one member's neighbours are weaker
// evidence than a pattern of three or more pairs). Marks in `weighed` (one flag per impact) the
// members it weighed with the other sound of their pair, whatever it chose. Returns the spacing
// of pairs too few to weigh the sequence whole (one or two members show it), for the single-member
// test in TakeMergedOnsetsThatFitTheSequence; nothing otherwise.
std::optional<double> TimeEveryPairOnOneSound(std::vector<Impact>& impacts,
                                              std::vector<MergedEvent>& merged,
                                              const BounceSequence& sequence,
                                              std::vector<bool>& weighed,
                                              bool weighed_again = false) {
  const auto& members = sequence.impact_indices;
  const int n = static_cast<int>(members.size());
  if (n < kMinMembersToWeighWhole) return std::nullopt;
  const auto impact_at = [&](int k) -> Impact& {
    return impacts[static_cast<std::size_t>(members[static_cast<std::size_t>(k)])];
  };
  std::vector<double> times;
  for (int k = 0; k < n; ++k) times.push_back(impact_at(k).onset_s);
  std::vector<std::vector<OtherSound>> others(static_cast<std::size_t>(n));
  std::vector<double> spacings;
  for (int k = 0; k < n; ++k) {
    const double onset = times[static_cast<std::size_t>(k)];
    const double after = k > 0 ? times[static_cast<std::size_t>(k - 1)] : -1e300;
    const double before = k + 1 < n ? times[static_cast<std::size_t>(k + 1)] : 1e300;
    auto& list = others[static_cast<std::size_t>(k)];
    for (MergedEvent& event : merged) {
      if (event.winner_s != onset || event.time_s == onset) continue;
      if (event.level_difference_db > kMaxQuieterDb) continue;
      if (event.time_s > after && event.time_s < before) list.push_back({event.time_s, &event});
    }
    const double later = impact_at(k).later_onset_s;
    if (std::isfinite(later) && later > onset && later < before) list.push_back({later, nullptr});
    for (const OtherSound& other : list) spacings.push_back(std::fabs(other.time_s - onset));
  }
  // The spacing most members show.
  const auto paired_with = [&](double spacing, int k) {
    // +1: the member is the earlier sound of a pair, -1 the later, 0 neither or both.
    int role = 0;
    const OtherSound* found = nullptr;
    for (const OtherSound& other : others[static_cast<std::size_t>(k)]) {
      const double offset = other.time_s - times[static_cast<std::size_t>(k)];
      if (std::fabs(std::fabs(offset) - spacing) > PairTolerance(spacing)) continue;
      const int this_role = offset > 0 ? 1 : -1;
      if (found && this_role != role) return std::pair<int, const OtherSound*>{0, nullptr};
      if (!found ||
          std::fabs(std::fabs(offset) - spacing) <
              std::fabs(std::fabs(found->time_s - times[static_cast<std::size_t>(k)]) - spacing)) {
        found = &other;
        role = this_role;
      }
    }
    return std::pair<int, const OtherSound*>{role, found};
  };
  double spacing = 0;
  int most = 0;
  for (double candidate : spacings) {
    if (candidate < kMinPairSpacingS) continue;
    int count = 0;
    for (int k = 0; k < n; ++k) count += paired_with(candidate, k).first != 0;
    if (count > most || (count == most && candidate < spacing)) {
      most = count;
      spacing = candidate;
    }
  }
  if (most < kMinPairedMembers) {
    // A member on the quieter sound of its pair (a louder sound merged into it, or its louder
    // later sound) is the evidence of a switch; pairs whose members are all the louder sound are
    // quiet sounds before or after bounces timed on themselves.
    for (int k = 0; k < n; ++k) {
      const OtherSound* other = paired_with(spacing, k).second;
      if (other && (!other->event || other->event->level_difference_db < 0)) return spacing;
    }
    return std::nullopt;
  }
  std::vector<std::pair<int, const OtherSound*>> pairs;
  std::vector<double> matched;
  for (int k = 0; k < n; ++k) {
    pairs.push_back(paired_with(spacing, k));
    if (pairs.back().second) {
      weighed[static_cast<std::size_t>(members[static_cast<std::size_t>(k)])] = true;
      matched.push_back(
          std::fabs(pairs.back().second->time_s - times[static_cast<std::size_t>(k)]));
    }
  }
  // Both choices are scored on the same ratios: every one a move of either touches.
  std::vector<bool> scored(static_cast<std::size_t>(n), false);
  for (int k = 0; k < n; ++k) {
    if (!pairs[static_cast<std::size_t>(k)].second) continue;
    for (int j = std::max(1, k - 1); j <= std::min(n - 2, k + 1); ++j) {
      scored[static_cast<std::size_t>(j)] = true;
    }
  }
  const auto fit_with = [&](const std::vector<bool>& move) {
    std::vector<double> moved = times;
    for (int k = 0; k < n; ++k) {
      if (move[static_cast<std::size_t>(k)]) {
        moved[static_cast<std::size_t>(k)] = pairs[static_cast<std::size_t>(k)].second->time_s;
      }
    }
    return WholeSequenceMisfit(moved, scored);
  };
  // Every member on the other sound of its pair moves; then each move the ratios clearly reject
  // (by kRequiredImprovement, as a move is taken) is undone, until none is left: a member paired
  // by chance with an unrelated sound at the spacing (the ringing's swell after a bounce) stays
  // where it is (--precursors seed 8 #31: its 13th member, on its bounce, had a louder sound 6.6
  // ms later). Undoing every move that does not help made a patchwork of the noise instead: seed
  // 43 #78 (members 1-9 on their clicks, the 10th-13th on their bounces) moved the 2nd-4th and
  // 9th to their bounces and left the 1st and the 5th-8th, and eta-bar went from 0.3439 +- 0.0001
  // to 0.3537 +- 0.0051 against the exact 0.3439.
  struct Choice {
    std::vector<bool> move;
    RatioFit fit;
    // First or last members whose move the ratios could not judge: left where they are.
    std::vector<int> unjudged;
    // Runs of members whose move their ends did not fit better, nor clearly worse (below): left
    // where they are.
    std::vector<int> rode_along;
    // The fit with those runs moved too: which sound the pairs put the members on.
    RatioFit fit_with_runs;
  };
  const auto choose = [&](int role_moved) {
    Choice choice;
    for (int k = 0; k < n; ++k) {
      choice.move.push_back(pairs[static_cast<std::size_t>(k)].first == role_moved);
    }
    choice.fit = fit_with(choice.move);
    for (bool undone = true; undone;) {
      undone = false;
      for (int k = 0; k < n; ++k) {
        if (!choice.move[static_cast<std::size_t>(k)]) continue;
        choice.move[static_cast<std::size_t>(k)] = false;
        const RatioFit fit = fit_with(choice.move);
        if ((choice.fit.misfit - fit.misfit) / (fit.scatter * fit.scatter) > kRequiredImprovement) {
          choice.fit = fit;
          undone = true;
        } else {
          choice.move[static_cast<std::size_t>(k)] = true;
        }
      }
    }
    // A first or last member's move shifts one ratio, a fraction of a percent on a long flight,
    // which the ratios cannot judge either way: it rides along with the others' choice, right or
    // wrong. Where its neighbour has a pair too, the choice puts the two on one sound; where the
    // neighbour's sound is not known, nothing says the member belongs on the chosen one.
    // silent_wrong_sweep.py seed 921 #156 (11 kHz plate, clicks 12 dB under each bounce 5.2 ms
    // before it): the detector kept the first, clipped bounce over its click, the next 8 members
    // were aligned on their bounces with no click recorded, and the late residual-only ones sat on
    // their clicks; the choice of the earlier sound moved the first member to its click (eta-bar
    // 17 sigmas off). Such a member moves only where the ratios clearly prefer it; otherwise it
    // stays and states half the spacing (below).
    for (const auto& [k, neighbour] : {std::pair{0, 1}, std::pair{n - 1, n - 2}}) {
      if (!choice.move[static_cast<std::size_t>(k)] ||
          pairs[static_cast<std::size_t>(neighbour)].second) {
        continue;
      }
      choice.move[static_cast<std::size_t>(k)] = false;
      const RatioFit fit = fit_with(choice.move);
      if ((fit.misfit - choice.fit.misfit) / (choice.fit.scatter * choice.fit.scatter) >
          kRequiredImprovement) {
        choice.move[static_cast<std::size_t>(k)] = true;
      } else {
        choice.fit = fit;
        choice.unjudged.push_back(k);
      }
    }
    choice.fit_with_runs = choice.fit;
    // Members that move together by the spacing keep their intervals: a run of consecutive moved
    // members changes only the ratios at its two ends, and it moves only where those ends fit
    // better moved. Otherwise the run rode along with moves elsewhere and made a switch of its
    // own at an end (silent_wrong_sweep.py --precursors seed 8 #147: members 0-7 on
    // their bounces, 8 and 10 too with their clicks merged, 9 heard only in the ringing and on its
    // click; the choice of the earlier sound fitted 8-10 and moved 0-3 with them, eta-bar 8
    // sigmas off).
    for (int begin = 0; begin < n;) {
      if (!choice.move[static_cast<std::size_t>(begin)]) {
        ++begin;
        continue;
      }
      int end = begin;
      while (end < n && choice.move[static_cast<std::size_t>(end)]) ++end;
      std::vector<bool> without = choice.move;
      for (int k = begin; k < end; ++k) without[static_cast<std::size_t>(k)] = false;
      const RatioFit fit = fit_with(without);
      if (fit.misfit <= choice.fit.misfit) {
        // Where the ratios cannot tell the run's two places apart either, it is on one sound or
        // the other, as far as they know.
        if ((choice.fit.misfit - fit.misfit) / (fit.scatter * fit.scatter) <=
            kRequiredImprovement) {
          for (int k = begin; k < end; ++k) choice.rode_along.push_back(k);
        }
        choice.move = std::move(without);
        choice.fit = fit;
      }
      begin = end;
    }
    return choice;
  };
  const RatioFit now = WholeSequenceMisfit(times, scored);
  // All on the earlier sound: the members now on the later one move.
  const Choice earlier = choose(-1);
  const Choice later = choose(1);
  const int role_moved = earlier.fit_with_runs.misfit <= later.fit_with_runs.misfit ? -1 : 1;
  const Choice& best = role_moved < 0 ? earlier : later;
  const Choice& other = role_moved < 0 ? later : earlier;
  const double median_spacing = Median(matched);
  if ((now.misfit - best.fit.misfit) / (best.fit.scatter * best.fit.scatter) <=
      kRequiredImprovement) {
    // The ratios cannot tell, but where some members are on the earlier sound of their pair and
    // some on the later, each interval across a switch is off by the spacing, so the members that
    // would move state half of it (--precursors seed 9 #159: clicks 5.9 ms and 13 dB before every
    // bounce of a ball with no scatter, three members on their clicks and the rest on their
    // bounces, flights of 0.3-0.5 s that the 1 % scatter floor cannot tell 5.6 ms apart on;
    // eta-bar 26 sigmas off, now 2.6). All on one sound, no interval spans a switch: stated so,
    // seed 8's #12, #33, #89 and #95 widened their eta-bar's sigma 10-70 times for nothing.
    bool on_earlier = false, on_later = false;
    for (const auto& [role, other] : pairs) {
      on_earlier = on_earlier || role > 0;
      on_later = on_later || role < 0;
    }
    // Weighed again after a member moved by its neighbours (below), the sequence has a switch the
    // pairs need not show: that member's.
    if ((on_earlier && on_later) || weighed_again) {
      for (int k = 0; k < n; ++k) {
        // An end member left where it is as unjudged, or a run that rode along, would have moved
        // too: the ratios that cannot tell cannot tell for them either (--precursors seed 923 #99:
        // members 0-3 on their clicks, the later ones on their bounces, only 0-1 with a pair).
        const auto listed = [k](const std::vector<int>& members) {
          return std::find(members.begin(), members.end(), k) != members.end();
        };
        // Nor can they for the members the other choice would move, or leave unjudged at an end:
        // where neither is taken, which one fits a little better says little. The random mix's
        // seed 947 #99 (22 kHz counter, 3.7 % scatter of the ratios): the 2nd-4th members on their
        // clicks, the 8th on its bounce with its click merged; the better choice moved the 8th,
        // and the 2nd-4th stated nothing (eta-bar 3.1 sigmas off). --precursors seed 948 #158: a
        // first member on its click, the 3rd and 7th on their bounces with their clicks merged,
        // whose moves the ratios clearly rejected; the tie fell to the choice that does not move
        // the first (eta-bar 0.2976 +- 0.0001 against the exact 0.2927). Not the runs the other
        // choice's ends did not fit better (rode_along): stating those too widened 204 right
        // answers of the sweep, 23 of them 10-92 times, for one more mended.
        const bool would_move =
            best.move[static_cast<std::size_t>(k)] || listed(best.unjudged) ||
            listed(best.rode_along) ||
            (listed(other.unjudged) && OnAClickWhereMostAreOnTheirBounces(pairs, k)) ||
            other.move[static_cast<std::size_t>(k)];
        if (!would_move) continue;
        Impact& member = impact_at(k);
        member.onset_uncertainty_s = std::hypot(member.onset_uncertainty_s, 0.5 * median_spacing);
      }
    }
    if (on_later && !weighed_again) {
      DoubtAFirstMemberOfUnknownSoundAmongBounces(impacts, merged, members, pairs, median_spacing);
    }
    DoubtAMiddleMemberOfUnknownSound(impacts, members, pairs, times, median_spacing);
    DoubtAPairedMemberTheRatiosMoveAlone(impacts, members, pairs, times);
    DoubtTheEndOfALeadingRunOfUnknownSound(
        impacts, members, pairs, std::vector<bool>(members.size(), false), times, median_spacing);
    return std::nullopt;
  }
  {
    std::vector<double> chosen = times;
    for (int k = 0; k < n; ++k) {
      if (best.move[static_cast<std::size_t>(k)]) {
        chosen[static_cast<std::size_t>(k)] = pairs[static_cast<std::size_t>(k)].second->time_s;
      }
    }
    DoubtAMiddleMemberOfUnknownSound(impacts, members, pairs, chosen, median_spacing);
    DoubtTheEndOfALeadingRunOfUnknownSound(impacts, members, pairs, best.move, chosen,
                                           median_spacing);
  }
  DoubtAnEndMemberOfUnknownSound(impacts, members, pairs, best.move, median_spacing);
  for (const int k : best.unjudged) {
    Impact& member = impact_at(k);
    member.onset_uncertainty_s = std::hypot(member.onset_uncertainty_s, 0.5 * median_spacing);
  }
  // The pairs' scatter about their spacing: how far either sound's onset wanders.
  double square_sum = 0;
  for (double m : matched) square_sum += (m - median_spacing) * (m - median_spacing);
  const double spread_s = std::sqrt(square_sum / static_cast<double>(matched.size()));
  std::vector<MergedEvent> set_aside;
  for (int k = 0; k < n; ++k) {
    if (!best.move[static_cast<std::size_t>(k)]) continue;
    const OtherSound* other = pairs[static_cast<std::size_t>(k)].second;
    Impact& member = impact_at(k);
    const double kept_s = member.onset_s;
    const double taken_s = other->time_s;
    char why[200];
    std::snprintf(why, sizeof why,
                  "the sequence's other members are timed on the %s of two sounds %.1f ms apart "
                  "(merged)",
                  role_moved < 0 ? "earlier" : "later", median_spacing * 1e3);
    if (other->event) {
      SwapWithTheMember(*other->event, kept_s, why);
    } else {
      MergedEvent event;
      event.time_s = kept_s;
      event.winner_s = taken_s;
      event.peak_dbfs = member.peak_dbfs;
      char text[512];
      std::snprintf(text, sizeof text,
                    "the detector's onset for the impact now at %.5f s, %.1f ms before it: a "
                    "quieter sound that rang into it; %s",
                    taken_s, (taken_s - kept_s) * 1e3, why);
      event.reason = text;
      set_aside.push_back(std::move(event));
    }
    member.onset_s = taken_s;
    member.onset_uncertainty_s = std::hypot(member.onset_uncertainty_s, spread_s);
    member.timed_from_response = false;
    member.later_onset_s = std::numeric_limits<double>::quiet_NaN();
    member.later_sound_over_onset_db = std::numeric_limits<double>::quiet_NaN();
    member.later_rise_s = std::numeric_limits<double>::quiet_NaN();
    member.later_rise_db = std::numeric_limits<double>::quiet_NaN();
    // The span before the onset it left is no longer this onset's.
    member.unsearched_span_s = 0;
  }
  for (MergedEvent& event : set_aside) merged.push_back(std::move(event));
  return std::nullopt;
}

// The first member's interval ratio has none before it, and a few ms on the first flight is a
// percent of it, under the ratios' scatter: neither the member rule below (which needs a ratio
// on each side) nor the ratios can tell which of its sounds the first bounce is. A click 12 dB
// under the drop's first, loudest bounce and 2-5 ms ahead of it rings into it and keeps one
// candidate, timed on the click, while each later bounce's click lies in the previous bounce's
// ringing and the bounce is timed on itself (silent_wrong_sweep.py --precursors seed 920 #1: the
// first member 2.1 ms early at a stated 32 us, eta-bar 12.8 sigmas off; seed 9 #50, 3.0 ms, 4.3
// sigmas). Where the first member has a louder later sound of its own (Impact::later_onset_s) at
// a spacing that most of the other members do not show, it is timed on another sound than they
// are and states half the spacing. A ball whose every bounce builds up to a later peak (a soft
// ball's first touch) shows it at most members and is left alone; so is a member the response
// timing timed (its own evidence) or the whole sequence weighed.
// The later sound must stand the rise threshold over the member's first millisecond: a 1 ms
// contact's loudest first bounce peaks a few ms in with its first millisecond 2-8 dB under, and
// at the 6 dB the later sound is offered at, 8 right answers of 2507 sweep files widened 3.4-87
// times (docs/codecs.md).
constexpr double kFirstMemberQuieterDb = 10.0;
void DoubtAFirstMemberOnAQuieterSound(std::vector<Impact>& impacts, const BounceSequence& sequence,
                                      const std::vector<bool>& weighed) {
  const auto& members = sequence.impact_indices;
  if (members.size() < 3) return;
  Impact& first = impacts[static_cast<std::size_t>(members.front())];
  if (first.timed_from_response || weighed[static_cast<std::size_t>(members.front())]) return;
  const double spacing_s = first.later_onset_s - first.onset_s;
  const double second_s = impacts[static_cast<std::size_t>(members[1])].onset_s;
  if (!(spacing_s >= kMinPairSpacingS) || !(first.later_onset_s < second_s) ||
      !(first.later_sound_over_onset_db >= kFirstMemberQuieterDb)) {
    return;
  }
  int showing = 0;
  for (std::size_t k = 1; k < members.size(); ++k) {
    const Impact& member = impacts[static_cast<std::size_t>(members[k])];
    const double spacing = member.later_onset_s - member.onset_s;
    if (std::isfinite(spacing) && std::fabs(spacing - spacing_s) <= PairTolerance(spacing_s)) {
      ++showing;
    }
  }
  if (2 * showing >= static_cast<int>(members.size()) - 1) return;
  first.onset_uncertainty_s = std::hypot(first.onset_uncertainty_s, 0.5 * spacing_s);
}

// The same where the first member won the merge over a later sound at least as loud as itself
// over the same span (MergedEvent::level_difference_db <= 0), before the second member: the
// later one rose by less than the threshold in the first one's ringing and lost to it, and the
// ratios cannot tell which is the bounce. The later sound may be the bounce after a click that a
// limiter levelled with it, or a reflection louder than the bounce (the detector suite's
// reverb_strong, 11.4 ms and 3.1 dB over it: the first member is right, and its eta-bar's sigma
// goes from 0.0116 to 0.0132). Not where most other members show a sound at that spacing after
// them, merged or their own later sound (the ball's own pattern, timed alike at every member), nor
// for a member timed from its response or weighed whole. bench/sweep_members.py over the sweep's
// 10782 earlier files: silent wrong 23 -> 22 (--precursors seed 925 #79: the first member on its
// click, its bounce merged 7.3 ms later as an echo that rose under the threshold), 27 eta-bar
// sigmas wider by 1.1-1.8 times; where the later sound may be up to 6 dB quieter (an echo), 56
// wider, up to 44 times.
void DoubtAFirstMemberBeforeALouderMergedSound(std::vector<Impact>& impacts,
                                               const std::vector<MergedEvent>& merged,
                                               const BounceSequence& sequence,
                                               const std::vector<bool>& weighed) {
  const auto& members = sequence.impact_indices;
  if (members.size() < 3) return;
  Impact& first = impacts[static_cast<std::size_t>(members.front())];
  if (first.timed_from_response || weighed[static_cast<std::size_t>(members.front())]) return;
  const double second_s = impacts[static_cast<std::size_t>(members[1])].onset_s;
  double spacing_s = 0;
  for (const MergedEvent& event : merged) {
    if (event.winner_s == first.onset_s && event.time_s > first.onset_s &&
        event.time_s < second_s && event.level_difference_db <= 0) {
      spacing_s = std::max(spacing_s, event.time_s - first.onset_s);
    }
  }
  if (!(spacing_s >= kMinPairSpacingS)) return;
  int showing = 0;
  for (std::size_t k = 1; k < members.size(); ++k) {
    const Impact& member = impacts[static_cast<std::size_t>(members[k])];
    const auto at_spacing = [&](double later_s) {
      return std::fabs(later_s - member.onset_s - spacing_s) <= PairTolerance(spacing_s);
    };
    bool shows = std::isfinite(member.later_onset_s) && at_spacing(member.later_onset_s);
    for (const MergedEvent& event : merged) {
      shows = shows || (event.winner_s == member.onset_s && at_spacing(event.time_s));
    }
    showing += shows ? 1 : 0;
  }
  if (2 * showing >= static_cast<int>(members.size()) - 1) return;
  first.onset_uncertainty_s = std::hypot(first.onset_uncertainty_s, 0.5 * spacing_s);
}

// A bounce's fresh attack out of its click's ringing (Impact::later_rise_db): why 6 dB, below.
constexpr double kFreshAttackDb = 6.0;

// A bounce's attack where the limiter held it and its click at one ceiling rises only 4-6 dB out
// of the click's ringing (--limiter --precursors seed 962 #34: 4.4-6.3 dB after the four members
// of a leading run on their clicks). So weak a rise counts only at the spacing of the sounds
// merged before other members, and only where such rises mark a leading run, for a beat or an
// echo rises as often after every bounce (DoubtAMemberBeforeAFreshAttackAtTheSpacing).
constexpr double kWeakAttackDb = 4.0;

// The spacing at which most members' fresh attacks (kFreshAttackDb) lie, where two or more lie
// within a pair's tolerance of one another: the median of the largest such group; nullopt where
// no two agree. A bounce's attack out of its click's ringing lies at the click's lead at every
// member on its click, while a plate's beating or a stray sound lands anywhere in a flight.
std::optional<double> SpacingOfTheFreshAttacks(const std::vector<Impact>& impacts,
                                               const std::vector<int>& members) {
  std::vector<double> attacks;
  for (const int index : members) {
    const Impact& member = impacts[static_cast<std::size_t>(index)];
    const double offset_s = member.later_rise_s - member.onset_s;
    if (member.later_rise_db >= kFreshAttackDb && offset_s >= kMinPairSpacingS) {
      attacks.push_back(offset_s);
    }
  }
  std::vector<double> best;
  for (const double centre : attacks) {
    std::vector<double> group;
    for (const double offset_s : attacks) {
      if (std::fabs(offset_s - centre) <= PairTolerance(centre)) group.push_back(offset_s);
    }
    if (group.size() > best.size()) best = std::move(group);
  }
  if (best.size() < 2) return std::nullopt;
  return Median(best);
}

// A member timed on its click, next to members timed on their bounces, whose pairs neither the
// merger nor the later-sound test recorded: a phone's look-ahead limiter holds a drop's loud
// click and bounce at one ceiling, so the bounce rises less than a threshold over the click's
// ringing and is not 6 dB over its first millisecond, and no rule that weighs levels or pairs
// sees it (with fewer than kMinPairedMembers pairs recorded, the whole sequence is not weighed).
// The bounce still begins with a fresh attack out of the click's ringing (Impact::later_rise_s),
// and where that attack lies at the spacing of the sounds merged before the other members, the
// member is on the earlier sound of the same pair: its two intervals are off by the spacing, and
// the ratios, the first member's especially, may not show it. So where most of the sounds merged
// before members (not more than kMaxQuieterDb under them) lie at one spacing, at two members or
// more, a member without one whose sharpest later rise lies at that spacing and rose by
// kFreshAttackDb, next to a member with one and no such rise (on its bounce), states at least
// half the spacing; not a later member the response timing timed (its own evidence, and the
// ratios on both sides of it see a switch there). The first member is doubted all the same: no
// ratio before it shows its switch, and the alignment searches only 5 ms about the detector's
// onset (ResponseTimingOptions::search_s), so a click with its bounce further on is aligned on
// itself (--limiter --precursors seed 964 #173: the first member aligned on its click 7.6 ms
// before its bounce, at +-40 us, eta-bar 124 sigmas off; now 2.0). Lifting the exception for
// every member also widened 7 right answers of seeds 940-955 without a limiter, up to 172 times
// (members on their bounces with a 6-7 dB rise at the spacing after them).
// bench/silent_wrong_sweep.py --limiter seeds 956-959 (1600 files, 860 eta-bars; stop 74):
// silent wrong 10 -> 6 (956p #30: the first member on its click 5.3 ms before its bounce, both at
// the ceiling, two members with their clicks merged; eta-bar 88 -> 2.1 sigmas off; 956p #84 26 ->
// 1.9, 958 #26 10.7 -> 2.0, 958p #137 5.2 -> 2.9), 15 eta-bar sigmas wider (the other 11 by 1.1-4.5
// times, 10 within one sigma before: members on their clicks beside ones on their bounces, whose
// errors cancelled in eta-bar). Fresh --limiter seeds 960-962 (1200 files, 678 eta-bars, 8 silent
// wrong: leading runs on their clicks that the response timing aligned, which it leaves): none
// mended, 9 sigmas wider, two by 20 and 43 times (members on their clicks beside ones on their
// bounces, eta-bar right by cancellation), 7 by 1.1-1.9 times. Seeds 940-955 without a limiter
// (3857 eta-bars): no answer changed, 12 sigmas wider by 1.1-1.8 times, all stated +-0.004 or
// wider before. Without the level and majority conditions, copies of the shared recordings
// widened up to 200 times (ub-mth337's steel_surface as 48 kHz float: noise sounds 26-35 dB under
// four members, 5.3-10 ms before them); stating half the spacing in quadrature on members other
// rules had doubted widened 15 more answers. 6 dB: two modes of a plate beating at full depth raise
// the energy by 5 dB (the peak of each 0.25 ms, which they swing by 5-10 dB, marked 61 right
// intervals at 4 dB).
void DoubtAMemberBeforeAFreshAttackAtTheSpacing(std::vector<Impact>& impacts,
                                                const std::vector<MergedEvent>& merged,
                                                const BounceSequence& sequence) {
  const auto& members = sequence.impact_indices;
  const auto member_at = [&](std::size_t k) -> Impact& {
    return impacts[static_cast<std::size_t>(members[k])];
  };
  std::vector<std::vector<double>> before(members.size());
  std::vector<double> spacings;
  for (const MergedEvent& event : merged) {
    for (std::size_t k = 0; k < members.size(); ++k) {
      const double onset_s = member_at(k).onset_s;
      if (event.winner_s == onset_s && event.time_s < onset_s &&
          event.level_difference_db <= kMaxQuieterDb) {
        before[k].push_back(onset_s - event.time_s);
        spacings.push_back(onset_s - event.time_s);
      }
    }
  }
  // With fewer than two merged sounds the attacks themselves can state the spacing, two or more
  // agreeing (SpacingOfTheFreshAttacks): --limiter --precursors seed 973 #38 had one click merged,
  // before its 3rd member, on its bounce, and attacks of 11-12 dB at that spacing after the 1st,
  // 2nd and 4th, on their clicks 4.4 ms early (eta-bar 6.7 sigmas off, now 1.5); and with nothing
  // merged at all, the leading run below (972p #60, 15 -> 1.9 sigmas; 958p #98).
  const bool from_attacks = spacings.size() < 2;
  const std::optional<double> spacing = from_attacks ? SpacingOfTheFreshAttacks(impacts, members)
                                                     : std::optional<double>(Median(spacings));
  if (!spacing) return;
  const double spacing_s = *spacing;
  const double tolerance_s = PairTolerance(spacing_s);
  std::vector<bool> shows(members.size(), false);
  for (std::size_t k = 0; k < members.size(); ++k) {
    shows[k] = std::any_of(before[k].begin(), before[k].end(),
                           [&](double s) { return std::fabs(s - spacing_s) <= tolerance_s; });
  }
  const auto showing = std::count(shows.begin(), shows.end(), true);
  const auto with_one = std::count_if(before.begin(), before.end(),
                                      [](const std::vector<double>& b) { return !b.empty(); });
  // Most sounds merged before members must lie at the spacing. Where fewer than two were merged,
  // the attacks state it, and one stray sound at another distance says nothing against them (fresh
  // --limiter --precursors seed 980 #140: a sound merged 6.6 ms before its 7th member, 7.6 dB
  // under it, where its leading run's attacks of 10-13 dB lay 4.7-5.1 ms after members 0-3 on
  // their clicks, kept the run below from running: eta-bar 0.2215 +- 0.0003 against the exact
  // 0.2274, 23 sigmas; now +- 0.0032).
  if (!from_attacks && (showing < 2 || 2 * showing <= with_one)) return;
  const auto attacked_at_the_spacing = [&](std::size_t k, double min_rise_db) {
    const Impact& member = member_at(k);
    return member.later_rise_db >= min_rise_db &&
           std::fabs(member.later_rise_s - member.onset_s - spacing_s) <= tolerance_s;
  };
  std::vector<bool> attack_after(members.size(), false);
  std::vector<bool> weak_attack_after(members.size(), false);
  for (std::size_t k = 0; k < members.size(); ++k) {
    attack_after[k] = attacked_at_the_spacing(k, kFreshAttackDb);
    weak_attack_after[k] = attacked_at_the_spacing(k, kWeakAttackDb);
  }
  // On its bounce: a sound merged before it at the spacing, and no attack at the spacing after it
  // (a member on its click can have another sound before it too: in the --precursors sweep's
  // seed 961 #37, one 9.2 ms before a click, where the pairs lie 8.1 ms apart).
  const auto on_bounce = [&](std::size_t k) { return shows[k] && !attack_after[k]; };
  // An attack at the spacing after half the members that show a sound before it, or more, is a
  // trait of the drop's bounces (a reflection, a ball's second touch), not of clicks: --limiter
  // seed 964 #54, a counter drop with a rise 9.2 ms after most bounces, 5-8 dB, whose merged
  // sounds lay 7.3-10.1 ms before four members (with every member the response timing timed
  // doubted, its second, on its bounce, widened eta-bar +-0.0005 -> 0.0084, right either way);
  // seed 950p #90 without a limiter, a member on its bounce, +-0.0059 -> 0.0050, right.
  std::ptrdiff_t bounces_attacked = 0;
  for (std::size_t k = 0; k < members.size(); ++k) bounces_attacked += shows[k] && attack_after[k];
  const bool attacks_mark_clicks = 2 * bounces_attacked < showing;
  std::vector<double> times;
  for (std::size_t k = 0; k < members.size(); ++k) times.push_back(member_at(k).onset_s);
  for (std::size_t k = 0; k < members.size(); ++k) {
    Impact& member = member_at(k);
    if ((member.timed_from_response && k > 0) || !attacks_mark_clicks || shows[k] ||
        !attack_after[k]) {
      continue;
    }
    if (!(k > 0 && on_bounce(k - 1)) && !(k + 1 < members.size() && on_bounce(k + 1))) continue;
    // A spacing the attacks alone state may be a reflection's after every bounce that one stray
    // sound merged before a member happens to match (--limiter seed 968 #65: rises 10.1-11.7 ms
    // after three members on their bounces, a sound 10.0 ms before a residual-only one, 15 dB
    // under it; their eta-bar's sigma widened 4.4 times), so there the ratios must lean towards
    // the member's move onto its attack at all.
    const int at = static_cast<int>(k);
    if (from_attacks && !(ImprovementOfAMove(times, at, at, at + 1, spacing_s) > 0)) continue;
    // At least half the spacing: a member another rule already doubted by as much (the same
    // switch, seen by the ratios or the pairs) is not doubted twice.
    member.onset_uncertainty_s = std::max(member.onset_uncertainty_s, 0.5 * spacing_s);
  }
  // The same switch after a leading run: the limiter can leave the first few, loudest bounces all
  // on their clicks with nothing recorded of either sound's pair, the response timing aligning
  // them to one another, and the member after the run on its bounce with its click merged; with
  // two pairs the whole sequence is not weighed, so DoubtTheEndOfALeadingRunOfUnknownSound does
  // not run. Where moving the run by the spacing fits the ratios it touches clearly better, the
  // flight after it states half the spacing. --limiter --precursors seeds 960 #178 and 962 #152
  // (members 0-3 on their clicks, aligned at +-11-73 us): eta-bar 100 and 60 sigmas off, now 1.8
  // and 1.9. Stated on the run's last member (until 2026-12-07), the doubt widened right answers
  // too: over the 1600 + 1200 limited files 4 (three by 30-144 times), each a run's last member
  // on its click beside the first on its bounce (eta-bar right by cancellation); in seeds 940-955
  // 943 #87 by 20 times (the 6th and 7th members 3.9 ms after their bounces).
  // Where the run ends is found below; a stray sound at another distance is not a pair and ends
  // nothing. Where the ratios lean towards the move but not by
  // kRequiredImprovement, most of the run's members with a fresh attack at the spacing after
  // them say the same (--limiter --precursors seed 963 #145: members 0-3 on their clicks 5.4 ms
  // early, the 3rd with a sound 11.5 ms before it, the move 4.7 scatters squared better, eta-bar
  // 3.4 sigmas off, now 1.6; 966 #19, 9.8 better, 16.5 -> 1.9).
  std::size_t run = 0;
  // With no sound merged at the spacing anywhere, the run ends after an attacked member, at least
  // half of it attacked: the end up to the last attacked member where the ratios prefer its move
  // at all (972p #60: members 0-3 on their clicks 2.4 ms early, the 3rd and 4th with attacks of
  // 8-9 dB; the 1.4 % switch on a 0.169 s flight stays under the ratios' 1 % floor squared twelve
  // times). Over the 7200 limited files of seeds 956-973 and 8000 without a limiter, 145 of 156 and
  // 102 of 109 member sigmas that these attack rules and the one below widened belong to members
  // beside an interval off by more than 1 ms. An earlier end, passing over attacked members after
  // it, where the ratios prefer its move clearly (kRequiredImprovement), and the most of the ends
  // tried: a member on its bounce can have a rise at the spacing too (an echo or a beat), and the
  // 7th member of --limiter --precursors seed 979 #42 had one of 8.3 dB, which stretched the run of
  // members 0-3 on their clicks (5.0 ms early, attacked 7-9 dB) over the sequence, and nothing was
  // stated (eta-bar 0.4802 +- 0.0001 against 0.4916, 82 sigmas; the move of members 0-3 20.5
  // scatters squared better; now +- 0.0064). Any preference for an earlier end doubted ub-mth337's
  // rubber ball (rises 4.0-4.5 ms after its first three bounces, 7-14 dB, and after every later
  // one at other spacings; 0.45 better). Ending the run at two members without an attack instead
  // cut 979p #89's run of five on their clicks after its 2nd member (its 3rd and 4th rose by 5.5
  // and 4.3 dB only). And the attacks must mark the run, as they mark clicks above: after its end
  // members are attacked at the spacing at most half as often as in it, for a reflection or a beat
  // follows every bounce alike (alessia rimbalzi's Palla with noise 50 dB under it: rises of 7-13
  // dB 9.6-10.6 ms after its 2nd, 4th and 5th of 6 bounces, and its 4th stated 5 ms).
  const bool unpaired_run = showing == 0;
  std::size_t last_attacked_end = 0;  // the run up to the last attacked member
  for (std::size_t k = 0; k < members.size(); ++k) {
    if (attack_after[k]) last_attacked_end = k + 1;
  }
  if (unpaired_run) {
    double best = -std::numeric_limits<double>::infinity();
    const auto all_attacked = std::count(attack_after.begin(), attack_after.end(), true);
    const auto n = static_cast<std::ptrdiff_t>(members.size());
    std::ptrdiff_t attacked = 0;
    for (std::size_t end = 1; end + 2 <= members.size(); ++end) {
      attacked += attack_after[end - 1] ? 1 : 0;
      const auto in_run = static_cast<std::ptrdiff_t>(end);
      const bool marks_the_run = 2 * (all_attacked - attacked) * in_run < attacked * (n - in_run);
      if (end < 2 || !attack_after[end - 1] || 2 * attacked < in_run || !marks_the_run) continue;
      const int last = static_cast<int>(end) - 1;
      const double improvement =
          ImprovementOfAMove(times, last, 0, static_cast<int>(end), spacing_s);
      if (improvement > best) {
        best = improvement;
        run = end;
      }
    }
  }
  // With sounds merged at the spacing, the run ends at the first member on its bounce (a sound
  // merged before it at the spacing, no attack after it) or before it, after a member attacked at
  // the spacing or wherever the ratios prefer the move by kRequiredImprovement: of these ends, the
  // one the ratios prefer most. The members between may be unknown (nothing merged, no attack) or
  // show both sounds. It ended at the first member with a sound merged at the spacing, and missed
  // --limiter --precursors seed 959 #146 (members 0-3 on their clicks 5.7 ms early, attacked 6-7
  // dB, the 5th on its bounce with nothing merged, the 6th-9th with their clicks merged: the run
  // taken to the 6th could not fit the ratios; eta-bar 0.2524 +- 0.0003 against 0.2656, 43 sigmas,
  // now +- 0.0071) and fresh seed 981 #86 (the 4th member on its click with a sound 15 dB under it
  // 4.7 ms before, at the spacing as the tolerance goes, ended the run at itself; 18 sigmas, now
  // 1.8).
  bool bounce_after_the_run = false;
  if (!unpaired_run) {
    std::size_t first_on_bounce = 0;
    while (first_on_bounce < members.size() && !on_bounce(first_on_bounce)) ++first_on_bounce;
    double best = -std::numeric_limits<double>::infinity();
    for (std::size_t end = 2;
         first_on_bounce < members.size() && end <= first_on_bounce && end + 2 <= members.size();
         ++end) {
      const int last = static_cast<int>(end) - 1;
      const double improvement =
          ImprovementOfAMove(times, last, 0, static_cast<int>(end), spacing_s);
      // An end the ratios prefer clearly needs no attack at it: --limiter --precursors seed
      // 970 #6, members 0-3 on their clicks 7.2 ms early, rises of 4.7-4.8 dB 7.4 ms after the
      // 1st and 2nd, the 4th's 8.5 ms after it (just outside the pairs' tolerance), the 5th on
      // its bounce with nothing merged, the 6th-8th with their clicks merged 7.4 ms before
      // them; the run's move to the 4th fitted 41.8 scatters squared better, the run to the 2nd
      // 0 (eta-bar 0.4240 +- 0.0006 against 0.4420, 28 sigmas; now +- 0.0101). Over the 13200
      // sweep files and the 1200 fresh ones, nothing else changed.
      if (end != first_on_bounce && !weak_attack_after[end - 1] &&
          !(improvement > kRequiredImprovement)) {
        continue;
      }
      if (improvement > best) {
        best = improvement;
        run = end;
        bounce_after_the_run = true;
      }
    }
  }
  // A run of two leaves four members and two ratios at least (the fewest a line through them
  // needs), where ImprovementOfAMove needs it.
  if (run >= 2 && run + 2 <= members.size() && (unpaired_run || bounce_after_the_run)) {
    const int last = static_cast<int>(run) - 1;
    const double improvement = ImprovementOfAMove(times, last, 0, static_cast<int>(run), spacing_s);
    const auto in_run = static_cast<std::ptrdiff_t>(run);
    const auto run_end = attack_after.begin() + in_run;
    const auto strongly_attacked = std::count(attack_after.begin(), run_end, true);
    // Beside sounds merged at the spacing, weak attacks count where they mark the run (after it,
    // at most half as often as in it): seed 962 #34, members 0-3 on their clicks 7.9 ms early with
    // rises of 4.4-6.3 dB at the spacing, one of them 6 dB; the move fitted 11.3 scatters squared
    // better, eta-bar 0.2589 +- 0.0006 against 0.2707 (21 sigmas; now +- 0.0062).
    const auto weak_end = weak_attack_after.begin() + in_run;
    const auto weakly_attacked = std::count(weak_attack_after.begin(), weak_end, true);
    const auto weakly_attacked_after = std::count(weak_end, weak_attack_after.end(), true);
    const auto after_run = static_cast<std::ptrdiff_t>(members.size()) - in_run;
    const bool weak_attacks_mark_the_run =
        2 * weakly_attacked_after * in_run <= weakly_attacked * after_run;
    const auto attacked =
        !unpaired_run && weak_attacks_mark_the_run ? weakly_attacked : strongly_attacked;
    const bool most_attacked = 2 * attacked > in_run;
    if (unpaired_run ? 2 * attacked >= in_run && (improvement > kRequiredImprovement ||
                                                  (run == last_attacked_end && improvement > 0))
                     : improvement > kRequiredImprovement ||
                           (attacks_mark_clicks && most_attacked && improvement > 0)) {
      // Over the 13200 sweep files the flight (DoubtTheFlightAfterALeadingRun) rather than the
      // run's last member gives 73 eta-bar sigmas back by more than 10 % (to as little as a 50th,
      // where the run ends past eta-bar's flights) and widens 26, 24 of them more than one sigma
      // off before; the same 22 silent wrong, none new, every mended answer as before. A last
      // member another rule doubted by as much already covers the switch.
      if (member_at(run - 1).onset_uncertainty_s < 0.5 * spacing_s) {
        DoubtTheFlightAfterALeadingRun(impacts, members, run, spacing_s);
      }
    }
  }
}

// The mirror of DoubtTheEndOfALeadingRunOfUnknownSound among one or two pairs: a limiter can
// leave the first few, loudest bounces on their clicks, the later bounce of some of them merged
// after them (louder, so the member is on the quieter sound) or recorded only as a fresh attack
// at the same spacing, and the first member it spares on its bounce with nothing recorded. Every
// interval inside the run is right; the one from its last member on is long by the spacing. So
// where the leading members up to the last one with a louder sound at the spacing after it each
// have such a sound or a fresh attack there (kFreshAttackDb), two members or more, and moving
// them all later by the spacing fits the ratios it touches clearly better (kRequiredImprovement),
// the run's last member states half the spacing. --limiter --precursors seed 973 #95 (32 kHz,
// clicks 5.9 ms before their bounces): members 0-3 on their clicks, aligned alike, the bounces of
// the 3rd and 4th merged after them 5-6 dB louder, the 1st and 2nd with attacks of 6.0-6.4 dB at
// the spacing; the 5th, heard only in the ringing, on its bounce; eta-bar 0.5782 +- 0.0035 against
// the exact 0.5942.
void DoubtTheEndOfALeadingRunOnTheQuieterSound(std::vector<Impact>& impacts,
                                               const std::vector<MergedEvent>& merged,
                                               const std::vector<int>& members,
                                               const std::vector<double>& times, double spacing_s) {
  const std::size_t n = members.size();
  const double tolerance_s = PairTolerance(spacing_s);
  const auto at_spacing = [&](std::size_t k, double later_s) {
    return std::fabs(later_s - times[k] - spacing_s) <= tolerance_s;
  };
  const auto before_a_louder_sound = [&](std::size_t k) {
    const Impact& member = impacts[static_cast<std::size_t>(members[k])];
    if (std::isfinite(member.later_onset_s) && at_spacing(k, member.later_onset_s)) return true;
    return std::any_of(merged.begin(), merged.end(), [&](const MergedEvent& event) {
      return event.winner_s == member.onset_s && event.level_difference_db < 0 &&
             at_spacing(k, event.time_s);
    });
  };
  const auto before_a_fresh_attack = [&](std::size_t k) {
    const Impact& member = impacts[static_cast<std::size_t>(members[k])];
    return member.later_rise_db >= kFreshAttackDb && at_spacing(k, member.later_rise_s);
  };
  std::size_t run = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (before_a_louder_sound(k)) {
      run = k + 1;
    } else if (!before_a_fresh_attack(k)) {
      break;
    }
  }
  if (run < 2 || run + 2 > n) return;
  const int last = static_cast<int>(run) - 1;
  if (!(ImprovementOfAMove(times, last, 0, static_cast<int>(run), spacing_s) >
        kRequiredImprovement)) {
    return;
  }
  DoubtTheFlightAfterALeadingRun(impacts, members, run, spacing_s);
}

}  // namespace

void TakeMergedOnsetsThatFitTheSequence(std::vector<Impact>& impacts,
                                        std::vector<MergedEvent>& merged,
                                        const std::vector<BounceSequence>& sequences) {
  std::vector<bool> weighed(impacts.size(), false);
  std::vector<std::optional<double>> few_pairs_spacing;
  for (const auto& sequence : sequences) {
    few_pairs_spacing.push_back(TimeEveryPairOnOneSound(impacts, merged, sequence, weighed));
  }
  for (std::size_t s = 0; s < sequences.size(); ++s) {
    const BounceSequence& sequence = sequences[s];
    const auto& members = sequence.impact_indices;
    std::vector<double> times;
    for (int index : members) times.push_back(impacts[static_cast<std::size_t>(index)].onset_s);
    bool moved_by_its_neighbours = false;
    for (std::size_t k = 1; k < members.size(); ++k) {
      Impact& member = impacts[static_cast<std::size_t>(members[k])];
      const bool last = k + 1 == members.size();
      // An aligned onset is its own evidence, even where the alignment left it where the detector
      // put it: the recording's constant between response and onset is the weighted median over
      // its impacts, so the best-timed impact's aligned onset is its detector onset to the bit.
      // Taken for one the response timing never saw, such a bounce lost its onset to a sound 6.5
      // ms before it (silent_wrong_sweep.py seed 9 #27, MP3 64k: eta-bar 0.3304 +- 0.0023
      // against the exact 0.3455).
      if (member.timed_from_response) continue;
      // The last member has one neighbour and one ratio, extrapolated from the line: only a sound
      // before it may take its onset. The merger lets the later of two sounds in ringing win
      // when it is louder (EventMerger), and a soft contact's sound builds up for milliseconds,
      // so a last bounce in ringing was often timed on its later part while its start lay
      // merged before it (detector_accuracy_bench's soft 1 ms contact on a plate: +3.7 ms at
      // +-2.0 ms, its start merged 3.6 ms before it and 6.5 dB quieter). Later sounds are left
      // out: a neighbour milliseconds off tilts the one ratio, and in the silent-wrong sweep
      // (10261 files) later sounds moved 4 last members further from their bounces, to 6-26 ms
      // (up to 5 sigmas).
      // Nor a member the whole sequence weighed with its pair's other sound (below): that choice
      // holds the sound, and ratios on one side moved such a member back onto its click (the
      // sweep's 934p #33, -6.2 ms).
      if (last && weighed[static_cast<std::size_t>(members[k])]) continue;
      const double max_quieter_db =
          ReferenceOnOneSide(static_cast<int>(k), static_cast<int>(members.size()))
              ? kMaxQuieterExtrapolatedDb
              : kMaxQuieterDb;
      std::optional<RatioFit> now;
      double best_misfit = 0;
      MergedEvent* best_event = nullptr;
      // Misfits of the sounds before the member that it out-levelled by less than kCloseLevelDb.
      std::vector<std::pair<double, double>> close_before;  // (time, misfit)
      for (MergedEvent& event : merged) {
        if (event.winner_s != member.onset_s || event.time_s == member.onset_s) continue;
        if (event.level_difference_db > max_quieter_db) continue;
        const double before_s = last ? member.onset_s : times[k + 1];
        if (!(event.time_s > times[k - 1] && event.time_s < before_s)) continue;
        if (!now) {
          now = Misfit(times, static_cast<int>(k));
          if (!now) break;
          best_misfit = now->misfit;
        }
        std::vector<double> moved = times;
        moved[k] = event.time_s;
        const auto alternative = Misfit(moved, static_cast<int>(k));
        if (alternative && event.time_s < member.onset_s &&
            event.level_difference_db < kCloseLevelDb) {
          close_before.emplace_back(event.time_s, alternative->misfit);
        }
        if (alternative && alternative->misfit < best_misfit) {
          best_misfit = alternative->misfit;
          best_event = &event;
        }
      }
      if (best_event &&
          (now->misfit - best_misfit) / (now->scatter * now->scatter) > kRequiredImprovement) {
        const double taken_s = best_event->time_s;
        SwapWithTheMember(*best_event, member.onset_s,
                          "the sound there, which the merger had set aside, continues the bounce "
                          "sequence's interval ratios better (merged)");
        member.onset_s = taken_s;
        member.unsearched_span_s = 0;
        times[k] = taken_s;
        moved_by_its_neighbours = true;
      } else if (!member.residual_only && !weighed[static_cast<std::size_t>(members[k])]) {
        // Kept, with an earlier sound it out-levelled by less than a rise threshold that the
        // ratios do not reject either: the two may be one sound, rising for longer than they
        // lie apart (a 1 ms contact, whose band above 6 kHz grows for a millisecond; a soft
        // ball's slow build-up), whose later part is the louder over the same span whichever it
        // is, and which of its candidates opened first is a matter of where the tracker's frames
        // fell. Half their distance goes into the member's uncertainty, as for a codec's
        // pre-echo merge (detect_file.cc). silent_wrong_sweep.py seed 404 #8 (96 kHz, 1 ms
        // contact): the 5th bounce's first candidate closed in ringing 1.3 ms into the bounce,
        // the next took its onset 3.5 dB louder over that span, +1.37 ms at a stated 25 us,
        // eta-bar 8.9 sigmas off. Not in the merger, where the onsets are still to be tracked:
        // a member stated +-several ms widens the window for the next bounce, and a stray sound
        // took it (zaky-ptv's ping-pong as AAC at 22 kHz then formed no sequence). Not for a
        // member the whole sequence weighed with its pair's other sound: that choice, taken or
        // stated, already holds the sound (a moved member's click is then merged into it:
        // doubting it again widened 9 of 154 answers of --precursors seed 8 and 6 of 144 of seed
        // 9, up to 25 times, 8 #127's eta-bar sigma 0.0002 -> 0.0049 at 0.1 sigmas off).
        double doubt_s = 0;
        for (const auto& [time_s, misfit] : close_before) {
          if ((misfit - now->misfit) / (now->scatter * now->scatter) <= kRequiredImprovement) {
            doubt_s = std::max(doubt_s, 0.5 * (member.onset_s - time_s));
          }
        }
        member.onset_uncertainty_s = std::hypot(member.onset_uncertainty_s, doubt_s);
      }
    }
    // A member moved by its neighbours after the whole sequence was weighed changes what the
    // weighing saw, so the sequence is weighed again (--precursors seed 922 #61: members 0-3 on
    // their clicks with their bounces as later sounds, the 5th timed 3.9 ms after its bounce and
    // the rest on their clicks with nothing recorded; the late 5th made the bounces fit better,
    // members 0-3 moved to them, and then the 5th, by its neighbours, to its click: a switch
    // between the 4th and 5th at a stated 26 us, eta-bar 15 sigmas off).
    const bool weighed_before = std::any_of(members.begin(), members.end(), [&](int index) {
      return weighed[static_cast<std::size_t>(index)];
    });
    if (moved_by_its_neighbours && weighed_before) {
      TimeEveryPairOnOneSound(impacts, merged, sequence, weighed, /*weighed_again=*/true);
    }
    // One or two pairs are too few to weigh the sequence whole, but where a member is on the
    // quieter sound of its pair, their spacing is the switch each member alone may make: a
    // limiter leaves the loud first bounces on their clicks or their bounces bounce by bounce,
    // mostly with nothing merged (--limiter --precursors seed 968 #10: members 0-3 and 5 aligned
    // on their clicks 7.3 ms early, the 4th on its bounce, one pair, the 5th's bounce merged
    // after it 6 dB louder; eta-bar 308 sigmas off, now 2.0). So each middle member's move by
    // that spacing is judged as DoubtAMiddleMemberOfUnknownSound judges one with no pair, on the
    // onsets after the moves above (judged before them, a member its neighbours then moved onto
    // its bounce kept a doubt for where it had been: --limiter seed 965 #119). --limiter seeds
    // 956-968 (5200 files, 2863 eta-bars): silent wrong 16 -> 14 (960p #170 too), none new, 22
    // sigmas wider (7 of answers within one sigma, by at most 1.4 times); seeds 940-957 without
    // a limiter (7200 files): no answer changed, 17 wider (10 within one sigma, by at most 1.3
    // times). With pairs of quiet sounds too (any pair): 966 #166 mended as well, but 67 sigmas
    // wider, the detector suite's steel_scatter as AAC 11 times (precursors 18-20 dB under two
    // members, 3.6 and 7.2 ms before them, and a ball whose ratios scatter).
    if (few_pairs_spacing[s]) {
      DoubtAMiddleMemberOfUnknownSound(
          impacts, members,
          std::vector<std::pair<int, const OtherSound*>>(members.size(), {0, nullptr}), times,
          *few_pairs_spacing[s]);
      DoubtTheEndOfALeadingRunOnTheQuieterSound(impacts, merged, members, times,
                                                *few_pairs_spacing[s]);
    }
    DoubtAFirstMemberOnAQuieterSound(impacts, sequence, weighed);
    DoubtAFirstMemberBeforeALouderMergedSound(impacts, merged, sequence, weighed);
    DoubtAMemberBeforeAFreshAttackAtTheSpacing(impacts, merged, sequence);
  }
}

}  // namespace bouncecal::audio
