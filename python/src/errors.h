#ifndef BOUNCECAL_PYTHON_ERRORS_H_
#define BOUNCECAL_PYTHON_ERRORS_H_

#include <pybind11/pybind11.h>

namespace bouncecal::python {

// Raises bouncecal.InputError, ConfigError, OutputError, CheckFailedError or Error (python
// bouncecal/_errors.py) for the bouncecal::Error of the same name, with its one-line message.
void RegisterErrorTranslation();

}  // namespace bouncecal::python

#endif  // BOUNCECAL_PYTHON_ERRORS_H_
