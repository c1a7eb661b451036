#pragma once
//! \file resources.h What the process has used so far (peak resident memory, CPU time; the CLI's
//! `--stats` and the benchmarks) and what it may still take: inputs too large for the machine are
//! refused up front with an estimate (issue 30), not after minutes of reading.

#include <cstddef>
#include <cstdint>
#include <string>

namespace geotex {

//! Peak resident set size of this process so far, in bytes (getrusage's ru_maxrss); 0 if unknown.
size_t peak_rss_bytes();

//! User + system CPU time of this process so far, in seconds.
double cpu_seconds();

//! "1.23 GiB", "45.6 MiB", "789 KiB": a byte count for people.
std::string format_bytes(size_t bytes);

//! Memory this process can still take, in bytes: the least of the machine's available memory
//! (/proc/meminfo MemAvailable), what the address-space limit (RLIMIT_AS) leaves beside the process's
//! current size, what its cgroup's memory.max leaves, and what the environment variable
//! GEOTEX_MAX_MEMORY ("2G", "500M", bytes) leaves beside the resident set; SIZE_MAX when none is known.
size_t available_memory_bytes();

//! Peak memory of reading a mesh of \p faces triangles and \p vertices vertices into a Mesh, beyond the
//! file's own bytes (measured on a 5.2 M-face sphere and a 10^6-face fan in PLY, STL and OBJ:
//! about 110 bytes per face and 135 per vertex; bench/bad-input.md).
size_t mesh_read_bytes(uint64_t faces, uint64_t vertices);

//! Sets the BLAS library's thread count (OpenBLAS, found at run time; a no-op for another BLAS, or when the
//! user set OPENBLAS_NUM_THREADS). OpenBLAS's workers busy-wait (sched_yield) between calls: beside
//! geotex's own OpenMP threads they doubled the CPU time of a resize (the bunny: 20 s -> 8.6 s with one)
//! and slowed every CHOLMOD factorization on a shared machine. The CLI and Python use one.
//! \return the previous count, or 0 when nothing was changed.
int set_blas_threads(int n);

//! Throws OutOfMemory (error.h) naming \p what, the estimate and what is available, when \p bytes
//! exceed available_memory_bytes(): refused in seconds instead of failing after minutes of work.
void require_memory(const std::string& what, size_t bytes);

}  // namespace geotex
