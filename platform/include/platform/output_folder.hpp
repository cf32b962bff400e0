// platform/output_folder.hpp: output folders written as a whole (the metric's report
// folder, each corpus item): a reader sees the whole previous set of files or the whole
// new one, never a mix, and a failed or stopped run leaves the previous folder untouched.
#pragma once
#include <platform/safe_file.hpp>

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace platform {

/// Checks, before the work, that `dir` can become an output folder: its parent exists
/// (or its nearest existing ancestor, as missing parents are made) is a writable folder,
/// and `dir` is absent or a folder (never a symbolic link) holding only names `ours` accepts.
/// Throws Error("output: <dir>: ...").
void checkOutputFolder(const std::filesystem::path& dir, const OwnedName& ours);

/// A folder whose files are written into a new hidden temporary folder beside `dir`
/// (".ladarvr-tmp-<pid>-XXXXXX", made with mkdir's O_EXCL semantics, registered for
/// removal on a signal with everything written into it, platform/cleanup.hpp), then
/// swapped in by commit(). Destroying it uncommitted removes the temporary folder.
class AtomicFolder {
  public:
    /// Checks `dir` as checkOutputFolder does, making missing parent folders, and creates
    /// the temporary folder. Throws Error("output: <dir>: ...").
    AtomicFolder(std::filesystem::path dir, OwnedName ours);
    ~AtomicFolder();
    AtomicFolder(const AtomicFolder&) = delete;
    AtomicFolder& operator=(const AtomicFolder&) = delete;

    /// Where the file `name` lies until commit(), for writers that make the file
    /// themselves (writeFileAtomic, CloudWriter); adopt(name) once it is there.
    std::filesystem::path path(const std::string& name) const;
    /// Writes `content` as the new file `name` (O_CREAT|O_EXCL|O_NOFOLLOW).
    /// Throws Error("output: <dir>/<name>: ...").
    void writeFile(const std::string& name, std::string_view content);
    /// Registers the file `name` another writer made at path(name) for removal on a signal.
    void adopt(const std::string& name);
    /// Checks `dir` again (it may have changed since), then moves the new folder into
    /// place: renameat2(RENAME_EXCHANGE) with the previous one, or, where the file system
    /// lacks it, the previous folder steps aside and the new one moves in; the previous
    /// folder is then removed. Throws Error("output: <dir>: ...") and leaves the previous
    /// folder in place on failure.
    void commit();

  private:
    void removeTemporary() noexcept;
    std::filesystem::path dir_;     // as given, for messages
    std::filesystem::path target_;  // links resolved
    std::filesystem::path parent_;
    OwnedName ours_;
    std::string temp_name_;  // the temporary folder's name in parent_
    int parent_fd_ = -1, temp_fd_ = -1;
    int temp_slot_ = -1;                              // cleanup registration of the temporary folder
    std::vector<std::pair<std::string, int>> files_;  // name, cleanup slot
    bool committed_ = false;
};

/// Writes `files` (name, content) as the folder `dir` through an AtomicFolder, after
/// removing the temporaries of dead runs beside it (safe_file.hpp).
void writeFolderAtomic(const std::filesystem::path& dir, const std::vector<std::pair<std::string, std::string>>& files,
                       const OwnedName& ours);

}  // namespace platform
