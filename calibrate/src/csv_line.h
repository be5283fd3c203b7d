#ifndef BOUNCECAL_CALIBRATE_SRC_CSV_LINE_H_
#define BOUNCECAL_CALIBRATE_SRC_CSV_LINE_H_

#include <string>
#include <vector>

namespace bouncecal::calibrate::internal {

// `text` without its leading and trailing spaces, tabs and carriage returns.
std::string TrimBlanks(const std::string& text);

// The comma-separated fields of one line, each trimmed; a field in double quotes may hold commas
// ("" is a quote), as `bouncecal analyze --csv` writes a file name that has one.
std::vector<std::string> SplitCsvLine(const std::string& line);

}  // namespace bouncecal::calibrate::internal

#endif  // BOUNCECAL_CALIBRATE_SRC_CSV_LINE_H_
