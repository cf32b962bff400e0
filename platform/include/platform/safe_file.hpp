// platform/safe_file.hpp: reading outside files and creating our own, safely as root.
//
// The tool runs as root with the host's /dev bound in, so, like coreutils' install/mv
// and rsync:
// - inputs must be regular files (a FIFO would block, /dev/zero never ends, a directory
//   reads as empty) of a bounded size; a command lists what it reads in an InputSet
//   (platform/input_set.hpp) and checks the outputs it names against it, so that no
//   output replaces an input (compared by device and inode: symlinks and hard links too);
// - outputs are written to a fresh temporary in the destination's folder, created with
//   O_CREAT|O_EXCL|O_NOFOLLOW under a random name ".ladarvr-tmp-<pid>-XXXXXX", and
//   renamed over the destination only if that is absent or a regular file (never a
//   symlink, device node, FIFO or socket);
// - scratch data (the generator's spool) lives in an anonymous file (O_TMPFILE, or
//   unlinked right after creation), so nothing of it outlives the process;
// - a stopped run removes its temporaries (platform/cleanup.hpp); the temporaries of a
//   killed run are removed by the next run that writes into the same folder.
#pragma once
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace platform {

/// The name prefix of every temporary file or folder the project creates.
inline constexpr std::string_view kTempPrefix = ".ladarvr-tmp-";

/// As core::printable, but valid UTF-8 is kept (text meant as text: names and labels from JSON,
/// messages): control characters (C0, DEL, C1) and bytes that are not valid UTF-8 as \xNN;
/// the cut never splits a character. Escaped text stays as it is, so applying it twice
/// changes nothing.
std::string printableUtf8(std::string_view text, std::size_t max_chars = 200);

/// The longest line messageLine returns: room for a few quoted paths (400 characters each)
/// and the words around them.
inline constexpr std::size_t kMaxMessageChars = 2000;

/// `message` as one line for stderr: printableUtf8's escaping and, over `max_chars`, the
/// middle cut to " ... " so the start (module, file, field) and the end (what is allowed)
/// both stay.
std::string messageLine(std::string_view message, std::size_t max_chars = kMaxMessageChars);

/// Writes "ladarvr: <label>: <messageLine(what)>" and a newline to stderr: the one way
/// errors ("error", "internal error") and warnings ("warning") reach the terminal, so a
/// value quoted into a message raw cannot break the line or steer the terminal.
void printMessage(std::string_view label, std::string_view what);

/// Why `path` is not a regular file, in words that follow the file's name ("does not
/// exist", "is a symbolic link loop", "is a dangling symbolic link", "is a directory",
/// "is a FIFO (named pipe)", "is a character device", ...); empty when it is one
/// (symbolic links followed).
std::string regularFileProblem(const std::filesystem::path& path);

/// Checks that `path` is a regular file. Throws Error("<what> <problem>; allowed: a regular file"), e.g.
/// "scene: s.json: mesh file 'a.obj' is a FIFO (named pipe); allowed: a regular file".
void checkInputFile(const std::filesystem::path& path, std::string_view what);

/// The whole of a regular file of at most `max_bytes`. Never blocks on a FIFO or reads a
/// device. Throws Error("<what> <problem>") as checkInputFile,
/// or "<what> is larger than <max_bytes> bytes; allowed: ...", or "... cannot be read: <reason>".
std::string readTextFile(const std::filesystem::path& path, std::size_t max_bytes, std::string_view what);

/// Throws Error("<what> '<dir>/<relative>': '<name>' in it is a symbolic link; allowed: ...")
/// when a name on the way from the folder `dir` down to `dir / relative` is a symbolic
/// link: a folder's own entries (a corpus item's cloud) are read where the folder holds
/// them, never through a link planted inside it. `dir` itself may be reached through
/// links, as the user named it. Absent names are left to the reader to report.
void checkNoLinkBelow(const std::filesystem::path& dir, const std::filesystem::path& relative, std::string_view what);

/// readTextFile for a file this run will replace, one an earlier run wrote and this one
/// continues (a resumed study's trials.csv): never read through a symbolic link. Throws as readTextFile, or "<what> is a symbolic link; ...".
std::string readOwnOutput(const std::filesystem::path& path, std::size_t max_bytes, std::string_view what);

/// A new file next to `destination` (same folder) for its content, named
/// ".ladarvr-tmp-<pid>-XXXXXX", registered for removal on a signal. The first creation
/// in a folder removes the temporaries of dead processes there. commit() renames it over
/// `destination`; destroying it uncommitted removes it.
class TempFile {
  public:
    /// Throws Error("output: <destination>: ...") naming the reason.
    explicit TempFile(std::filesystem::path destination);
    ~TempFile();
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;

    /// The open stream (binary, write); stays owned by the TempFile. Its descriptor also
    /// reads, for a writer that reads back what it wrote.
    std::FILE* file() const { return file_; }
    /// The temporary's path, for tests and messages.
    std::filesystem::path path() const;
    const std::filesystem::path& destination() const { return destination_; }
    /// Flushes, closes and renames over the destination if that is absent or a regular
    /// file. On any failure the temporary is removed and
    /// Error("output: <destination>: <what failed>: <reason>") is thrown. A test may hold
    /// it between the two steps (platform/test_hold.hpp, LADARVR_TEST_HOLD_COMMIT).
    void commit();
    /// Closes and removes the temporary now (also what the destructor does).
    void discard() noexcept;

  private:
    std::filesystem::path destination_;
    std::string name_;  // the temporary's name inside the folder
    int dirfd_ = -1;    // the destination's folder
    int slot_ = -1;     // cleanup registration
    std::FILE* file_ = nullptr;
};

/// An anonymous read-write file in `dir` (O_TMPFILE where the file system has it, else
/// a TempFile-style name unlinked at once): nothing of it survives the process, not
/// even after SIGKILL. `what` names the output it serves in messages.
/// Throws Error("output: <what>: cannot create a scratch file in '<dir>': <reason>").
std::FILE* openScratchFile(const std::filesystem::path& dir, std::string_view what);

/// Frees the whole pages of the scratch file `scratch` from `freed` (0, or what an earlier
/// call returned) up to `end`, bytes read for the last time: written but perhaps not yet
/// on the disk, they need not go there, and their memory serves other writes at once.
/// Returns the offset freed up to (`end` rounded down to a page, or `freed` if more).
/// Where the file system cannot punch holes the bytes stay, which costs only time.
std::uint64_t freeScratchBefore(std::FILE* scratch, std::uint64_t freed, std::uint64_t end);

/// Decides whether a name found in an existing output folder is one we write there.
using OwnedName = std::function<bool(const std::string& name)>;

/// Removes the ".ladarvr-tmp-<pid>-<tag>" entries in `dir` (tag: 1 to 32 letters and
/// digits: TempFile's six random ones, a corpus item's id) whose process is no longer
/// alive, and only what our own runs can have made: regular files of this user, and
/// folders of this user that hold nothing but regular files of this user named as
/// `folder_holds` accepts (or temporaries). Links, FIFOs, devices, sockets and other
/// folders stay. Quiet; errors are ignored.
void removeStaleTemporaries(const std::filesystem::path& dir, const OwnedName& folder_holds = {});

/// The longest path (in bytes, without the final NUL) and the longest name in it that
/// the project accepts for a file it reads or writes: Linux's PATH_MAX - 1 and NAME_MAX.
inline constexpr std::size_t kMaxPathBytes = 4095;
inline constexpr std::size_t kMaxNameBytes = 255;

/// Throws Error("<what> '<path, shortened>': the path is N bytes long; allowed at most
/// 4095 bytes" (or "... a name in it is N bytes long; allowed at most 255 bytes per
/// name")) when `path` is longer than the system can open; `what` names the option.
void checkPathLength(const std::filesystem::path& path, std::string_view what);

/// What a path is to a run, for checkDistinctPaths.
enum class PathRole {
    Input,         // a file the run reads
    InputFolder,   // a folder the run reads from (its `names`, or everything in it)
    Output,        // a file the run writes
    OutputFolder,  // a folder the run writes into (its `names`) or replaces as a whole
};

/// One path given to a run: the option that gave it (for messages, e.g. "--out"), the
/// path, its role and, for folders, a test of the names inside it that the run reads or
/// writes (applied to the first name below the folder; empty: every name).
struct RunPath {
    std::string option;
    std::filesystem::path path;
    PathRole role = PathRole::Input;
    OwnedName names;
};

/// Removes the folder `name` inside the open folder `parent_fd` if it is a real folder
/// (no link) of this user holding only regular files of this user whose names `holds`
/// accepts or are temporaries; returns whether it did. Anything else is left whole.
bool removeOwnFolder(int parent_fd, const std::string& name, const OwnedName& holds);

/// Opens a file this command creates and keeps (a lock file, an appended manifest):
/// `flags` (O_RDONLY, O_RDWR, O_WRONLY | O_APPEND, with O_CREAT to create it) plus
/// O_NOFOLLOW, O_NONBLOCK (cleared after the open) and O_NOCTTY. The name must be absent
/// (with O_CREAT) or a regular file of this user, checked before the open and on the
/// open descriptor: a symbolic link, a device node, a FIFO, a socket, a folder or
/// another user's file is refused with Error("<what> <path>: is ...; allowed: a regular
/// file this command created"). Returns the descriptor.
int openOwnFile(const std::filesystem::path& path, int flags, std::string_view what);

/// The whole of a file this command wrote and now reads back (openOwnFile's checks), at
/// most `max_bytes`; the command may replace it afterwards. Throws
/// Error("<what> <path>: ...").
std::string readOwnFile(const std::filesystem::path& path, std::size_t max_bytes, std::string_view what);

/// Makes the folder `path` if it is absent (its parent must exist) or checks the one
/// there: a real folder of this user, not a symbolic link. Throws Error("<what> <path>:
/// is ...; allowed: a folder this command made").
void makeOwnFolder(const std::filesystem::path& path, std::string_view what);

/// The check every command runs on its paths before any work: no output is an input or
/// another output, and no path lies inside an output folder where the run writes (or
/// that it replaces), nor an output inside an input folder where the run reads. Paths
/// are compared after resolving links in their existing part (two names of one file,
/// hard links included, are the same file); empty paths are skipped; each path's length
/// is checked first (checkPathLength). Throws Error("<command>: <option> '<path>' and
/// <option> '<path>' <why>; allowed: ..."), one line naming both options.
void checkDistinctPaths(std::string_view command, const std::vector<RunPath>& paths);

}  // namespace platform
