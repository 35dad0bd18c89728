// libFuzzer target: the cloud readers (io/cloud_io.h: PCD and PLY through the
// header checks and PCL; XYZ, TXT and CSV text; LAS) with their recentring of a
// cloud far from the origin. The first byte picks the format (low 3 bits: pcd, ply,
// xyz, csv, txt, las) and whether input.scale is 1 or 0.001 (bit 3); the rest is the
// file. A reader may refuse the bytes with InputError; anything else (a crash, a
// sanitizer report, another exception, a leak) is a finding, and so is a point the
// readers promise not to return: non-finite, or, after recentring, farther from the
// origin than the cloud's largest allowed extent plus 10 km. scripts/fuzz.sh.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>

#include "uavip/core/error.h"
#include "uavip/io/cloud_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const kExtensions[] = {".pcd", ".ply", ".xyz", ".csv",
                                            ".txt", ".las", ".xyz", ".csv"};
  static const std::string base = "/tmp/uavip_fuzz_cloud_" + std::to_string(::getpid());
  const std::string path = base + kExtensions[data[0] & 7];
  {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  uavip::io::CloudReadOptions options;
  if (data[0] & 8) options.scale = 0.001;
  try {
    uavip::io::CloudReadInfo info;
    const uavip::PointList points = uavip::io::loadCloud(path, options, &info);
    if (!info.origin_m.allFinite()) __builtin_trap();
    for (const auto& p : points) {
      if (!p.allFinite()) __builtin_trap();  // the readers promise finite points
      // Recentred and no wider than kMaxCloudExtentM: every point near the origin.
      if (p.cwiseAbs().maxCoeff() > uavip::io::kMaxCloudExtentM + uavip::io::kRecentreBeyondM)
        __builtin_trap();
    }
  } catch (const uavip::InputError&) {
  }
  std::remove(path.c_str());
  return 0;
}
