#ifndef BOUNCECAL_PYTHON_ARGUMENTS_H_
#define BOUNCECAL_PYTHON_ARGUMENTS_H_

#include <pybind11/pybind11.h>

#include <ctime>
#include <optional>
#include <string>

#include "bouncecal/calibrate/ball_choice.h"
#include "bouncecal/dem/contact_law.h"
#include "bouncecal/dem/drop.h"

// Keyword arguments that several functions share (a law, a ball), turned into library values.
// Problems are ConfigError naming the keyword, as the command line names its option.
namespace bouncecal::python {

// `law`: a law name ("walton-braun") or a {"law", "parameters"} dict as in a material card's
// "contact_law"; `parameters`: None or {name: value} on top of it. Validated unless `validate` is
// false.
dem::ContactLawConfig LawFromPython(pybind11::handle law, pybind11::handle parameters,
                                    bool validate = true);

// The ball keywords (ball=, diameter_m=, density_kg_per_m3=, mass_kg=) under the command line's
// rules (calibrate::ResolveBall), or nothing when none was given. `complete` (calibrate: an
// experiment's ball is never assumed) asks a size with a mass; otherwise what is missing is the
// 1 cm steel ball's.
std::optional<dem::Ball> BallFromArguments(const calibrate::BallChoice& arguments, bool complete);

// The value of SOURCE_DATE_EPOCH when set (ConfigError unless a whole number of seconds in
// 0..9999-12-31), else now: when a material card says it was made, as the command line does.
std::time_t CardCreationTime();

}  // namespace bouncecal::python

#endif  // BOUNCECAL_PYTHON_ARGUMENTS_H_
