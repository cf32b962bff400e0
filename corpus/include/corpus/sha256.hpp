// corpus/sha256.hpp: SHA-256 (FIPS 180-4) of the files the corpus writes, so a manifest
// line says exactly which bytes an item holds and two runs can be compared file by file.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace corpus {

/// Incremental SHA-256: update() any number of times, then hex() once.
class Sha256 {
public:
    Sha256();
    void update(const void* data, std::size_t bytes);
    void update(std::string_view text) { update(text.data(), text.size()); }
    /// The digest as 64 lowercase hex digits; the object is spent afterwards.
    std::string hex();

private:
    void block(const std::uint8_t* p);
    std::array<std::uint32_t, 8> h_;
    std::array<std::uint8_t, 64> buffer_{};
    std::size_t used_ = 0;
    std::uint64_t total_bytes_ = 0;
};

/// The hex SHA-256 of `text`.
std::string sha256Hex(std::string_view text);

}  // namespace corpus
