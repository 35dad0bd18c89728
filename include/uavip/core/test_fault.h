#pragma once
/// \file
/// The test hook of the fault tests on the Slurm path (scripts/slurm/faults.sh): a
/// task (a command and its array index) fails or is killed on purpose, reliably, at a
/// chosen point. Armed only by the environment variable UAVIP_TEST_FAULT, whose value is
/// "TASK:ACTION" with TASK as the command names it (setFaultTask: "run-tile 3",
/// "plan-section 1", "merge") and ACTION one of
///  - kill-mid-write: io::StagedOutputs::commit() renames the first half of its staged
///    files onto their targets, then the process kills itself with SIGKILL (a task lost
///    in the middle of writing its outputs);
///  - fail: the command throws before it commits anything (a task that fails).
/// Unset (always, outside the tests) nothing changes.

#include <string>

namespace uavip::core {

/// Names this process's task for UAVIP_TEST_FAULT (the CLI, once it knows its index).
void setFaultTask(const std::string& task);

/// True when UAVIP_TEST_FAULT asks `action` of this process's task.
bool faultArmed(const std::string& action);

/// Throws std::runtime_error "test fault: TASK fails (UAVIP_TEST_FAULT)" when "fail" is
/// armed for this task.
void failIfArmed();

}  // namespace uavip::core
