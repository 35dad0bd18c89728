// libFuzzer target: scene.json and mission.json as uavip reads them
// (io/scene_json.h sceneFromJson; io/mission_export.h flightFromMissionJson and
// sortiesFromMissionJson). The first byte picks the reader. Invalid JSON or a
// document the reader refuses must end in InputError / NoMissionError / a JSON
// parse error; anything else is a finding. scripts/fuzz.sh.

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "uavip/core/error.h"
#include "uavip/io/mission_export.h"
#include "uavip/io/scene_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception&) {
    return 0;
  }
  try {
    switch (data[0] % 4) {
      case 0:
        uavip::io::sceneFromJson(j, "fuzz.json");
        break;
      case 1:
        uavip::io::flightFromMissionJson(j, "fuzz.json", "");
        break;
      case 2:
        uavip::io::flightFromMissionJson(j, "fuzz.json", "0");
        break;
      default:
        uavip::io::sortiesFromMissionJson(j, "fuzz.json");
        break;
    }
  } catch (const uavip::InputError&) {
  } catch (const uavip::io::NoMissionError&) {
  }
  return 0;
}
