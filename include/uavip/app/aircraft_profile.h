#pragma once
/// \file
/// The aircraft profile layer of the config (core/params.h: default < profile <
/// `auto` < file): `uav.model` / `uav.payload` in a config, or `--drone` / `--payload`
/// on `plan` and `run`, name a profile of core/aircraft.h whose figures become the
/// camera, the gimbal's pitch range, the speeds, the endurance and the UAV's size
/// wherever the file does not set them.

#include <string>
#include <vector>

#include "uavip/app/scenario.h"
#include "uavip/core/aircraft.h"

namespace uavip::app {

/// Applies the profile `config.uav.model` names (with `config.uav.payload`) at the
/// profile layer; `generic` sets nothing. Values the file set stay; a camera the file
/// describes by any camera key stays whole. Returns one line per value the profile
/// set or capped, for the summary. Throws InputError (prefix `where`) for an unknown
/// name or a payload the drone cannot carry.
std::vector<std::string> applyAircraftProfile(Config& config, const std::string& where);

/// Sets `uav.model` and `uav.payload` from `--drone` / `--payload` (empty: keep the
/// file's) and applies the profile; the command line outranks the file for these two.
std::vector<std::string> selectAircraft(Config& config, const std::string& drone,
                                        const std::string& payload);

/// The GSD a camera gives at `distance_m` from a surface, the coarser axis [mm/px].
double gsdAt(const aircraft::CameraSpec& camera, double distance_m);

}  // namespace uavip::app
