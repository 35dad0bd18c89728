#include "uavip/core/error.h"

#include <cmath>
#include <sstream>

namespace uavip {

void require(bool cond, const std::string& where, const std::string& what) {
  if (!cond) throw InputError(where + ": " + what);
}

void requirePositive(double value, const std::string& where, const std::string& name) {
  if (!(std::isfinite(value) && value > 0.0)) {
    std::ostringstream os;
    os << where << ": " << name << " must be > 0, got " << value;
    throw InputError(os.str());
  }
}

void requireThat(bool ok, const std::string& where, const std::string& name,
                 const std::string& range, double value) {
  if (!ok) {
    std::ostringstream os;
    os << where << ": " << name << " must be " << range << ", got " << value;
    throw InputError(os.str());
  }
}

}  // namespace uavip
