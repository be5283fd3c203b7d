#include "python_values.h"

#include <cmath>
#include <string>

#include "bouncecal/error.h"

namespace bouncecal::python {

namespace py = pybind11;

py::object NewResult(const char* type_name) {
  return py::module_::import("bouncecal._result").attr(type_name)();
}

py::array_t<double> FloatArray(const std::vector<double>& values) {
  return py::array_t<double>(static_cast<py::ssize_t>(values.size()), values.data());
}

py::object OptionalFloat(const std::optional<double>& value) {
  return value ? py::object(py::float_(*value)) : py::object(py::none());
}

py::list StringList(const std::vector<std::string>& values) {
  py::list list;
  for (const auto& value : values) list.append(value);
  return list;
}

namespace {

bool IsNumberOrNull(const nlohmann::json& value) { return value.is_number() || value.is_null(); }

// Rows of numbers, all of one length: a matrix.
bool IsNumberMatrix(const nlohmann::json& array) {
  if (array.empty() || !array.front().is_array() || array.front().empty()) return false;
  const std::size_t columns = array.front().size();
  for (const auto& row : array) {
    if (!row.is_array() || row.size() != columns) return false;
    for (const auto& value : row) {
      if (!IsNumberOrNull(value)) return false;
    }
  }
  return true;
}

double AsDouble(const nlohmann::json& value) {
  return value.is_null() ? std::nan("") : value.get<double>();
}

py::object NumberArray(const nlohmann::json& array) {
  bool integers = !array.empty();
  for (const auto& value : array) integers = integers && value.is_number_integer();
  if (integers) {
    py::array_t<std::int64_t> out(static_cast<py::ssize_t>(array.size()));
    auto view = out.mutable_unchecked<1>();
    for (std::size_t i = 0; i < array.size(); ++i) {
      view(static_cast<py::ssize_t>(i)) = array[i].get<std::int64_t>();
    }
    return out;
  }
  py::array_t<double> out(static_cast<py::ssize_t>(array.size()));
  auto view = out.mutable_unchecked<1>();
  for (std::size_t i = 0; i < array.size(); ++i) {
    view(static_cast<py::ssize_t>(i)) = AsDouble(array[i]);
  }
  return out;
}

py::object NumberMatrix(const nlohmann::json& array) {
  const auto rows = static_cast<py::ssize_t>(array.size());
  const auto columns = static_cast<py::ssize_t>(array.front().size());
  py::array_t<double> out({rows, columns});
  auto view = out.mutable_unchecked<2>();
  for (py::ssize_t r = 0; r < rows; ++r) {
    for (py::ssize_t c = 0; c < columns; ++c) {
      view(r, c) = AsDouble(array[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)]);
    }
  }
  return out;
}

}  // namespace

py::object FromJson(const nlohmann::json& value) {
  switch (value.type()) {
    case nlohmann::json::value_t::object: {
      py::object result = NewResult();
      for (const auto& [key, item] : value.items()) result[py::str(key)] = FromJson(item);
      return result;
    }
    case nlohmann::json::value_t::array: {
      // An empty array says nothing of what it would hold (numbers, strings, records): it is
      // an empty list, so that a list of warnings or recordings is a list whether or not empty.
      bool numbers = !value.empty();
      for (const auto& item : value) numbers = numbers && IsNumberOrNull(item);
      if (numbers) return NumberArray(value);
      if (IsNumberMatrix(value)) return NumberMatrix(value);
      py::list list;
      for (const auto& item : value) list.append(FromJson(item));
      return list;
    }
    case nlohmann::json::value_t::string:
      return py::str(value.get<std::string>());
    case nlohmann::json::value_t::boolean:
      return py::bool_(value.get<bool>());
    case nlohmann::json::value_t::number_integer:
      return py::int_(value.get<std::int64_t>());
    case nlohmann::json::value_t::number_unsigned:
      return py::int_(value.get<std::uint64_t>());
    case nlohmann::json::value_t::number_float:
      return py::float_(value.get<double>());
    default:
      return py::none();
  }
}

py::object TableFromRecords(const nlohmann::json& records, const std::vector<std::string>& columns,
                            const std::vector<std::string>& text_columns,
                            const std::vector<std::string>& bool_columns) {
  py::object table = NewResult("Table");
  for (const auto& column : columns) {
    nlohmann::json values = nlohmann::json::array();
    for (const auto& record : records) values.push_back(record.at(column));
    table[py::str(column)] = values.empty() ? py::object(FloatArray({})) : FromJson(values);
  }
  for (const auto& column : bool_columns) {
    py::array_t<bool> values(static_cast<py::ssize_t>(records.size()));
    auto view = values.mutable_unchecked<1>();
    for (std::size_t i = 0; i < records.size(); ++i) {
      view(static_cast<py::ssize_t>(i)) = records[i].at(column).get<bool>();
    }
    table[py::str(column)] = values;
  }
  for (const auto& column : text_columns) {
    py::list values;
    for (const auto& record : records) values.append(record.at(column).get<std::string>());
    table[py::str(column)] = values;
  }
  return table;
}

nlohmann::json ToJson(py::handle value, std::string_view context) {
  const std::string where(context);
  if (value.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value)) return value.cast<std::int64_t>();
  if (py::isinstance<py::float_>(value)) {
    const double number = value.cast<double>();
    if (!std::isfinite(number)) {
      throw ConfigError(where + ": " + std::to_string(number) + " is not a finite number");
    }
    return number;
  }
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::dict>(value)) {
    nlohmann::json object = nlohmann::json::object();
    for (const auto& [key, item] : value.cast<py::dict>()) {
      if (!py::isinstance<py::str>(key)) {
        throw ConfigError(where + ": key " + py::repr(key).cast<std::string>() +
                          " is not a string; JSON objects have string keys");
      }
      const auto name = key.cast<std::string>();
      object[name] = ToJson(item, where + "." + name);
    }
    return object;
  }
  // numpy scalars and arrays go through their Python equivalents.
  if (py::hasattr(value, "tolist") && py::hasattr(value, "dtype")) {
    return ToJson(value.attr("tolist")(), context);
  }
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    nlohmann::json array = nlohmann::json::array();
    std::size_t index = 0;
    for (const auto& item : value) {
      array.push_back(ToJson(item, where + "[" + std::to_string(index++) + "]"));
    }
    return array;
  }
  throw ConfigError(where + ": a " + py::type::of(value).attr("__name__").cast<std::string>() +
                    " cannot be written as JSON; give a dict, list, str, number, bool or None");
}

bool IsPathLike(py::handle value) {
  return py::isinstance<py::str>(value) || py::hasattr(value, "__fspath__");
}

std::filesystem::path ToPath(py::handle value, std::string_view what) {
  if (!IsPathLike(value)) {
    throw ConfigError(std::string(what) + " must be a path (str or os.PathLike), got a " +
                      py::type::of(value).attr("__name__").cast<std::string>());
  }
  const py::object text = py::module_::import("os").attr("fspath")(value);
  if (!py::isinstance<py::str>(text)) {
    throw ConfigError(std::string(what) + " must be a text path, got bytes");
  }
  return std::filesystem::path(text.cast<std::string>());
}

}  // namespace bouncecal::python
