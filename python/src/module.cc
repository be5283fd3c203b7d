// The extension module bouncecal._bouncecal; bouncecal/__init__.py re-exports its functions.
#include <pybind11/pybind11.h>

#include <string>

#include "bindings.h"
#include "bouncecal/version.h"
#include "errors.h"
#include "keywords.h"

PYBIND11_MODULE(_bouncecal, module) {
  module.doc() =
      "bouncecal's libraries for Python: analyze, simulate_drop, calibrate, pack, export, "
      "export_check (docs/python.md).";
  module.attr("__version__") = std::string(bouncecal::Version());
  bouncecal::python::RegisterErrorTranslation();
  bouncecal::python::BindAnalyze(module);
  bouncecal::python::BindSimulate(module);
  bouncecal::python::BindCalibrate(module);
  bouncecal::python::BindPack(module);
  bouncecal::python::BindExport(module);
  // Result documents keep the libraries' neutral text (options named in backticks, the same
  // document as the command line's --json); what a person reads is spelt in keywords.
  module.def("_with_keywords", &bouncecal::python::WithKeywords, pybind11::arg("message"),
             "The message with each option it names in backticks spelt as Python's keyword.");
}
