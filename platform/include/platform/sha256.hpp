// platform/sha256.hpp: the project's one SHA-256, for the digests its files record: a
// corpus manifest's line per file, a SPEC or design file's identity, a detector model's
// bytes and its training manifests. OpenSSL's libcrypto computes it (with the CPU's SHA
// instructions where there are some: a paper cloud is 36 MiB, a 100x one 3.6 GB, and
// hashing must stay a small part of writing one).
#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

namespace platform {

/// Incremental SHA-256: update() any number of times, then hex() once.
/// Throws core::Error("platform: SHA-256: ...") if OpenSSL fails (out of memory).
class Sha256 {
  public:
    Sha256();
    ~Sha256();
    Sha256(const Sha256&) = delete;
    Sha256& operator=(const Sha256&) = delete;
    void update(const void* data, std::size_t bytes);
    void update(std::string_view text) { update(text.data(), text.size()); }
    /// The digest as 64 lowercase hex digits; the object is spent afterwards.
    std::string hex();

    struct Context;

  private:
    std::unique_ptr<Context> context_;
};

/// The hex SHA-256 of `bytes`.
std::string sha256Hex(std::string_view bytes);

/// Size and hex SHA-256 of a file.
struct FileDigest {
    std::uint64_t bytes = 0;
    std::string sha256;
};

/// The FileDigest of `file`, read in chunks and never through a symbolic link at its
/// last name. Throws core::Error("<module>: <file>: cannot read: <reason>").
FileDigest sha256File(const std::filesystem::path& file, std::string_view module);

}  // namespace platform
