#include "geotex/core/resources.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <dlfcn.h>
#include <fstream>
#include <limits>
#include <string>
#include <sys/resource.h>
#include <unistd.h>

#include <fmt/format.h>

#include "geotex/core/error.h"

namespace geotex {

size_t peak_rss_bytes() {
  rusage u{};
  if (getrusage(RUSAGE_SELF, &u) != 0) return 0;
  return static_cast<size_t>(u.ru_maxrss) * 1024;  // Linux reports KiB
}

double cpu_seconds() {
  rusage u{};
  if (getrusage(RUSAGE_SELF, &u) != 0) return 0;
  auto sec = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return sec(u.ru_utime) + sec(u.ru_stime);
}

std::string format_bytes(size_t bytes) {
  const double b = static_cast<double>(bytes);
  if (b >= 1024.0 * 1024 * 1024) return fmt::format("{:.2f} GiB", b / (1024.0 * 1024 * 1024));
  if (b >= 1024.0 * 1024) return fmt::format("{:.1f} MiB", b / (1024.0 * 1024));
  return fmt::format("{:.0f} KiB", b / 1024.0);
}

namespace {
// The first number after \p key in a text file such as /proc/meminfo ("MemAvailable:  123 kB"), times
// \p unit; 0 if absent.
uint64_t number_after(const char* file, const std::string& key, uint64_t unit) {
  std::ifstream in(file);
  std::string word;
  while (in >> word)
    if (word == key) {
      uint64_t v = 0;
      if (in >> v) return v * unit;
      return 0;
    }
  return 0;
}

// The single number a cgroup v2 file holds ("max" or a byte count); 0 for "max" or when absent.
uint64_t cgroup_value(const char* file) {
  std::ifstream in(file);
  std::string word;
  if (!(in >> word) || word == "max") return 0;
  try {
    return std::stoull(word);
  } catch (const std::exception&) {
    return 0;
  }
}
// GEOTEX_MAX_MEMORY: a cap the user sets ("2G", "500M", "64K" or bytes); 0 when unset or unreadable.
uint64_t user_cap() {
  const char* env = std::getenv("GEOTEX_MAX_MEMORY");
  if (!env || !*env) return 0;
  char* end = nullptr;
  const double v = std::strtod(env, &end);
  if (!(v > 0) || end == env) return 0;
  double unit = 1;
  switch (*end) {
    case 'k': case 'K': unit = 1024.0; break;
    case 'm': case 'M': unit = 1024.0 * 1024; break;
    case 'g': case 'G': unit = 1024.0 * 1024 * 1024; break;
    case 't': case 'T': unit = 1024.0 * 1024 * 1024 * 1024; break;
    default: break;
  }
  const double b = v * unit;
  return b >= 1.8e19 ? 0 : static_cast<uint64_t>(b);
}
}  // namespace

size_t available_memory_bytes() {
  uint64_t avail = std::numeric_limits<uint64_t>::max();
  if (const uint64_t cap = user_cap(); cap > 0) {
    const uint64_t used = number_after("/proc/self/status", "VmRSS:", 1024);
    avail = cap > used ? cap - used : 0;
  }
  if (const uint64_t m = number_after("/proc/meminfo", "MemAvailable:", 1024); m > 0) avail = std::min(avail, m);
  rlimit lim{};
  if (getrlimit(RLIMIT_AS, &lim) == 0 && lim.rlim_cur != RLIM_INFINITY) {
    const uint64_t used = number_after("/proc/self/status", "VmSize:", 1024);
    avail = std::min<uint64_t>(avail, lim.rlim_cur > used ? lim.rlim_cur - used : 0);
  }
  if (const uint64_t max = cgroup_value("/sys/fs/cgroup/memory.max"); max > 0) {
    // The cgroup's use counts its page cache, which the kernel gives back under pressure: a cgroup that
    // has read many files sits near its limit without being short of memory.
    const uint64_t current = cgroup_value("/sys/fs/cgroup/memory.current");
    const uint64_t cache = number_after("/sys/fs/cgroup/memory.stat", "file", 1);
    const uint64_t used = current > cache ? current - cache : 0;
    avail = std::min<uint64_t>(avail, max > used ? max - used : 0);
  }
  return static_cast<size_t>(std::min<uint64_t>(avail, std::numeric_limits<size_t>::max()));
}

namespace {
// OpenBLAS's own entry points, looked up in the process: the executable's libraries (RTLD_DEFAULT), else
// the libraries the Python module loaded privately (RTLD_NOLOAD: only when already loaded).
void* openblas_symbol(const char* name) {
  if (void* f = dlsym(RTLD_DEFAULT, name)) return f;
  for (const char* lib : {"libblas.so.3", "libopenblas.so.0", "libopenblasp.so.0"})
    if (void* h = dlopen(lib, RTLD_LAZY | RTLD_NOLOAD)) {
      void* f = dlsym(h, name);
      dlclose(h);
      if (f) return f;
    }
  return nullptr;
}
}  // namespace

int set_blas_threads(int n) {
  if (std::getenv("OPENBLAS_NUM_THREADS")) return 0;
  static const auto get = reinterpret_cast<int (*)()>(openblas_symbol("openblas_get_num_threads"));
  static const auto set = reinterpret_cast<void (*)(int)>(openblas_symbol("openblas_set_num_threads"));
  if (!get || !set) return 0;
  const int previous = get();
  if (previous != n) set(n);
  return previous;
}

size_t mesh_read_bytes(uint64_t faces, uint64_t vertices) {
  constexpr uint64_t kPerFace = 110, kPerVertex = 135;
  const double bytes = double(faces) * kPerFace + double(vertices) * kPerVertex;
  return bytes >= double(std::numeric_limits<size_t>::max()) ? std::numeric_limits<size_t>::max()
                                                              : static_cast<size_t>(bytes);
}

void require_memory(const std::string& what, size_t bytes) {
  const size_t avail = available_memory_bytes();
  if (bytes <= avail) return;
  throw OutOfMemory(fmt::format("{} needs about {} of memory; {} are available (refused before the work)", what,
                                format_bytes(bytes), format_bytes(avail)));
}

}  // namespace geotex
