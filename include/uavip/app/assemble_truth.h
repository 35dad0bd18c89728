#pragma once
/// \file
/// Stages 1–2 scored against the simulator's ground truth (paper §III: loop closure,
/// drift, registration; docs/ARCHITECTURE.md, sim/): the numbers of
/// `cloud.report.json` that exist only when the truth is known. Evaluation, not a
/// stage: app::assemble calls these only when it is given the truth.

#include "uavip/app/assemble.h"
#include "uavip/core/raw_log.h"
#include "uavip/registration/station_registration.h"
#include "uavip/scan/station_assembler.h"
#include "uavip/sim/world_model.h"

namespace uavip::app {

/// The scenario's true world moved into a raw log's frame: every primitive shifted by
/// −`origin_m` (sim::SimulatedLog::origin_m, the log frame's origin in scenario
/// coordinates [m]).
sim::WorldModel worldInLogFrame(const sim::WorldModel& world, const Vec3& origin_m);

/// Scores station `c` (stage 1) registered as `r` (stage 2) against its true body
/// poses: the drift errors over the turn, the true drift, the errors of the recorded
/// and the registered station position and the registered rotation. The station
/// frame's origin is the UAV centre at the first horizontal scan, with world axes.
/// Leaves `s` as it is when the truth has no horizontal pose.
void scoreStation(StationReport& s, const scan::StationCloud& c,
                  const registration::StationResult& r, const RawLogTruth::StationTruth& truth);

/// Scores the merged cloud of `result` against the true surfaces of `world` (log
/// frame): RMS and 95th percentile of the point-to-truth distances over an even
/// subsample of at most 200,000 points, `threads` at a time. Nothing when the world
/// or the cloud is empty.
void scoreCloud(AssembleResult& result, const sim::WorldModel& world, int threads);

}  // namespace uavip::app
