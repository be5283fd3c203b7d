// The LAMMPS data start-positions format (atom_style sphere), as LAMMPS's write_data writes it
// and bouncecal's own packings are exported.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <string>
#include <utility>

#include "bouncecal/error.h"
#include "scene/particle_file_parsers.h"

namespace bouncecal::dem::scene::particle_file {

namespace {

// A LAMMPS section header (Velocities, Pair Coeffs, ...) rather than a row: ends the Atoms
// section. A row has at least 7 fields and starts with a number ("inf" and "nan" read as numbers,
// so a row holding them is refused as not finite, and a garbled row as not a number).
bool IsSectionHeader(const std::vector<std::string>& fields) {
  if (fields.size() >= 7 || !std::isalpha(static_cast<unsigned char>(fields[0][0]))) return false;
  try {
    std::size_t used = 0;
    std::stod(fields[0], &used);
    return used != fields[0].size();
  } catch (const std::exception&) {
    return true;
  }
}

}  // namespace

std::vector<FileParticle> ReadLammpsData(std::istream& in, const std::filesystem::path& path,
                                         int dimension) {
  std::string line;
  int line_no = 0;
  int header_line = 0;
  std::int64_t atoms = -1;
  while (std::getline(in, line)) {
    ++line_no;
    const auto fields = SplitFields(line.substr(0, line.find('#')), false);
    if (fields.size() == 2 && fields[1] == "atoms") {
      atoms = ParseWhole(fields[0], path, line_no, 0, 1e15);
      header_line = line_no;
    }
    if (!fields.empty() && fields[0] == "Atoms") break;
  }
  if (atoms < 0) {
    throw InputError(path.string() + ": no 'N atoms' header line; expected a LAMMPS data file");
  }
  RefuseCount(path, static_cast<double>(atoms), dimension);
  std::vector<std::pair<std::int64_t, FileParticle>> read;
  // The section runs to the next section header or the end of the file, not just to the
  // announced count: rows past it would otherwise be dropped without a word.
  while (std::getline(in, line)) {
    ++line_no;
    const auto fields = SplitFields(line.substr(0, line.find('#')), false);
    if (fields.empty()) continue;
    if (IsSectionHeader(fields)) break;
    if (static_cast<std::int64_t>(read.size()) == atoms) {
      throw InputError(fmt::format(
          "{}: the Atoms section holds more than the {} atoms the header announces on line {}; "
          "fix the 'N atoms' line or remove the extra rows",
          Where(path, line_no), atoms, header_line));
    }
    if (fields.size() < 7) {
      throw InputError(Where(path, line_no) +
                       ": expected 'id type diameter density x y z' (atom_style sphere)");
    }
    NewParticle p;
    const auto id = ParseWhole(fields[0], path, line_no, -1e15, 1e15);
    p.species = static_cast<std::int32_t>(ParseWhole(fields[1], path, line_no, 1, kMaxSpecies)) - 1;
    p.radius_m = 0.5 * ParseNumber(fields[2], path, line_no);
    for (int d = 0; d < dimension; ++d) {
      p.position_m[d] = ParseNumber(fields[4 + d], path, line_no);
    }
    if (dimension == 2) RefuseZIn2d(ParseNumber(fields[6], path, line_no), path, line_no);
    if (!(p.radius_m > 0) || p.species < 0) {
      throw InputError(Where(path, line_no) + ": diameter must be > 0 and type >= 1");
    }
    read.push_back({id, {p, line_no}});
  }
  if (static_cast<std::int64_t>(read.size()) != atoms) {
    throw InputError(fmt::format(
        "{}: the Atoms section holds {} of the {} atoms the header announces; fix the 'N atoms' "
        "line or add the missing rows",
        Where(path, header_line), read.size(), atoms));
  }
  std::stable_sort(read.begin(), read.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (std::size_t k = 1; k < read.size(); ++k) {
    if (read[k].first == read[k - 1].first) {
      throw InputError(fmt::format(
          "{}: atom id {} appears again (first on line {}); LAMMPS atom ids must be unique",
          Where(path, read[k].second.line), read[k].first, read[k - 1].second.line));
    }
  }
  std::vector<FileParticle> out;
  out.reserve(read.size());
  for (const auto& entry : read) out.push_back(entry.second);
  return out;
}

}  // namespace bouncecal::dem::scene::particle_file
