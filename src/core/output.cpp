// The output discipline (output.h): checked targets, temporaries beside them, all-or-nothing commit,
// temporaries removed on SIGINT/SIGTERM/SIGHUP. POSIX/Linux calls throughout: the rules are about
// inodes, modes and signals, which std::filesystem does not expose.

#include "geotex/core/output.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <mutex>
#include <random>

#include <fmt/format.h>

#include "geotex/core/error.h"

namespace geotex {

namespace fs = std::filesystem;

namespace {

std::string errno_text(int e) { return std::strerror(e); }

// ---------------------------------------------------------------------------------------------
// Named temporaries, for the signal handler: a static table it can walk without allocating.
// A slot is free (0), being filled (1) or live (2); the handler unlinks the live ones.

struct TempSlot {
  std::atomic<int> state{0};
  int dirfd = -1;
  char name[24] = {};
};
constexpr size_t kSlots = 256;
TempSlot g_slots[kSlots];

// Returns the slot index, or -1 if the table is full (the temporary is then only removed by its
// owner, not by a signal).
int register_temporary(int dirfd, const char* name) {
  for (size_t i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (!g_slots[i].state.compare_exchange_strong(expected, 1)) continue;
    g_slots[i].dirfd = dirfd;
    std::snprintf(g_slots[i].name, sizeof(g_slots[i].name), "%s", name);
    g_slots[i].state.store(2, std::memory_order_release);
    return static_cast<int>(i);
  }
  return -1;
}

void unregister_temporary(int slot) {
  if (slot >= 0) g_slots[slot].state.store(0, std::memory_order_release);
}

extern "C" void geotex_remove_temporaries_on_signal(int sig) {
  for (auto& s : g_slots)
    if (s.state.load(std::memory_order_acquire) == 2) ::unlinkat(s.dirfd, s.name, 0);
  // SA_RESETHAND restored the default action; the signal is blocked until this handler returns,
  // then it takes effect (terminates the process as it would have without us).
  ::raise(sig);
}

void install_signal_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
      struct sigaction old {};
      if (::sigaction(sig, nullptr, &old) != 0) continue;
      if ((old.sa_flags & SA_SIGINFO) || old.sa_handler != SIG_DFL) continue;  // the program's choice
      struct sigaction sa {};
      sa.sa_handler = geotex_remove_temporaries_on_signal;
      sigemptyset(&sa.sa_mask);
      sa.sa_flags = SA_RESETHAND;
      ::sigaction(sig, &sa, nullptr);
    }
  });
}

std::atomic<bool> g_named_temporaries{false};

mode_t current_umask() {
  // /proc/self/status has it without the race of umask(umask(0)) (Linux ≥ 4.7).
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("Umask:", 0) == 0) return static_cast<mode_t>(std::stoul(line.substr(6), nullptr, 8));
  const mode_t m = ::umask(022);
  ::umask(m);
  return m;
}

// A short temporary name in the target's folder: never longer than any name the folder allows.
std::string random_temp_name() {
  static thread_local std::mt19937_64 rng(std::random_device{}() ^ static_cast<uint64_t>(::getpid()));
  static const char* alphabet = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
  std::string s = ".geotex-";
  for (int i = 0; i < 6; ++i) s += alphabet[rng() % 62];
  return s;
}

const char* kind_of(mode_t m) {
  if (S_ISDIR(m)) return "a directory";
  if (S_ISFIFO(m)) return "a FIFO (named pipe)";
  if (S_ISSOCK(m)) return "a socket";
  if (S_ISCHR(m) || S_ISBLK(m)) return "a device";
  if (S_ISLNK(m)) return "a symbolic link";
  return "not a regular file";
}

// ---------------------------------------------------------------------------------------------
// Resolving and checking a target.

struct FileId {
  dev_t dev = 0;
  ino_t ino = 0;
  bool operator==(const FileId& o) const { return dev == o.dev && ino == o.ino; }
};

// Where an output goes: the end of the symbolic-link chain at the given path.
struct Target {
  fs::path given;        // as the caller wrote it
  fs::path file;         // the end of the link chain (the file that is replaced)
  std::string name;      // its last component
  int dirfd = -1;        // its folder (O_PATH)
  FileId dir;            // the folder's identity
  bool exists = false;
  struct stat st {};     // the existing file's, when it exists

  Target() = default;
  Target(const Target&) = delete;
  Target& operator=(const Target&) = delete;
  Target(Target&& o) noexcept { *this = std::move(o); }
  Target& operator=(Target&& o) noexcept {
    std::swap(given, o.given);
    std::swap(file, o.file);
    std::swap(name, o.name);
    std::swap(dirfd, o.dirfd);
    std::swap(dir, o.dir);
    std::swap(exists, o.exists);
    std::swap(st, o.st);
    return *this;
  }
  ~Target() {
    if (dirfd >= 0) ::close(dirfd);
  }
  // The slot this output occupies: the same folder and name means the same output.
  bool same_place(const Target& o) const { return dir == o.dir && name == o.name; }
  FileId id() const { return {st.st_dev, st.st_ino}; }
};

[[noreturn]] void refuse(const std::string& what, const fs::path& path, const std::string& why) {
  throw IoError(what.empty() || what == "output" ? fmt::format("{}: {}", path.string(), why)
                                                 : fmt::format("{} {}: {}", what, path.string(), why));
}

// Follow the symbolic links at \p path (a dangling one is fine: its target will be created).
fs::path end_of_links(const fs::path& path, const std::string& what) {
  fs::path cur = path;
  for (int hop = 0; hop < 40; ++hop) {
    struct stat st {};
    if (::lstat(cur.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return cur;
    std::error_code ec;
    const fs::path to = fs::read_symlink(cur, ec);
    if (ec) refuse(what, path, fmt::format("cannot read the symbolic link {} ({})", cur.string(), ec.message()));
    cur = to.is_absolute() ? to : cur.parent_path() / to;
  }
  refuse(what, path, "too many levels of symbolic links");
}

// Resolve and check an output path (the rules of output.h). Opens its folder.
Target check_output(const fs::path& path, const std::string& what) {
  if (path.empty()) throw IoError(what.empty() ? "empty output path" : fmt::format("{}: empty output path", what));
  Target t;
  t.given = path;
  t.file = end_of_links(path, what);
  t.name = t.file.filename().string();
  if (t.name.empty() || t.name == "." || t.name == "..") refuse(what, path, "names a folder, not a file");
  const fs::path dir = t.file.has_parent_path() ? t.file.parent_path() : fs::path(".");
  t.dirfd = ::open(dir.c_str(), O_PATH | O_DIRECTORY | O_CLOEXEC);
  if (t.dirfd < 0) {
    const int e = errno;
    if (e == ENOENT) refuse(what, path, fmt::format("folder {} does not exist", dir.string()));
    if (e == ENOTDIR) refuse(what, path, fmt::format("{} is not a folder", dir.string()));
    refuse(what, path, fmt::format("cannot open folder {} ({})", dir.string(), errno_text(e)));
  }
  struct stat dst {};
  if (::fstat(t.dirfd, &dst) != 0) refuse(what, path, fmt::format("cannot stat folder {}", dir.string()));
  t.dir = {dst.st_dev, dst.st_ino};
  const long name_max = ::fpathconf(t.dirfd, _PC_NAME_MAX);
  const size_t limit = name_max > 0 ? static_cast<size_t>(name_max) : NAME_MAX;
  if (t.name.size() > limit)
    refuse(what, path, fmt::format("the file name is {} bytes long; the folder allows at most {}", t.name.size(), limit));
  if (::fstatat(t.dirfd, t.name.c_str(), &t.st, AT_SYMLINK_NOFOLLOW) == 0) {
    t.exists = true;
    if (!S_ISREG(t.st.st_mode))
      refuse(what, path, fmt::format("is {}; geotex writes only regular files", kind_of(t.st.st_mode)));
    // No write bit at all, or none for us: the owner meant it to stay (root passes access(2) anyway).
    if ((t.st.st_mode & 0222) == 0 || ::faccessat(t.dirfd, t.name.c_str(), W_OK, AT_EACCESS) != 0)
      refuse(what, path, "is read-only; geotex does not replace it");
  } else if (errno != ENOENT) {
    refuse(what, path, fmt::format("cannot stat ({})", errno_text(errno)));
  }
  if (::faccessat(t.dirfd, ".", W_OK | X_OK, AT_EACCESS) != 0)
    refuse(what, path, fmt::format("cannot write in folder {} ({})", dir.string(), errno_text(errno)));
  return t;
}

// ---------------------------------------------------------------------------------------------
// One output: its target and its temporary.

struct Output {
  Target target;
  std::string what;
  int fd = -1;              // the temporary (O_TMPFILE: unnamed; else named tmp_name)
  std::string tmp_name;     // empty for an unnamed temporary
  int slot = -1;            // in the signal table while named
  bool written = false;

  Output() = default;
  Output(const Output&) = delete;
  Output(Output&& o) noexcept
      : target(std::move(o.target)), what(std::move(o.what)), fd(o.fd), tmp_name(std::move(o.tmp_name)),
        slot(o.slot), written(o.written) {
    o.fd = -1;
    o.slot = -1;
    o.tmp_name.clear();
  }
  ~Output() { discard(); }

  void discard() {
    if (!tmp_name.empty()) ::unlinkat(target.dirfd, tmp_name.c_str(), 0);
    unregister_temporary(slot);
    slot = -1;
    tmp_name.clear();
    if (fd >= 0) ::close(fd);
    fd = -1;
  }

  void open_temporary(bool named) {
    if (!named) {
      fd = ::openat(target.dirfd, ".", O_TMPFILE | O_RDWR | O_CLOEXEC, 0666);
      if (fd >= 0) return;
      // EOPNOTSUPP/EISDIR/EINVAL: the file system has no O_TMPFILE; use a named temporary.
    }
    for (int attempt = 0; attempt < 100; ++attempt) {
      const std::string name = random_temp_name();
      fd = ::openat(target.dirfd, name.c_str(), O_CREAT | O_EXCL | O_RDWR | O_CLOEXEC, 0600);
      if (fd >= 0) {
        tmp_name = name;
        slot = register_temporary(target.dirfd, name.c_str());
        // mkstemp-style files are 0600; a new output gets what open(2) would have given it.
        ::fchmod(fd, 0666 & ~current_umask());
        return;
      }
      if (errno != EEXIST) break;
    }
    refuse(what, target.given, fmt::format("cannot create a temporary file in its folder ({})", errno_text(errno)));
  }

  void write(std::string_view bytes) {
    if (fd < 0) open_temporary(g_named_temporaries.load());
    else if (::ftruncate(fd, 0) != 0 || ::lseek(fd, 0, SEEK_SET) != 0)
      refuse(what, target.given, fmt::format("cannot rewrite the temporary file ({})", errno_text(errno)));
    written = false;
    size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        const int e = n < 0 ? errno : ENOSPC;
        discard();
        refuse(what, target.given, fmt::format("write failed ({})", errno_text(e)));
      }
      done += static_cast<size_t>(n);
    }
    written = true;
  }

  // The target may have changed since it was declared: check it again (no rename yet).
  void recheck() {
    Target now = check_output(target.given, what);
    if (!now.same_place(target)) refuse(what, target.given, "changed during the run (its link points elsewhere now)");
    target.exists = now.exists;
    target.st = now.st;
  }

  // Give the temporary the target's name. Mode (and owner, where allowed) of a replaced file are kept.
  void put_in_place() {
    if (target.exists) {
      ::fchmod(fd, target.st.st_mode & 07777 & ~(S_ISUID | S_ISGID));
      if (target.st.st_uid != ::geteuid() || target.st.st_gid != ::getegid()) {
        if (::fchown(fd, target.st.st_uid, target.st.st_gid) != 0) {
          // Not allowed (not root): the file becomes ours, with the old permission bits.
        }
      }
    }
    const char* name = target.name.c_str();
    if (tmp_name.empty()) {  // unnamed: link it in, directly when nothing is there yet
      const std::string proc = fmt::format("/proc/self/fd/{}", fd);
      if (!target.exists && ::linkat(AT_FDCWD, proc.c_str(), target.dirfd, name, AT_SYMLINK_FOLLOW) == 0) return;
      for (int attempt = 0; attempt < 100 && tmp_name.empty(); ++attempt) {
        const std::string t = random_temp_name();
        if (::linkat(AT_FDCWD, proc.c_str(), target.dirfd, t.c_str(), AT_SYMLINK_FOLLOW) == 0) {
          tmp_name = t;
          slot = register_temporary(target.dirfd, t.c_str());
        } else if (errno != EEXIST) {
          break;
        }
      }
      if (tmp_name.empty()) copy_to_named();
    }
    if (::renameat(target.dirfd, tmp_name.c_str(), target.dirfd, name) != 0)
      refuse(what, target.given, fmt::format("cannot move the written file into place ({})", errno_text(errno)));
    unregister_temporary(slot);
    slot = -1;
    tmp_name.clear();
  }

  // Without /proc an unnamed temporary cannot be linked: copy it to a named one.
  void copy_to_named() {
    const int unnamed = fd;
    fd = -1;
    const mode_t mode = target.exists ? (target.st.st_mode & 0777) : (0666 & ~current_umask());
    try {
      open_temporary(true);
    } catch (...) {
      ::close(unnamed);
      throw;
    }
    ::fchmod(fd, mode);
    char buf[1 << 16];
    off_t off = 0;
    for (;;) {
      const ssize_t n = ::pread(unnamed, buf, sizeof(buf), off);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) {
        ::close(unnamed);
        refuse(what, target.given, fmt::format("cannot read the temporary file back ({})", errno_text(errno)));
      }
      if (n == 0) break;
      for (ssize_t done = 0; done < n;) {
        const ssize_t w = ::write(fd, buf + done, static_cast<size_t>(n - done));
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) {
          ::close(unnamed);
          refuse(what, target.given, fmt::format("write failed ({})", errno_text(w < 0 ? errno : ENOSPC)));
        }
        done += w;
      }
      off += n;
    }
    ::close(unnamed);
  }
};

thread_local OutputTransaction* t_active = nullptr;

struct InputFile {
  fs::path path;
  bool exists = false;
  FileId id;             // the file's (a hard or symbolic link to it has the same)
  bool placed = false;   // folder + name known (for a path that does not exist yet)
  FileId dir;
  std::string name;
};

InputFile describe_input(const fs::path& path) {
  InputFile in;
  in.path = path;
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {
    in.exists = true;
    in.id = {st.st_dev, st.st_ino};
    return in;
  }
  const fs::path file = end_of_links(path, "input");
  const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
  if (::stat(dir.c_str(), &st) == 0) {
    in.placed = true;
    in.dir = {st.st_dev, st.st_ino};
    in.name = file.filename().string();
  }
  return in;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

// Standard output (the path "-"): written whole, after a command's files are in place.
static void write_stdout(std::string_view bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(STDOUT_FILENO, bytes.data() + done, bytes.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw IoError(fmt::format("standard output (-): write failed ({})", errno_text(errno)));
    }
    done += static_cast<size_t>(n);
  }
}

static bool is_stdout(const fs::path& path) { return path == "-"; }

struct OutputTransaction::Impl {
  std::vector<Output> outputs;
  std::vector<InputFile> inputs;
  bool done = false;
  std::string stdout_what;     // non-empty: standard output is declared (by this flag)
  bool stdout_written = false;
  std::string stdout_bytes;

  void check_against_inputs(const Output& o, const InputFile& in) const {
    const Target& t = o.target;
    const bool same = (t.exists && in.exists && t.id() == in.id) ||
                      (!t.exists && !in.exists && in.placed && t.dir == in.dir && t.name == in.name);
    if (!same) return;
    std::error_code ec;
    const bool literally = fs::absolute(t.given, ec).lexically_normal() == fs::absolute(in.path, ec).lexically_normal();
    refuse(o.what, t.given, literally ? "is also an input of this command; write the result to another file"
                                      : fmt::format("is the same file as the input {} (a link to it); write the "
                                                    "result to another file", in.path.string()));
  }

  Output* find(const fs::path& path) {
    // Resolve the written path like a declared one and compare the places.
    Target t;
    try {
      t = check_output(path, "");
    } catch (const IoError&) {
      return nullptr;
    }
    for (auto& o : outputs)
      if (o.target.same_place(t)) return &o;
    return nullptr;
  }
};

OutputTransaction::OutputTransaction() : impl_(std::make_unique<Impl>()), previous_(t_active) {
  install_signal_handlers();
  t_active = this;
}

OutputTransaction::~OutputTransaction() {
  if (t_active == this) t_active = previous_;
  // ~Output removes each temporary.
}

OutputTransaction* OutputTransaction::active() { return t_active; }

void OutputTransaction::declare_input(const fs::path& path) {
  if (impl_->done) throw IoError("declare_input() after commit()");
  if (is_stdout(path)) return;  // standard input: no file an output could be
  InputFile in = describe_input(path);
  for (const auto& o : impl_->outputs) impl_->check_against_inputs(o, in);
  impl_->inputs.push_back(std::move(in));
}

void OutputTransaction::declare(const fs::path& path, const std::string& what) {
  if (impl_->done) throw IoError("declare() after commit()");
  if (is_stdout(path)) {
    if (!impl_->stdout_what.empty())
      refuse(what, path, fmt::format("is standard output, as {} is; one output can go there", impl_->stdout_what));
    impl_->stdout_what = what.empty() ? "output" : what;
    return;
  }
  Output o;
  o.what = what;
  o.target = check_output(path, what);
  for (const auto& in : impl_->inputs) impl_->check_against_inputs(o, in);
  for (const auto& other : impl_->outputs) {
    const bool same = other.target.same_place(o.target) ||
                      (other.target.exists && o.target.exists && other.target.id() == o.target.id());
    if (same)
      refuse(what, path, fmt::format("is the same file as {} {}; each output needs its own file", other.what,
                                     other.target.given.string()));
  }
  impl_->outputs.push_back(std::move(o));
}

bool OutputTransaction::is_declared(const fs::path& path) const {
  if (is_stdout(path)) return !impl_->stdout_what.empty();
  return impl_->find(path) != nullptr;
}

void OutputTransaction::commit() {
  if (impl_->done) throw IoError("commit() called twice");
  std::vector<std::string> missing;
  for (const auto& o : impl_->outputs)
    if (!o.written) missing.push_back(fmt::format("{} {}", o.what, o.target.given.string()));
  if (!impl_->stdout_what.empty() && !impl_->stdout_written) missing.push_back(impl_->stdout_what + " -");
  if (!missing.empty())
    throw IoError(fmt::format("declared but never written: {} (nothing was replaced)", fmt::join(missing, ", ")));
  for (auto& o : impl_->outputs) o.recheck();
  std::vector<std::string> placed;
  for (auto& o : impl_->outputs) {
    try {
      o.put_in_place();
    } catch (const IoError& e) {
      if (placed.empty()) throw;
      throw IoError(fmt::format("{} (already replaced: {})", e.what(), fmt::join(placed, ", ")));
    }
    placed.push_back(o.target.given.string());
    o.discard();
  }
  // Standard output last: a pipe reader sees a result only when every file is in place.
  if (impl_->stdout_written) write_stdout(impl_->stdout_bytes);
  impl_->done = true;
  if (t_active == this) t_active = previous_;
}

void write_file_atomic(const fs::path& path, std::string_view bytes) {
  install_signal_handlers();
  if (OutputTransaction* tx = OutputTransaction::active()) {
    if (is_stdout(path)) {
      if (tx->impl_->stdout_what.empty())
        throw IoError("standard output (-): not declared as an output (internal error: every output of a command "
                      "is declared before its work starts)");
      if (tx->impl_->stdout_written) throw IoError("standard output (-): written twice");
      tx->impl_->stdout_bytes.assign(bytes);
      tx->impl_->stdout_written = true;
      return;
    }
    Output* o = tx->impl_->find(path);
    if (!o) {
      (void)check_output(path, "");  // the path's own problem first, if it has one
      throw IoError(fmt::format("{}: not declared as an output (internal error: every output of a command is "
                                "declared before its work starts)", path.string()));
    }
    o->write(bytes);
    return;
  }
  if (is_stdout(path)) return write_stdout(bytes);
  Output o;
  o.what = "output";
  o.target = check_output(path, o.what);
  o.write(bytes);
  o.put_in_place();
}

namespace detail {
bool use_named_temporaries(bool named) { return g_named_temporaries.exchange(named); }
}  // namespace detail

}  // namespace geotex
