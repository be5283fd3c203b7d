#ifndef BOUNCECAL_PYTHON_BINDINGS_H_
#define BOUNCECAL_PYTHON_BINDINGS_H_

#include <pybind11/pybind11.h>

// One function per file registers the module's functions of one command (docs/python.md).
namespace bouncecal::python {

void BindAnalyze(pybind11::module_& module);    // analyze
void BindSimulate(pybind11::module_& module);   // simulate_drop
void BindCalibrate(pybind11::module_& module);  // calibrate, Calibration.card/write_card
void BindPack(pybind11::module_& module);       // pack
void BindExport(pybind11::module_& module);     // export, export_check

}  // namespace bouncecal::python

#endif  // BOUNCECAL_PYTHON_BINDINGS_H_
