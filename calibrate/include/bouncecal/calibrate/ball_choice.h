#ifndef BOUNCECAL_CALIBRATE_BALL_CHOICE_H_
#define BOUNCECAL_CALIBRATE_BALL_CHOICE_H_

#include <optional>
#include <string>

#include "bouncecal/dem/drop.h"

namespace bouncecal::calibrate {

// How a user names a ball: a preset (`ball`, e.g. "tennis") or its size with either its density
// (solid) or its mass (hollow). The command line and Python fill this from their options and
// keywords and share one set of rules (ResolveBall), so the two cannot drift apart; each front end
// spells the fields its own way (--diameter-m, diameter_m).
struct BallChoice {
  std::optional<std::string> preset;  // field `ball`
  std::optional<double> diameter_m;
  std::optional<double> density_kg_per_m3;
  std::optional<double> mass_kg;

  bool Given() const { return preset || diameter_m || density_kg_per_m3 || mass_kg; }
};

// What a partly described ball is completed with.
enum class BallCompletion {
  // An experiment's ball (calibrate, material cards): never assumed, so a size needs a mass and
  // a mass a size.
  kAsGiven,
  // A simulation's ball: what is left out is the paper's 1 cm steel ball's (dem::Ball{}).
  kPaperBall,
};

// The ball the choice describes, or nothing when none of its fields is set. A preset excludes
// the other three, density excludes mass, and every value must lie in dem::Ball's valid range.
// Problems are OptionErrors naming the fields, spelt by each front end.
std::optional<dem::Ball> ResolveBall(const BallChoice& choice, BallCompletion completion);

}  // namespace bouncecal::calibrate

#endif  // BOUNCECAL_CALIBRATE_BALL_CHOICE_H_
