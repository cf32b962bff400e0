// engine/atomic_file.hpp: write-to-temp-then-rename for every output of the project.
#pragma once
#include <filesystem>
#include <string_view>

namespace engine {

/// Writes `content` to "<path>.tmp-<pid>" then renames it to `path`. On failure the
/// temporary file is removed and Error("output: <path>: <reason>") is thrown; an
/// existing file under `path` is left untouched.
void writeFileAtomic(const std::filesystem::path& path, std::string_view content);

/// A temporary sibling of `path`: "<path>.tmp-<pid>".
std::filesystem::path tempSibling(const std::filesystem::path& path);

/// Throws Error("output: <path>: directory '<dir>' does not exist") etc. before work starts.
void checkWritableDestination(const std::filesystem::path& path);

}  // namespace engine
