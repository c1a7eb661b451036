#pragma once
//! \file output.h How geotex writes files: every output of a command is checked before any work,
//! written in full to a temporary beside its target, and put in place only when all of them are
//! complete. A failed or interrupted run leaves every existing file as it was and no temporary behind.
//!
//! Typical use (a command with a mesh output and an optional report):
//! \code
//!   OutputTransaction out;                 // the calling thread's active transaction from here on
//!   out.declare_input(in_path);
//!   out.declare(out_path, "-o");           // checked now: throws IoError before minutes of work
//!   if (!report.empty()) out.declare(report, "--report");
//!   Mesh m = read_mesh(in_path); ...       // the work
//!   write_mesh(m, out_path);               // goes to a temporary
//!   write_text_atomic(report, json);       // goes to a temporary
//!   out.commit();                          // both renamed into place
//! \endcode
//! If anything throws before commit(), the destructor removes the temporaries; no existing file is
//! touched.
//!
//! Rules for every output (checked by declare(), again by commit(), and by every write outside a
//! transaction):
//! - its folder exists and is writable; its name fits the folder's NAME_MAX. Temporaries never use
//!   the target's name: they are unnamed (O_TMPFILE) where the file system allows, otherwise
//!   `.geotex-XXXXXX` (14 bytes) in the same folder;
//! - a directory, FIFO, socket or device at the path is refused (without opening it, so a FIFO does
//!   not block); an existing file without any write permission bit is refused ("… is read-only;
//!   geotex does not replace it");
//! - a symbolic link at the path is written through: the link stays, the file it points to (the end
//!   of its chain, which may not exist yet) is replaced atomically;
//! - a replaced file keeps its permission bits (a mode-600 file stays 600) and, where allowed, its
//!   owner and group; a new file gets 0666 & ~umask;
//! - inside a transaction, an output may not be a declared input (the same path, a hard link or a
//!   symbolic link to it), and two outputs may not be the same file.
//!
//! Signals: the first transaction or atomic write installs handlers for SIGINT, SIGTERM and SIGHUP
//! where their disposition is still the default (a handler set by the program, e.g. Python's SIGINT,
//! is left alone; so is SIG_IGN). The handler unlinks the named temporaries of every thread
//! (async-signal-safe: unlinkat on a static table) and re-raises the signal with the default action.
//! SIGKILL cannot be caught: with O_TMPFILE it leaves nothing (an unnamed temporary vanishes with
//! the process), except during commit(), when each output has a name for the few microseconds
//! between its link and its rename; on a file system without O_TMPFILE it leaves the
//! `.geotex-XXXXXX` files of the outputs written so far.
//!
//! Temporaries are not fsync()ed before they are put in place (as before this class): a power cut
//! right after a run may, on some file systems, leave an output empty, never a mix of old and new.
//!
//! commit() renames the outputs one after the other; each rename is atomic, the group is not: if a
//! rename fails after every check passed (an I/O error), the outputs renamed before it stay replaced
//! and the error names them.

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace geotex {

void write_file_atomic(const std::filesystem::path& path, std::string_view bytes);

//! The outputs of one command, written all together or not at all. Not copyable or movable.
//!
//! Scope: a transaction is active on the thread that constructed it, from construction until
//! commit() or destruction; then the one that was active before it (if any) is active again.
//! While a transaction is active on a thread, every atomic write of the library on that thread
//! (write_file_atomic(), write_mesh(), write_ply(), write_edge_values(), write_polylines_obj(),
//! write_text_atomic(), write_texture(), write_png(), …) goes to the temporary of a declared output
//! and throws IoError for a path that was not declared. Other threads are not affected (so Python
//! threads can each run their own). Without an active transaction each write is atomic on its own,
//! under the same rules.
class OutputTransaction {
 public:
  OutputTransaction();
  //! Without commit(): removes every temporary; no target is touched.
  ~OutputTransaction();
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;

  //! A file the command reads. No output may be this file. It need not exist (its path is compared).
  void declare_input(const std::filesystem::path& path);

  //! An output, checked now against the rules in the file comment, against every declared input
  //! (declare inputs first; an input declared later is checked against the outputs already
  //! declared) and against the other outputs. \p what names it in messages (a flag such as
  //! "--edges", or "output"). Declaring the same path twice is an error too.
  //! \throw IoError naming \p what and the path.
  void declare(const std::filesystem::path& path, const std::string& what = "output");

  //! Whether \p path (as given to declare(), or any spelling of it) is a declared output.
  bool is_declared(const std::filesystem::path& path) const;

  //! Put every output in place. Every declared output must have been written (\throw IoError naming
  //! those that were not, before anything is renamed); each target is checked again. After commit()
  //! the transaction is no longer active and the object can only be destroyed.
  void commit();

  //! The transaction active on the calling thread, or nullptr.
  static OutputTransaction* active();

  struct Impl;  //!< (implementation)

 private:
  friend void write_file_atomic(const std::filesystem::path& path, std::string_view bytes);
  std::unique_ptr<Impl> impl_;
  OutputTransaction* previous_ = nullptr;
};

//! Write \p bytes to \p path atomically: inside an active transaction to the declared output's
//! temporary (put in place at commit()), otherwise to a temporary renamed into place at once.
//! \throw IoError (see the rules above; also a full disk), the target untouched.
void write_file_atomic(const std::filesystem::path& path, std::string_view bytes);

namespace detail {
//! Tests only: use named `.geotex-XXXXXX` temporaries even where O_TMPFILE works, to exercise the
//! fallback and the signal handler's unlinking. Returns the previous setting.
bool use_named_temporaries(bool named);
}  // namespace detail

}  // namespace geotex
