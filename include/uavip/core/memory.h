#pragma once
/// \file
/// Process-wide allocator settings for the programs (the CLI, the benchmarks).

namespace uavip {

/// Keeps freed heap memory in the process for the next allocation. By default glibc
/// serves every block above a (dynamic, 128 kB–32 MB) threshold with its own mmap and
/// unmaps it on free, so the next cloud-sized vector faults every page in again
/// (what that cost: docs/architecture_notes.md, "Figures behind the code"). Raises the
/// mmap threshold to its maximum (32 MB) and never trims the heap. Call once at start,
/// before any thread; a no-op off glibc.
/// Transparent huge pages (`GLIBC_TUNABLES=glibc.malloc.hugetlb=1` in the
/// environment; glibc reads it only at start) cut the faults further.
void keepFreedMemoryForReuse();

}  // namespace uavip
