// platform/atomic_file.hpp: write-to-temp-then-rename for every output of the project.
#pragma once
#include <filesystem>
#include <string_view>

namespace platform {

class InputSet;

/// Writes `content` to a fresh temporary in the same folder (platform::TempFile:
/// O_EXCL|O_NOFOLLOW, random name) then renames it to `path`. On failure the temporary
/// is removed and Error("output: <path>: <reason>") is thrown; an existing file under
/// `path` is left untouched.
void writeFileAtomic(const std::filesystem::path& path, std::string_view content);

/// Checks a destination before work starts. Throws Error("output: <path>: ...") when the
/// name is empty, its folder is missing, not a directory or not writable, or the name
/// exists and is not a regular file (a directory, a symbolic link, a device node, a FIFO
/// or a socket: never replaced).
void checkWritableDestination(const std::filesystem::path& path);

/// The same, and then refuses a name that is one of the run's `inputs`, or lies where one
/// of its input folders refuses outputs (InputSet::checkNotAnInput).
void checkWritableDestination(const std::filesystem::path& path, const InputSet& inputs);

}  // namespace platform
