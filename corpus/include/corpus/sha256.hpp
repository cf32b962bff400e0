// corpus/sha256.hpp: SHA-256 of the files the corpus writes, so a manifest line says
// exactly which bytes an item holds and two runs can be compared file by file. OpenSSL's
// libcrypto computes it (with the CPU's SHA instructions where there are some: a paper
// cloud is 36 MiB, a 100x one 3.6 GB, and hashing must stay a small part of an item).
#pragma once
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

namespace corpus {

/// Incremental SHA-256: update() any number of times, then hex() once.
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

/// The hex SHA-256 of `text`.
std::string sha256Hex(std::string_view text);

/// Size and hex SHA-256 of a regular file, read in chunks. Throws core::Error
/// ("corpus: <file>: cannot read ...").
struct FileDigest {
    std::uint64_t bytes = 0;
    std::string sha256;
};
FileDigest sha256File(const std::filesystem::path& file);

}  // namespace corpus
