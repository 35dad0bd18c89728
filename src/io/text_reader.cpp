// XYZ, TXT and CSV clouds: x y z first on each line (io/cloud_io.h, loadCloud).

#include <algorithm>
#include <cctype>
#include <exception>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>

#include "cloud_formats.h"
#include "uavip/core/error.h"
#include "uavip/core/text.h"
#include "uavip/io/atomic_file.h"

namespace uavip::io {

void parseXyz(std::istream& in, const std::string& path,
              const std::function<void(const Vec3&)>& point) {
  std::string line;
  std::size_t line_no = 0;
  bool header_allowed = true;  // until the first line that is not blank or a comment
  while (std::getline(in, line)) {
    ++line_no;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream fields(line);
    std::string sx, sy, sz;
    // A header of column names before the first point (CloudCompare writes
    // "//X,Y,Z", spreadsheets "x,y,z"): its first word starts with a letter or '/'.
    if (header_allowed &&
        (std::isalpha(static_cast<unsigned char>(line[first])) || line[first] == '/') &&
        line.find_first_of("0123456789") == std::string::npos) {
      header_allowed = false;
      continue;
    }
    header_allowed = false;
    if (!(fields >> sx >> sy >> sz)) {
      throw InputError(path + ":" + std::to_string(line_no) + ": expected 'x y z', got '" + line +
                       "'");
    }
    Vec3 p;
    try {
      std::size_t used = 0;
      const std::string* parts[3] = {&sx, &sy, &sz};
      for (int i = 0; i < 3; ++i) {
        p[i] = std::stod(*parts[i], &used);
        if (used != parts[i]->size()) throw std::invalid_argument(*parts[i]);
      }
    } catch (const std::exception&) {
      throw InputError(path + ":" + std::to_string(line_no) + ": not a number in '" + line + "'");
    }
    if (!p.allFinite()) {
      throw InputError(path + ":" + std::to_string(line_no) + ": point " + formatRawPoint(p) +
                       " is not finite; remove the line");
    }
    point(p);
  }
}

PointList loadXyz(const std::string& path) {
  std::istringstream in(readFile(path));
  PointList out;
  parseXyz(in, path, [&](const Vec3& p) { out.push_back(p); });
  return out;
}

}  // namespace uavip::io
