#pragma once
/// \file
/// Process-wide allocator settings for the programs (the CLI, the benchmarks).

namespace uavip {

/// Keeps freed heap memory in the process for the next allocation. By default glibc
/// serves every block above a (dynamic, 128 kB–32 MB) threshold with its own mmap and
/// unmaps it on free, so the next cloud-sized vector faults every page in again; on
/// the 2-core VMs this project is measured on a page fault costs about 12 µs (a
/// 36 MB copy of 1.5 M points spent 0.11 s faulting), and stages 1–2 of the bridge
/// spent 0.3 s of 1.4 s so. Raises the mmap threshold to its maximum (32 MB) and
/// never trims the heap: stages 1–2 of `uavip assemble` on the bridge 1.4–1.6 -> 1.2 s,
/// peak memory +3 %. Call once at start, before any thread; a no-op off glibc.
/// Transparent huge pages (`GLIBC_TUNABLES=glibc.malloc.hugetlb=1` in the
/// environment; glibc reads it only at start) cut the faults further.
void keepFreedMemoryForReuse();

}  // namespace uavip
