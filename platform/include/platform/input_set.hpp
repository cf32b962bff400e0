// platform/input_set.hpp: the files and folders one run reads, which no output of the run
// may replace. A command builds its InputSet from what it reads (its input files, the files
// a scene or a corpus names) and hands it to the checks of the outputs it names
// (checkWritableDestination in platform/atomic_file.hpp), so the checks see every input
// whatever the order the command reads and writes in. Outputs inside an output folder are
// kept apart from the inputs a command names by checkDistinctPaths (platform/safe_file.hpp).
#pragma once
#include <platform/safe_file.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace platform {

class InputSet {
  public:
    /// Adds the file `path` names, symbolic links followed; files are compared by device
    /// and inode, so a hard link or a link to it names the same input. A name that cannot
    /// be examined (absent) adds nothing: no output can replace it.
    void addFile(const std::filesystem::path& path);

    /// Adds the folder `dir` (links followed): an output inside it, at any depth and via
    /// any link, whose path relative to `dir` (generic, '/'-separated) `may_write` does not
    /// accept is refused; the folder itself is refused always. An absent folder adds nothing.
    void addFolder(const std::filesystem::path& dir, OwnedName may_write);

    /// Throws Error("output: <path>: is the input file '<input>' of this run; give another
    /// name") when `output` names (via any link) a file of the set, or "output: <path>: is
    /// '<relative>' inside the input folder '<dir>' of this run, which this command reads;
    /// give another name" when it lies where an input folder refuses outputs.
    void checkNotAnInput(const std::filesystem::path& output) const;

  private:
    struct File {
        std::uint64_t dev = 0, ino = 0;
        std::string path;
    };
    struct Folder {
        std::filesystem::path canonical;
        std::string path;
        OwnedName may_write;
    };
    std::vector<File> files_;
    std::vector<Folder> folders_;
};

}  // namespace platform
