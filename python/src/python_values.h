#ifndef BOUNCECAL_PYTHON_PYTHON_VALUES_H_
#define BOUNCECAL_PYTHON_PYTHON_VALUES_H_

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

// The conversions every binding shares, between the libraries' values and what the module hands
// to Python: results are bouncecal._result.Result objects (dicts whose keys read as attributes,
// with the keys of the command line's JSON), numbers in sequence are numpy arrays.
namespace bouncecal::python {

// A new, empty object of the class `type_name` of bouncecal._result (Result, Table, Calibration,
// Deck).
pybind11::object NewResult(const char* type_name = "Result");

pybind11::array_t<double> FloatArray(const std::vector<double>& values);
template <typename Int>
pybind11::array_t<std::int64_t> IntArray(const std::vector<Int>& values) {
  pybind11::array_t<std::int64_t> array(static_cast<pybind11::ssize_t>(values.size()));
  auto out = array.template mutable_unchecked<1>();
  for (std::size_t i = 0; i < values.size(); ++i) {
    out(static_cast<pybind11::ssize_t>(i)) = static_cast<std::int64_t>(values[i]);
  }
  return array;
}
pybind11::object OptionalFloat(const std::optional<double>& value);
pybind11::list StringList(const std::vector<std::string>& values);

// The library's JSON as Python: objects become Result, non-empty arrays of numbers numpy arrays
// (int64 when every element is an integer, else float64 with NaN for null; arrays of equally long
// number arrays two-dimensional), other arrays (and empty ones) lists, null None.
pybind11::object FromJson(const nlohmann::json& value);

// A list of per-event JSON records as a Table of columns (numpy arrays: int64 where every entry
// is an integer, bool for `bool_columns`, float64 with NaN for null; lists of str for
// `text_columns`). An empty list gives empty float64 columns (empty lists for text).
pybind11::object TableFromRecords(const nlohmann::json& records,
                                  const std::vector<std::string>& columns,
                                  const std::vector<std::string>& text_columns = {},
                                  const std::vector<std::string>& bool_columns = {});

// A Python value as JSON: dict (string keys), list, tuple, str, bool, int, float, None, numpy
// arrays and scalars. ConfigError naming `context` for anything else or a non-finite float.
nlohmann::json ToJson(pybind11::handle value, std::string_view context);

// A str or os.PathLike as a path; ConfigError naming `what` otherwise.
std::filesystem::path ToPath(pybind11::handle value, std::string_view what);
bool IsPathLike(pybind11::handle value);

}  // namespace bouncecal::python

#endif  // BOUNCECAL_PYTHON_PYTHON_VALUES_H_
