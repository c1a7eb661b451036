// Inputs without a name of their own: gzipped files (the inner extension names the format) and
// standard input (the format sniffed from the bytes); the names of the formats for --format.

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/io.h"
#include "geotex/core/progress.h"
#include "io_detail.h"

namespace geotex {

namespace fs = std::filesystem;

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

// The text after a UTF-8 byte order mark and leading blanks.
std::string_view text_start(std::string_view data) {
  if (data.substr(0, 3) == "\xEF\xBB\xBF") data.remove_prefix(3);
  while (!data.empty() && is_blank(data.front())) data.remove_prefix(1);
  return data;
}

std::string human_bytes(uint64_t n) {
  if (n >= (uint64_t(1) << 30)) return fmt::format("{:.0f} GiB", double(n) / double(uint64_t(1) << 30));
  return fmt::format("{:.0f} MiB", double(n) / double(uint64_t(1) << 20));
}

}  // namespace

namespace detail {

bool starts_ascii_stl(std::string_view data) { return text_start(data).substr(0, 5) == "solid"; }

bool is_gzip_magic(std::string_view data) {
  return data.size() >= 2 && static_cast<unsigned char>(data[0]) == 0x1f && static_cast<unsigned char>(data[1]) == 0x8b;
}

StdinBytes read_stdin(size_t max_bytes, const std::function<bool(std::string_view)>& complete) {
  if (::isatty(STDIN_FILENO))
    throw IoError("standard input (-) is a terminal; pipe a mesh into it (geotex generate cube -o - | geotex info -)");
  auto too_large = [&] {
    return IoError(fmt::format("standard input (-): more than {}, the limit for a stream", human_bytes(max_bytes)));
  };
  StdinBytes out;
  std::string& data = out.data;
  std::vector<char> chunk(1 << 16);
  auto read_some = [&](size_t len) -> size_t {
    for (;;) {
      const ssize_t n = ::read(STDIN_FILENO, chunk.data(), len);
      if (n >= 0) return static_cast<size_t>(n);
      if (errno == EINTR) {
        check_interrupt();
        continue;
      }
      if (errno == EAGAIN) return SIZE_MAX;  // a non-blocking pipe with nothing yet: wait in poll()
      throw IoError(fmt::format("standard input (-): read failed ({})", std::strerror(errno)));
    }
  };
  // `< FILE`: the file as large as it was now (a file another process appends to is a snapshot, as
  // read_regular_file() reads files by name).
  struct stat st {};
  if (::fstat(STDIN_FILENO, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0) {
    const off_t at = ::lseek(STDIN_FILENO, 0, SEEK_CUR);
    const uint64_t left = static_cast<uint64_t>(st.st_size) - static_cast<uint64_t>(std::max<off_t>(at, 0));
    if (left > max_bytes) throw too_large();
    while (data.size() < left) {
      const size_t n = read_some(std::min<size_t>(chunk.size(), left - data.size()));
      if (n == 0 || n == SIZE_MAX) break;
      data.append(chunk.data(), n);
    }
    return out;
  }
  // A pipe: whether the bytes hold a whole mesh is asked when they have doubled since the last answer
  // (the parses cost at most twice one parse of everything) and when the writer pauses for 100 ms (tail -f).
  size_t checked = 0, next_check = size_t(1) << 16;
  auto whole = [&] {
    if (!complete || data.size() == checked) return false;
    checked = data.size();
    next_check = 2 * data.size();
    return complete(data);
  };
  for (;;) {
    pollfd p{STDIN_FILENO, POLLIN, 0};
    const int ready = ::poll(&p, 1, 100);
    if (ready < 0 && errno != EINTR) throw IoError(fmt::format("standard input (-): poll failed ({})", std::strerror(errno)));
    check_interrupt();
    if (ready <= 0 && !whole()) continue;  // nothing for 100 ms, and not a whole mesh yet
    if (ready <= 0) break;
    const size_t n = read_some(chunk.size());
    if (n == SIZE_MAX) continue;
    if (n == 0) return out;
    if (data.size() + n > max_bytes) {
      if (whole()) break;
      throw too_large();
    }
    data.append(chunk.data(), n);
    if (data.size() >= next_check && whole()) break;
  }
  out.stopped_early = true;  // the loop ends here only when the bytes so far hold a whole mesh
  return out;
}

}  // namespace detail

bool is_gzip_path(const fs::path& path) { return lower(path.extension().string()) == ".gz"; }

std::string format_name(MeshFormat format) {
  switch (format) {
    case MeshFormat::Obj: return "obj";
    case MeshFormat::Ply: return "ply";
    case MeshFormat::Off: return "off";
    case MeshFormat::Stl: return "stl";
    case MeshFormat::Gltf: return "gltf";
    case MeshFormat::Glb: return "glb";
  }
  return "?";
}

MeshFormat format_from_name(const std::string& name) {
  const std::string n = lower(name);
  for (MeshFormat f : {MeshFormat::Ply, MeshFormat::Obj, MeshFormat::Off, MeshFormat::Stl, MeshFormat::Gltf,
                       MeshFormat::Glb})
    if (format_name(f) == n) return f;
  throw InvalidInput(fmt::format("unknown mesh format '{}' (use ply, obj, off, stl, gltf or glb)", name));
}

MeshFormat sniff_format(std::string_view data) {
  if (data.substr(0, 4) == "glTF") return MeshFormat::Glb;
  // A binary STL has no magic; its size is its signature (an ascii STL with that size is rare, and
  // the binary reader would then refuse it as a whole).
  if (data.size() >= 84) {
    uint32_t n;
    std::memcpy(&n, data.data() + 80, 4);
    if (84ull + 50ull * n == data.size() && !detail::starts_ascii_stl(data)) return MeshFormat::Stl;
  }
  const std::string_view text = text_start(data);
  auto first_word = [&] {
    size_t end = 0;
    while (end < text.size() && !is_blank(text[end])) ++end;
    return text.substr(0, end);
  };
  const std::string_view word = first_word();
  if (word == "ply") return MeshFormat::Ply;
  if (word.size() >= 3 && word.size() <= 6 && word.substr(word.size() - 3) == "OFF") return MeshFormat::Off;
  if (!text.empty() && text.front() == '{') return MeshFormat::Gltf;
  if (word == "solid") return MeshFormat::Stl;
  return MeshFormat::Obj;  // OBJ has no header; its reader names what does not fit

}

std::string gunzip(std::string_view data, const std::string& name, size_t max_bytes) {
  const bool zlib_header = data.size() >= 2 && (static_cast<unsigned char>(data[0]) & 0x0f) == 8 &&
                           ((static_cast<unsigned char>(data[0]) << 8) | static_cast<unsigned char>(data[1])) % 31 == 0;
  if (!detail::is_gzip_magic(data) && !zlib_header)
    throw IoError(fmt::format("{}: not gzip data (it does not start with the gzip bytes 1f 8b)", name));
  z_stream z{};
  // 15 + 32: a gzip or a zlib header, detected.
  if (inflateInit2(&z, 15 + 32) != Z_OK) throw IoError(fmt::format("{}: cannot start gzip decompression", name));
  struct End {
    z_stream* z;
    ~End() { inflateEnd(z); }
  } end{&z};
  std::string out;
  std::vector<char> chunk(1 << 18);
  size_t pos = 0;
  for (;;) {
    // zlib counts in uInt: feed the input in pieces of at most 1 GiB.
    const size_t piece = std::min<size_t>(data.size() - pos, size_t(1) << 30);
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data() + pos));
    z.avail_in = static_cast<uInt>(piece);
    int rc = Z_OK;
    do {
      z.next_out = reinterpret_cast<Bytef*>(chunk.data());
      z.avail_out = static_cast<uInt>(chunk.size());
      rc = inflate(&z, Z_NO_FLUSH);
      if (rc == Z_DATA_ERROR || rc == Z_NEED_DICT || rc == Z_STREAM_ERROR)
        throw IoError(fmt::format("{}: corrupt gzip data ({}) after {} compressed bytes", name,
                                  z.msg ? z.msg : "invalid data", pos + piece - z.avail_in));
      if (rc == Z_MEM_ERROR) throw IoError(fmt::format("{}: out of memory while decompressing", name));
      const size_t produced = chunk.size() - z.avail_out;
      if (out.size() + produced > max_bytes)
        throw IoError(fmt::format("{}: decompresses to more than {}, the limit for a gzipped mesh", name,
                                  human_bytes(max_bytes)));
      out.append(chunk.data(), produced);
    } while (rc != Z_STREAM_END && (z.avail_out == 0 || z.avail_in > 0) && rc != Z_BUF_ERROR);
    pos += piece - z.avail_in;
    if (rc == Z_STREAM_END) {
      // gzip allows several members one after the other (cat a.gz b.gz); zeros are padding.
      if (detail::is_gzip_magic(data.substr(pos))) {
        inflateReset(&z);
        continue;
      }
      const std::string_view rest = data.substr(pos);
      if (std::any_of(rest.begin(), rest.end(), [](char c) { return c != '\0'; }))
        throw IoError(fmt::format("{}: {} bytes after the end of the gzip data (not gzip)", name, rest.size()));
      return out;
    }
    if (pos >= data.size())
      throw IoError(fmt::format("{}: truncated gzip data (it ends after {} compressed bytes, {} decompressed, "
                                "before the end of its stream)", name, data.size(), out.size()));
  }
}

}  // namespace geotex
