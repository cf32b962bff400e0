// platform/cache_folder.hpp: the user's cache folder for files the project derives from an
// input (a cloud's COPC index), keyed by the input's identity, and the folder's size bound.
//
// The folder is $XDG_CACHE_HOME/<name> (else $HOME/.cache/<name>), made mode 0700 when
// missing and refused when it is a symbolic link, not a folder or another user's. Each
// cached file is named from a hash of its input's identity (device, inode, size,
// modification time in ns and canonical path), so a changed or replaced input gets a new
// name and the old file ages out. Files are written there as every output is (a TempFile,
// then one rename), so two runs deriving the same file each rename a whole one into place
// and a reader never sees half of it. The bound removes only regular files of this user
// whose names the caller's pattern accepts, least recently used first (a reuse sets the
// file's modification time to now).
#pragma once
#include <platform/safe_file.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <sys/types.h>
#include <vector>

namespace platform {

/// $XDG_CACHE_HOME/<name> when XDG_CACHE_HOME is an absolute path, else
/// $HOME/.cache/<name> (the XDG base directory rule: a relative value is ignored). Throws
/// Error("<what>: no cache folder: neither XDG_CACHE_HOME nor HOME is an absolute path").
std::filesystem::path userCacheFolder(std::string_view name, std::string_view what);

/// Makes `dir` with mode 0700 when it is absent (its missing parents too, 0700, as the
/// XDG rule asks), or checks the one there. Throws Error("<what> <dir>: is a symbolic
/// link; allowed: a folder of this user") (or "is a regular file ...", "belongs to user
/// id N ...", "cannot create the folder: ...").
void makeCacheFolder(const std::filesystem::path& dir, std::string_view what);

/// What tells one state of a file from another without reading it.
struct FileIdentity {
    dev_t device = 0;
    ino_t inode = 0;
    std::uint64_t size_bytes = 0;
    std::int64_t mtime_ns = 0;  // modification time since the epoch
    std::filesystem::path canonical;
};

/// The identity of the regular file `path` (links followed). Throws Error("<what> <path>:
/// cannot stat: <reason>").
FileIdentity fileIdentity(const std::filesystem::path& path, std::string_view what);

/// 32 lowercase hex digits from `identity` and `salt` (two 64-bit FNV-1a hashes over the
/// same text with different bases): equal identities give equal keys, and any field that
/// changes gives another.
std::string identityKey(const FileIdentity& identity, std::string_view salt);

/// A cached file found by name: a regular file of this user (never followed through a
/// link). Marks it used now (its modification time, through an O_NOFOLLOW descriptor).
/// False when it is absent; throws Error("<what> <path>: is ...; allowed: a regular file
/// this command created") when something else sits under the name.
bool useCachedFile(const std::filesystem::path& path, std::string_view what);

/// Removes files from `dir` until those whose names `ours` accepts total at most
/// `max_bytes`: the least recently used first (oldest modification time, then name),
/// never `keep` (a name in `dir`), and only regular files of this user (links, folders,
/// other users' files and names `ours` refuses are neither counted nor touched). Returns
/// the names removed, in order. Errors are ignored (a file another run removed first).
std::vector<std::string> boundCacheFolder(const std::filesystem::path& dir, const OwnedName& ours,
                                          std::uint64_t max_bytes, const std::string& keep);

}  // namespace platform
