#pragma once
//! \file resources.h What the process has used so far: peak and current resident memory, CPU time.
//! Used by the CLI's `--stats` flag and by benchmarks that report peak memory.

#include <cstddef>
#include <string>

namespace geotex {

//! Peak resident set size of this process so far, in bytes (getrusage's ru_maxrss); 0 if unknown.
size_t peak_rss_bytes();

//! User + system CPU time of this process so far, in seconds.
double cpu_seconds();

//! "1.23 GiB", "45.6 MiB", "789 KiB": a byte count for people.
std::string format_bytes(size_t bytes);

}  // namespace geotex
