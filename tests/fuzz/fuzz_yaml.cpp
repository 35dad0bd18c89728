// libFuzzer target: the YAML readers of scenarios and configs (app/scenario.h:
// parseScenario and parseConfig). The first byte picks the reader (0 scenario,
// 1 config), the rest is the file. The header promises InputError for any problem
// (invalid YAML included: src/app/scenario.cpp turns YAML::Exception into InputError),
// so only InputError is expected; anything else (a crash, a sanitizer report, a
// yaml-cpp or other exception, a leak) is a finding. scripts/fuzz.sh.

#include <cstddef>
#include <cstdint>
#include <string>

#include "uavip/app/scenario.h"
#include "uavip/core/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    if (data[0] % 2 == 0) {
      uavip::app::parseScenario(text, "fuzz.yaml");
    } else {
      uavip::app::parseConfig(text, "fuzz.yaml");
    }
  } catch (const uavip::InputError&) {
  }
  return 0;
}
