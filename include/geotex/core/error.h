#pragma once
//! \file error.h Typed errors. Every geotex function reports failure by throwing one of these;
//! the CLI turns them into one line on stderr and a non-zero exit code.

#include <stdexcept>
#include <string>
#include <string_view>

namespace geotex {

namespace detail {
//! \p message with each NUL byte written as `\x00`: what() is a C string, so a NUL from a file's
//! bytes (quoted in a message) would cut the line there and hide the cause.
inline std::string without_nul(std::string_view message) {
  std::string out;
  out.reserve(message.size());
  for (const char c : message) {
    if (c == '\0') out += "\\x00";
    else out += c;
  }
  return out;
}

//! \p v as a message shows a number read from a file: an integral value (an index stored as a float or
//! double) as its exact integer, 18446744073709551616 rather than 1.8446744073709552e+19; others shortest.
std::string exact_number(double v);
}  // namespace detail

//! Base of every geotex error.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(detail::without_nul(message)) {}
  explicit Error(const char* message) : std::runtime_error(message) {}
};

//! The caller's data or parameters cannot be used (empty mesh, NaN coordinates, not a disk, …).
class InvalidInput : public Error {
 public:
  using Error::Error;
};

//! A file could not be read or written (missing, unreadable, malformed, truncated, …).
class IoError : public Error {
 public:
  using Error::Error;
};

//! The work needs more memory than the machine has left (an estimate made before the work, or an
//! allocation that failed). Python: a MemoryError.
class OutOfMemory : public Error {
 public:
  using Error::Error;
};

//! A numerical solve failed (matrix not positive definite, no convergence, …).
class SolverError : public Error {
 public:
  using Error::Error;
};

}  // namespace geotex
