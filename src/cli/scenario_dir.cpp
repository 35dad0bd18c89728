#include "src/cli/scenario_dir.h"

#ifndef UAVIP_SCENARIO_DIR
#define UAVIP_SCENARIO_DIR "scenarios"
#endif

namespace uavip::cli {

std::string bundledScenarioDir() { return UAVIP_SCENARIO_DIR; }

}  // namespace uavip::cli
