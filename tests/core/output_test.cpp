// The output discipline (core/output.h): outputs checked before any work, written all together or
// not at all, modes and links kept, special files refused, temporaries removed on signals.

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/core/output.h"
#include "geotex/tools/shapes.h"
#include "test_util.h"

using namespace geotex;
using geotex::test::read_file;
using geotex::test::TempDir;
using geotex::test::write_file;
namespace fs = std::filesystem;

namespace {

// The names in a folder (hidden ones included: a temporary left behind shows here).
std::set<std::string> listing(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

mode_t mode_of(const std::string& path) {
  struct stat st {};
  EXPECT_EQ(::stat(path.c_str(), &st), 0) << path;
  return st.st_mode & 07777;
}

// A message check: the error names the path and says why.
template <class E, class F>
::testing::AssertionResult throws_with(F&& f, const std::string& needle) {
  try {
    f();
  } catch (const E& e) {
    if (std::string(e.what()).find(needle) == std::string::npos)
      return ::testing::AssertionFailure() << "message without '" << needle << "': " << e.what();
    return ::testing::AssertionSuccess();
  } catch (const std::exception& e) {
    return ::testing::AssertionFailure() << "other exception: " << e.what();
  }
  return ::testing::AssertionFailure() << "no exception";
}

Mesh nan_mesh() {
  Mesh m = icosphere(0);
  m.point(m.vertex_handle(3))[1] = std::numeric_limits<double>::quiet_NaN();
  return m;
}

// Restores the named-temporaries setting at scope exit.
struct NamedTemporaries {
  bool old;
  explicit NamedTemporaries(bool on) : old(detail::use_named_temporaries(on)) {}
  ~NamedTemporaries() { detail::use_named_temporaries(old); }
};

}  // namespace

TEST(Output, DeclareRefusesUnusableTargetsAtOnce) {
  TempDir tmp;
  OutputTransaction tx;
  EXPECT_TRUE(throws_with<IoError>([&] { tx.declare(tmp / "missing/out.obj", "-o"); }, "does not exist"));
  EXPECT_TRUE(throws_with<IoError>([&] { tx.declare(tmp.path, "-o"); }, "is a directory"));
  EXPECT_TRUE(throws_with<IoError>([&] { tx.declare(tmp / "sub/", "-o"); }, "folder"));
  // A device: a node of our own (never /dev/null itself: a regression, or today's main run as root,
  // would rename a regular file over it). Creating one needs root; a link to /dev/null is safe.
  const std::string dev = tmp / "null.obj";
  if (::mknod(dev.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0) fs::create_symlink("/dev/null", dev);
  EXPECT_TRUE(throws_with<IoError>([&] { tx.declare(dev, "--report"); }, "a device"));
  // A FIFO is refused without being opened: opening it for writing would block without a reader.
  ASSERT_EQ(::mkfifo((tmp / "fifo.obj").c_str(), 0644), 0);
  EXPECT_TRUE(throws_with<IoError>([&] { tx.declare(tmp / "fifo.obj", "-o"); }, "FIFO"));
  // A socket.
  const int s = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  const std::string sock = tmp / "sock.obj";
  ASSERT_LT(sock.size(), sizeof(addr.sun_path));
  std::snprintf(addr.sun_path, sizeof(addr.sun_path), "%s", sock.c_str());
  ASSERT_EQ(::bind(s, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)), 0);
  EXPECT_TRUE(throws_with<IoError>([&] { tx.declare(sock, "-o"); }, "socket"));
  ::close(s);
  // A read-only file is kept, whoever runs geotex (root passes access(2), so the mode bits decide).
  write_file(tmp / "ro.obj", "keep");
  ::chmod((tmp / "ro.obj").c_str(), 0444);
  EXPECT_TRUE(throws_with<IoError>([&] { tx.declare(tmp / "ro.obj", "-o"); }, "is read-only; geotex does not replace it"));
  // A name longer than the folder allows.
  EXPECT_TRUE(throws_with<IoError>([&] { tx.declare(tmp / (std::string(256, 'n') + ".obj"), "-o"); }, "bytes long"));
  // The error names the flag.
  EXPECT_TRUE(throws_with<IoError>([&] { tx.declare(tmp / "missing/e.ply", "--edges"); }, "--edges"));
  EXPECT_EQ(read_file(tmp / "ro.obj"), "keep");
}

TEST(Output, WritesOutsideATransactionFollowTheSameRules) {
  TempDir tmp;
  const Mesh m = icosphere(0);
  ASSERT_EQ(::mkfifo((tmp / "fifo.obj").c_str(), 0644), 0);
  EXPECT_TRUE(throws_with<IoError>([&] { write_mesh(m, tmp / "fifo.obj"); }, "FIFO"));  // no block
  write_file(tmp / "ro.obj", "keep");
  ::chmod((tmp / "ro.obj").c_str(), 0444);
  EXPECT_TRUE(throws_with<IoError>([&] { write_mesh(m, tmp / "ro.obj"); }, "read-only"));
  EXPECT_EQ(read_file(tmp / "ro.obj"), "keep");
  const std::string dev = tmp / "null.txt";  // see DeclareRefusesUnusableTargetsAtOnce
  if (::mknod(dev.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0) fs::create_symlink("/dev/null", dev);
  EXPECT_TRUE(throws_with<IoError>([&] { write_text_atomic(dev, "x"); }, "a device"));
  EXPECT_EQ(listing(tmp.path), (std::set<std::string>{"fifo.obj", "ro.obj", "null.txt"}));
}

TEST(Output, LongFileNamesWork) {
  // 250 characters: the target fits NAME_MAX (255); a temporary named after it (".NAME.tmp-PID") would not.
  TempDir tmp;
  const Mesh m = icosphere(1);
  const std::string name = std::string(246, 'a') + ".obj";
  ASSERT_EQ(name.size(), 250u);
  write_mesh(m, tmp / name);
  EXPECT_EQ(read_mesh(tmp / name).n_faces(), m.n_faces());
  write_mesh(m, tmp / name);  // replacing it too
  {
    OutputTransaction tx;
    tx.declare(tmp / name, "-o");
    write_mesh(m, tmp / name);
    tx.commit();
  }
  EXPECT_EQ(listing(tmp.path), std::set<std::string>{name});
  const std::string longest = std::string(251, 'b') + ".obj";  // 255
  write_mesh(m, tmp / longest);
  EXPECT_EQ(read_mesh(tmp / longest).n_faces(), m.n_faces());
}

TEST(Output, ReplacedFileKeepsItsModeAndNewFileFollowsUmask) {
  TempDir tmp;
  const Mesh m = icosphere(1);
  for (mode_t mode : {0600, 0640, 0604}) {
    const std::string p = tmp / "secret.ply";
    write_file(p, "old");
    ::chmod(p.c_str(), mode);
    write_mesh(m, p);
    EXPECT_EQ(mode_of(p), mode);
    OutputTransaction tx;
    tx.declare(p);
    write_mesh(m, p);
    tx.commit();
    EXPECT_EQ(mode_of(p), mode);
    EXPECT_EQ(read_mesh(p).n_faces(), m.n_faces());
  }
  for (bool named : {false, true}) {
    NamedTemporaries nt(named);
    const mode_t old = ::umask(027);
    const std::string p = tmp / (named ? "new-named.obj" : "new.obj");
    write_mesh(m, p);
    ::umask(old);
    EXPECT_EQ(mode_of(p), 0640u) << "named temporaries " << named;
  }
}

TEST(Output, SymlinkAtTheOutputIsWrittenThrough) {
  TempDir tmp;
  fs::create_directories(tmp.path / "real");
  const Mesh a = icosphere(0), b = icosphere(1);
  write_mesh(a, tmp / "real/target.obj");
  ::chmod((tmp / "real/target.obj").c_str(), 0600);
  fs::create_symlink("real/target.obj", tmp.path / "link.obj");  // relative, into another folder
  fs::create_symlink("link.obj", tmp.path / "link2.obj");         // a chain
  write_mesh(b, tmp / "link2.obj");
  EXPECT_TRUE(fs::is_symlink(tmp.path / "link.obj"));
  EXPECT_TRUE(fs::is_symlink(tmp.path / "link2.obj"));
  EXPECT_EQ(fs::read_symlink(tmp.path / "link.obj"), "real/target.obj");
  EXPECT_EQ(read_mesh(tmp / "real/target.obj").n_faces(), b.n_faces());
  EXPECT_EQ(mode_of(tmp / "real/target.obj"), 0600u);
  {
    OutputTransaction tx;
    tx.declare(tmp / "link.obj", "-o");
    write_mesh(a, tmp / "link.obj");
    tx.commit();
  }
  EXPECT_TRUE(fs::is_symlink(tmp.path / "link.obj"));
  EXPECT_EQ(read_mesh(tmp / "real/target.obj").n_faces(), a.n_faces());
  // A dangling link: its target is created.
  fs::create_symlink("real/new.obj", tmp.path / "dangling.obj");
  write_mesh(b, tmp / "dangling.obj");
  EXPECT_TRUE(fs::is_symlink(tmp.path / "dangling.obj"));
  EXPECT_EQ(read_mesh(tmp / "real/new.obj").n_faces(), b.n_faces());
  EXPECT_EQ(listing(tmp.path / "real"), (std::set<std::string>{"target.obj", "new.obj"}));
  // A link to a FIFO is refused like the FIFO.
  ASSERT_EQ(::mkfifo((tmp / "real/fifo").c_str(), 0644), 0);
  fs::create_symlink("real/fifo", tmp.path / "to-fifo.obj");
  EXPECT_TRUE(throws_with<IoError>([&] { write_mesh(b, tmp / "to-fifo.obj"); }, "FIFO"));
  // A loop of links.
  fs::create_symlink("loop2.obj", tmp.path / "loop1.obj");
  fs::create_symlink("loop1.obj", tmp.path / "loop2.obj");
  EXPECT_TRUE(throws_with<IoError>([&] { write_mesh(b, tmp / "loop1.obj"); }, "symbolic links"));
}

TEST(Output, AnOutputMayNotBeAnInputOrAnotherOutput) {
  TempDir tmp;
  const Mesh m = icosphere(0);
  write_mesh(m, tmp / "in.obj");
  fs::create_hard_link(tmp.path / "in.obj", tmp.path / "hard.obj");
  fs::create_symlink("in.obj", tmp.path / "soft.obj");
  {
    OutputTransaction tx;
    tx.declare_input(tmp / "in.obj");
    EXPECT_TRUE(throws_with<IoError>([&] { tx.declare(tmp / "in.obj", "-o"); }, "also an input"));
    EXPECT_TRUE(throws_with<IoError>([&] { tx.declare(tmp.path / "." / "in.obj", "-o"); }, "input"));
    EXPECT_TRUE(throws_with<IoError>([&] { tx.declare(tmp / "hard.obj", "--edges"); }, "same file as the input"));
    EXPECT_TRUE(throws_with<IoError>([&] { tx.declare(tmp / "soft.obj", "--edges"); }, "same file as the input"));
    tx.declare(tmp / "a.obj", "-o");
    EXPECT_TRUE(throws_with<IoError>([&] { tx.declare(tmp / "a.obj", "--report"); }, "same file as -o"));
    EXPECT_TRUE(throws_with<IoError>([&] { tx.declare(tmp.path / "." / "a.obj", "--report"); }, "same file as -o"));
    fs::create_symlink("a.obj", tmp.path / "to-a.obj");
    EXPECT_TRUE(throws_with<IoError>([&] { tx.declare(tmp / "to-a.obj", "--report"); }, "same file as -o"));
    // An input declared after the output is checked too.
    tx.declare(tmp / "b.obj", "--mesh");
    EXPECT_TRUE(throws_with<IoError>([&] { tx.declare_input(tmp / "b.obj"); }, "also an input"));
  }
  EXPECT_EQ(read_mesh(tmp / "in.obj").n_faces(), m.n_faces());
}

TEST(Output, NothingIsReplacedUntilCommitAndEverythingThen) {
  TempDir tmp;
  const Mesh a = icosphere(0), b = icosphere(1);
  write_file(tmp / "x.obj", "old x");
  write_file(tmp / "r.json", "old r");
  const auto before = listing(tmp.path);
  {
    OutputTransaction tx;
    EXPECT_EQ(OutputTransaction::active(), &tx);
    tx.declare(tmp / "x.obj", "-o");
    tx.declare(tmp / "r.json", "--report");
    tx.declare(tmp / "new.ply", "--mesh");
    EXPECT_TRUE(tx.is_declared(tmp.path / "." / "r.json"));
    write_mesh(b, tmp / "x.obj");
    write_text_atomic(tmp / "r.json", "{}\n");
    write_mesh(a, tmp / "new.ply");
    write_mesh(a, tmp / "x.obj");  // written again: the last one counts
    EXPECT_EQ(read_file(tmp / "x.obj"), "old x");
    EXPECT_EQ(read_file(tmp / "r.json"), "old r");
    EXPECT_EQ(listing(tmp.path), before);  // unnamed temporaries: nothing visible
    tx.commit();
    EXPECT_EQ(OutputTransaction::active(), nullptr);
  }
  EXPECT_EQ(read_mesh(tmp / "x.obj").n_faces(), a.n_faces());
  EXPECT_EQ(read_file(tmp / "r.json"), "{}\n");
  EXPECT_EQ(read_mesh(tmp / "new.ply").n_faces(), a.n_faces());
  EXPECT_EQ(listing(tmp.path), (std::set<std::string>{"x.obj", "r.json", "new.ply"}));
}

TEST(Output, AFailedSecondOutputLeavesTheFirstOutputsFileUntouched) {
  TempDir tmp;
  const Mesh m = icosphere(1);
  for (bool named : {false, true}) {
    NamedTemporaries nt(named);
    write_file(tmp / "out.obj", "old output");
    write_file(tmp / "edges.ply", "old edges");
    const auto before = listing(tmp.path);
    // The second writer refuses its data (a NaN), after the first output was written.
    EXPECT_THROW(
        {
          OutputTransaction tx;
          tx.declare(tmp / "out.obj", "-o");
          tx.declare(tmp / "edges.ply", "--edges");
          write_mesh(m, tmp / "out.obj");
          write_mesh(nan_mesh(), tmp / "edges.ply");
          tx.commit();
        },
        InvalidInput);
    // The work fails after the first output (any exception).
    EXPECT_THROW(
        {
          OutputTransaction tx;
          tx.declare(tmp / "out.obj", "-o");
          tx.declare(tmp / "edges.ply", "--edges");
          write_mesh(m, tmp / "out.obj");
          throw std::runtime_error("the solver failed");
        },
        std::runtime_error);
    // The second output's folder went away during the run.
    fs::create_directories(tmp.path / "gone");
    EXPECT_THROW(
        {
          OutputTransaction tx;
          tx.declare(tmp / "out.obj", "-o");
          tx.declare(tmp / "gone/e.ply", "--edges");
          write_mesh(m, tmp / "out.obj");
          fs::remove(tmp.path / "gone");
          write_mesh(m, tmp / "gone/e.ply");
          tx.commit();
        },
        IoError);
    // A declared output that was never written: commit refuses before replacing anything.
    EXPECT_TRUE(throws_with<IoError>(
        [&] {
          OutputTransaction tx;
          tx.declare(tmp / "out.obj", "-o");
          tx.declare(tmp / "edges.ply", "--edges");
          write_mesh(m, tmp / "out.obj");
          tx.commit();
        },
        "never written"));
    EXPECT_EQ(read_file(tmp / "out.obj"), "old output");
    EXPECT_EQ(read_file(tmp / "edges.ply"), "old edges");
    EXPECT_EQ(listing(tmp.path), before) << "named temporaries " << named;
  }
}

TEST(Output, ADiskFullSecondOutputLeavesTheFirstUntouched) {
  // A file size limit makes the second (larger) write fail with EFBIG, as a full disk would.
  TempDir tmp;
  write_file(tmp / "out.obj", "old output");
  write_file(tmp / "big.obj", "old big");
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::signal(SIGXFSZ, SIG_IGN);
    rlimit lim{4000, 4000};
    ::setrlimit(RLIMIT_FSIZE, &lim);
    int code = 3;
    try {
      OutputTransaction tx;
      tx.declare(tmp / "out.obj", "-o");
      tx.declare(tmp / "big.obj", "--mesh");
      write_mesh(icosphere(0), tmp / "out.obj");  // ~1 kB
      write_mesh(icosphere(3), tmp / "big.obj");  // ~40 kB
      tx.commit();
      code = 0;
    } catch (const IoError&) {
      code = 1;
    } catch (...) {
      code = 2;
    }
    ::_exit(code);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);  // an IoError
  EXPECT_EQ(read_file(tmp / "out.obj"), "old output");
  EXPECT_EQ(read_file(tmp / "big.obj"), "old big");
  EXPECT_EQ(listing(tmp.path), (std::set<std::string>{"out.obj", "big.obj"}));
}

TEST(Output, UndeclaredWritesAreRefusedInsideATransaction) {
  TempDir tmp;
  const Mesh m = icosphere(0);
  OutputTransaction tx;
  tx.declare(tmp / "a.obj");
  EXPECT_TRUE(throws_with<IoError>([&] { write_mesh(m, tmp / "b.obj"); }, "not declared"));
  EXPECT_TRUE(throws_with<IoError>([&] { write_text_atomic(tmp / "c.txt", "x"); }, "not declared"));
  EXPECT_TRUE(listing(tmp.path).empty());
  // Another thread is not in this transaction: its writes are atomic one by one.
  std::thread t([&] { write_mesh(m, tmp / "other-thread.obj"); });
  t.join();
  EXPECT_TRUE(fs::exists(tmp.path / "other-thread.obj"));
  // A nested transaction is active until it ends; then the outer one is again.
  {
    OutputTransaction inner;
    EXPECT_EQ(OutputTransaction::active(), &inner);
    inner.declare(tmp / "b.obj");
    write_mesh(m, tmp / "b.obj");
    inner.commit();
    EXPECT_EQ(OutputTransaction::active(), &tx);
  }
  EXPECT_TRUE(fs::exists(tmp.path / "b.obj"));
  EXPECT_EQ(OutputTransaction::active(), &tx);
}

TEST(Output, WritersRefuseNonFiniteValuesBeforeTouchingAnyFile) {
  TempDir tmp;
  const Mesh bad = nan_mesh();
  for (const char* name : {"x.obj", "x.off", "x.ply", "x.stl"}) {
    write_file(tmp / name, "old");
    EXPECT_TRUE(throws_with<InvalidInput>([&] { write_mesh(bad, tmp / name); }, "non-finite")) << name;
    EXPECT_EQ(read_file(tmp / name), "old");
  }
  Mesh huge = icosphere(0);
  huge.point(huge.vertex_handle(0))[0] = 1e300;  // finite, but not a float
  EXPECT_TRUE(throws_with<InvalidInput>([&] { write_mesh(huge, tmp / "x.stl"); }, "32-bit"));
  write_mesh(huge, tmp / "huge.ply");  // PLY keeps doubles: reads back exactly
  EXPECT_EQ(positions(read_mesh(tmp / "huge.ply"))(0, 0), 1e300);
  const Mesh m = icosphere(0);
  PlyExtras x;
  x.vertex_scalars["height"] = std::vector<double>(m.n_vertices(), 0.0);
  x.vertex_scalars["height"][2] = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(throws_with<InvalidInput>([&] { write_ply(m, tmp / "x.ply", x); }, "'height' of vertex 2"));
  Eigen::VectorXd values = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(m.n_edges()));
  values[1] = std::nan("");
  EXPECT_TRUE(throws_with<InvalidInput>([&] { write_edge_values(m, values, "tilt", tmp / "x.ply"); }, "'tilt' of edge 1"));
  MatrixX3d V = positions(m);
  V(1, 2) = std::nan("");
  MatrixX2i seg(1, 2);
  seg << 0, 1;
  EXPECT_TRUE(throws_with<InvalidInput>([&] { write_polylines_obj(V, seg, tmp / "x.obj"); }, "non-finite"));
  EXPECT_EQ(read_file(tmp / "x.ply"), "old");
  EXPECT_EQ(read_file(tmp / "x.obj"), "old");
}

namespace {

// Run \p body in a child that writes inside a transaction, then waits to be killed with \p sig.
// Returns the folder's listing after the child died, and whether the child died of that signal.
struct KilledChild {
  bool died_of_signal = false;
  bool saw_named_temporary = false;
};

KilledChild kill_during_transaction(const TempDir& tmp, int sig, bool named) {
  int ready[2];
  EXPECT_EQ(::pipe(ready), 0);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(ready[0]);
    ::signal(sig, SIG_DFL);  // a shell that starts the tests in the background ignores SIGINT: not here
    try {
      detail::use_named_temporaries(named);
      OutputTransaction tx;
      tx.declare(tmp / "out.obj", "-o");
      tx.declare(tmp / "edges.ply", "--edges");
      write_mesh(icosphere(2), tmp / "out.obj");
      write_mesh(icosphere(1), tmp / "edges.ply");
      const char c = 'r';
      (void)!::write(ready[1], &c, 1);
      for (;;) ::pause();  // "the work", interrupted
    } catch (...) {
    }
    ::_exit(2);  // never back into the test runner
  }
  ::close(ready[1]);
  char c = 0;
  KilledChild r;
  EXPECT_EQ(::read(ready[0], &c, 1), 1) << "the child failed before it was ready";
  ::close(ready[0]);
  for (const auto& name : listing(tmp.path)) r.saw_named_temporary |= name.rfind(".geotex-", 0) == 0;
  ::kill(pid, sig);
  int status = 0;
  EXPECT_EQ(::waitpid(pid, &status, 0), pid);
  r.died_of_signal = WIFSIGNALED(status) && WTERMSIG(status) == sig;
  return r;
}

}  // namespace

TEST(Output, SignalsRemoveTheTemporaries) {
  TempDir tmp;
  write_file(tmp / "out.obj", "old output");
  const auto before = listing(tmp.path);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    const KilledChild r = kill_during_transaction(tmp, sig, /*named=*/true);
    EXPECT_TRUE(r.saw_named_temporary) << "the child wrote named temporaries before it was killed";
    EXPECT_TRUE(r.died_of_signal) << "the signal keeps its default effect (" << sig << ")";
    EXPECT_EQ(listing(tmp.path), before) << "signal " << sig;
    EXPECT_EQ(read_file(tmp / "out.obj"), "old output");
  }
}

TEST(Output, SigkillLeavesNothingWithUnnamedTemporaries) {
  TempDir tmp;
  const int probe = ::open(tmp.path.c_str(), O_TMPFILE | O_RDWR, 0600);
  if (probe < 0) GTEST_SKIP() << "the temporary folder's file system has no O_TMPFILE";
  ::close(probe);
  write_file(tmp / "out.obj", "old output");
  const auto before = listing(tmp.path);
  const KilledChild r = kill_during_transaction(tmp, SIGKILL, /*named=*/false);
  EXPECT_FALSE(r.saw_named_temporary);
  EXPECT_TRUE(r.died_of_signal);
  EXPECT_EQ(listing(tmp.path), before);
  EXPECT_EQ(read_file(tmp / "out.obj"), "old output");
}
