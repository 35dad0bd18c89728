// libFuzzer target: the cloud readers (io/cloud_io.h: PCD and PLY through the
// header checks and PCL, XYZ, LAS). The first byte picks the format, the rest is
// the file. A reader may refuse the bytes with InputError; anything else (a crash,
// a sanitizer report, another exception, a leak) is a finding. scripts/fuzz.sh.

#include "uavip/core/error.h"
#include "uavip/io/cloud_io.h"

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const kExtensions[] = {".pcd", ".ply", ".xyz", ".las"};
  static const std::string base = "/tmp/uavip_fuzz_cloud_" + std::to_string(::getpid());
  const std::string path = base + kExtensions[data[0] % 4];
  {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  try {
    const uavip::PointList points = uavip::io::loadCloud(path);
    for (const auto& p : points) {
      if (!p.allFinite()) __builtin_trap();  // the readers promise finite points
    }
  } catch (const uavip::InputError&) {
  }
  std::remove(path.c_str());
  return 0;
}
