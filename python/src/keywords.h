#ifndef BOUNCECAL_PYTHON_KEYWORDS_H_
#define BOUNCECAL_PYTHON_KEYWORDS_H_

#include <string>
#include <string_view>

namespace bouncecal::python {

// `message` with each option the libraries name in backticks (bouncecal::SpellOptions) spelt as
// Python's keyword: `first_n=3` -> first_n=3, `objective=intervals` -> objective='intervals'.
// An option only the command line has is named as its flag, saying so.
std::string WithKeywords(std::string_view message);

}  // namespace bouncecal::python

#endif  // BOUNCECAL_PYTHON_KEYWORDS_H_
