// The CSV start-positions format: a header naming the columns, one row per particle.
#include <algorithm>
#include <string>

#include "bouncecal/error.h"
#include "scene/particle_file_parsers.h"

namespace bouncecal::dem::scene::particle_file {

std::vector<FileParticle> ReadCsv(std::istream& in, const std::filesystem::path& path,
                                  int dimension) {
  std::string line;
  int line_no = 0;
  std::vector<std::string> header;
  while (header.empty() && std::getline(in, line)) {
    ++line_no;
    // Spreadsheet programs often save "CSV UTF-8" with a byte order mark before the header.
    if (line_no == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    if (line.empty() || line[0] == '#') continue;
    header = SplitFields(line, true);
  }
  if (header.empty()) {
    throw InputError(path.string() + ": is empty; expected a header line x_m,y_m" +
                     (dimension == 3 ? ",z_m" : "") +
                     ",diameter_m[,species] and one row per particle");
  }
  auto column = [&](const std::string& name, bool required) -> int {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) {
      if (required) {
        throw InputError(path.string() + ": the header has no '" + name +
                         "' column; expected x_m,y_m" + (dimension == 3 ? ",z_m" : "") +
                         ",diameter_m[,species]");
      }
      return -1;
    }
    return static_cast<int>(it - header.begin());
  };
  const int cx = column("x_m", true);
  const int cy = column("y_m", true);
  const int cz = column("z_m", dimension == 3);
  const int cd = column("diameter_m", true);
  const int cs = column("species", false);
  std::vector<FileParticle> out;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#' || line.find_first_not_of(" \t\r") == std::string::npos) {
      continue;
    }
    const auto fields = SplitFields(line, true);
    if (fields.size() != header.size()) {
      throw InputError(Where(path, line_no) + ": " + std::to_string(fields.size()) +
                       " fields where the header has " + std::to_string(header.size()));
    }
    NewParticle p;
    p.position_m[0] = ParseNumber(fields[cx], path, line_no);
    p.position_m[1] = ParseNumber(fields[cy], path, line_no);
    if (cz >= 0) {
      const double z = ParseNumber(fields[cz], path, line_no);
      if (dimension == 3) {
        p.position_m[2] = z;
      } else {
        RefuseZIn2d(z, path, line_no);
      }
    }
    p.radius_m = 0.5 * ParseNumber(fields[cd], path, line_no);
    if (cs >= 0) {
      p.species = static_cast<std::int32_t>(ParseWhole(fields[cs], path, line_no, 0, kMaxSpecies));
    }
    if (!(p.radius_m > 0) || p.species < 0) {
      throw InputError(Where(path, line_no) + ": diameter must be > 0 and species >= 0");
    }
    out.push_back({p, line_no});
    // Checked while reading so a runaway file is refused before it fills memory.
    if (out.size() > static_cast<std::size_t>(kMaxSceneParticles)) {
      RefuseCount(path, static_cast<double>(out.size()), dimension);
    }
  }
  return out;
}

}  // namespace bouncecal::dem::scene::particle_file
