#include "errors.h"

#include <Python.h>

#include <exception>
#include <string>
#include <string_view>

#include "bouncecal/error.h"
#include "bouncecal/option_error.h"
#include "keywords.h"

namespace bouncecal::python {
namespace {

// Every message is spelt for Python first: the libraries name options in backticks.
void Raise(const char* class_name, const std::string& message) {
  PyObject* errors = PyImport_ImportModule("bouncecal._errors");
  if (errors == nullptr) return;  // the ImportError stays set: the package itself is broken
  PyObject* type = PyObject_GetAttrString(errors, class_name);
  Py_DECREF(errors);
  if (type == nullptr) return;
  PyErr_SetString(type, WithKeywords(message).c_str());
  Py_DECREF(type);
}

}  // namespace

void RegisterErrorTranslation() {
  pybind11::register_exception_translator([](std::exception_ptr pending) {
    try {
      if (pending) std::rethrow_exception(pending);
    } catch (const InputError& error) {
      Raise("InputError", error.what());
    } catch (const OptionError& error) {
      // The library names its fields; Python's keywords are the same names.
      const auto keyword = [](std::string_view field) { return std::string(field); };
      Raise("ConfigError", SpellFields(error.what(), error.fields(), keyword));
    } catch (const ConfigError& error) {
      Raise("ConfigError", error.what());
    } catch (const OutputError& error) {
      Raise("OutputError", error.what());
    } catch (const CheckFailedError& error) {
      Raise("CheckFailedError", error.what());
    } catch (const Error& error) {
      Raise("Error", error.what());
    }
  });
}

}  // namespace bouncecal::python
