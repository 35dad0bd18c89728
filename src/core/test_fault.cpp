#include "uavip/core/test_fault.h"

#include <cstdlib>
#include <stdexcept>

namespace uavip::core {
namespace {

std::string& faultTask() {
  static std::string task;
  return task;
}

}  // namespace

void setFaultTask(const std::string& task) { faultTask() = task; }

bool faultArmed(const std::string& action) {
  const char* want = std::getenv("UAVIP_TEST_FAULT");
  return want != nullptr && !faultTask().empty() && want == faultTask() + ":" + action;
}

void failIfArmed() {
  if (faultArmed("fail"))
    throw std::runtime_error("test fault: " + faultTask() + " fails (UAVIP_TEST_FAULT)");
}

}  // namespace uavip::core
