#include "uavip/core/memory.h"

#include <cstdlib>  // defines __GLIBC__ on glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace uavip {

void keepFreedMemoryForReuse() {
#if defined(__GLIBC__)
  // 32 MB: glibc's largest accepted mmap threshold on 64-bit (4 MB · sizeof(long)).
  mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);  // trim only above 1 GiB of free heap top
#endif
}

}  // namespace uavip
