#pragma once
/// \file
/// Process-wide memory settings for the programs (the CLI, the benchmarks): the
/// allocator's, and the memory budget every large allocation is checked against
/// before it is made (requireMemory), so an input too large for the machine is
/// refused at once with the value to change instead of swapping or dying late.

#include <string>

namespace uavip {

/// Keeps freed heap memory in the process for the next allocation. By default glibc
/// serves every block above a (dynamic, 128 kB–32 MB) threshold with its own mmap and
/// unmaps it on free, so the next cloud-sized vector faults every page in again
/// (what that cost: docs/architecture_notes.md, "Figures behind the code"). Raises the
/// mmap threshold to its maximum (32 MB) and never trims the heap. Freed memory is also
/// reused across threads: at most one malloc arena per hardware thread (glibc's default
/// is 8 per core, each keeping what its threads freed; plan-section of the 4 km
/// viaduct's largest section peaked at 1,033 MiB with the default, 979 MiB with 2
/// arenas on 2 cores). Call once at start, before any thread; a no-op off glibc.
/// Transparent huge pages (`GLIBC_TUNABLES=glibc.malloc.hugetlb=1` in the
/// environment; glibc reads it only at start) cut the faults further.
void keepFreedMemoryForReuse();

/// Memory this machine can give the process [bytes]: the lower of /proc/meminfo's
/// MemAvailable and the cgroup's limit (v2 memory.max, v1 memory.limit_in_bytes);
/// 0 when neither can be read.
double availableMemoryBytes();

/// The memory budget [bytes]: set by setMemoryBudget (the CLI's --max-memory), else
/// 80 % of availableMemoryBytes() when first asked (no limit when that is unknown).
double memoryBudgetBytes();

/// Sets the budget [bytes] (> 0). Call before any thread.
void setMemoryBudget(double bytes);

/// Throws InputError "<what> needs about N GB, more than the memory budget of B GB
/// (--max-memory); <how_to_fix>, or raise --max-memory" when `bytes` exceeds the
/// budget. Cheap: call it with an estimate before every allocation that grows with
/// the input, from its extent and counts.
void requireMemory(double bytes, const std::string& what, const std::string& how_to_fix);

/// A size as "4G", "512M", "1.5GB", "800MiB" or plain bytes [bytes]; throws
/// InputError naming `option` for anything else or a size not above 0.
double parseMemorySize(const std::string& text, const std::string& option);

/// A size in bytes as "1.23 GB" / "456 MB" (decimal units).
std::string formatBytes(double bytes);

}  // namespace uavip
