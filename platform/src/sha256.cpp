// platform/src/sha256.cpp: SHA-256 (platform/sha256.hpp) through OpenSSL's EVP interface.
#include <platform/sha256.hpp>

#include <core/error.hpp>

#include <openssl/evp.h>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

namespace platform {

struct Sha256::Context {
    EVP_MD_CTX* ctx = nullptr;
};

Sha256::Sha256() : context_(std::make_unique<Context>()) {
    context_->ctx = EVP_MD_CTX_new();
    if (!context_->ctx || EVP_DigestInit_ex(context_->ctx, EVP_sha256(), nullptr) != 1) {
        EVP_MD_CTX_free(context_->ctx);
        throw core::Error("platform: SHA-256: OpenSSL could not start a digest");
    }
}

Sha256::~Sha256() { EVP_MD_CTX_free(context_->ctx); }

void Sha256::update(const void* data, std::size_t bytes) {
    if (bytes > 0 && EVP_DigestUpdate(context_->ctx, data, bytes) != 1)
        throw core::Error("platform: SHA-256: OpenSSL digest update failed");
}

std::string Sha256::hex() {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int length = 0;
    if (EVP_DigestFinal_ex(context_->ctx, digest, &length) != 1 || length != 32)
        throw core::Error("platform: SHA-256: OpenSSL digest failed");
    static const char* kDigits = "0123456789abcdef";
    std::string out;
    for (unsigned int i = 0; i < length; ++i) {
        out += kDigits[digest[i] >> 4];
        out += kDigits[digest[i] & 15];
    }
    return out;
}

std::string sha256Hex(std::string_view bytes) {
    Sha256 s;
    s.update(bytes);
    return s.hex();
}

FileDigest sha256File(const std::filesystem::path& file, std::string_view module) {
    const std::string head = std::string(module) + ": " + core::printable(file.string()) + ": cannot read: ";
    const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
    if (fd < 0) throw core::Error(head + std::strerror(errno));
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    FileDigest d;
    Sha256 s;
    std::vector<char> buffer(std::size_t(1) << 20);
    for (;;) {
        const ssize_t n = ::read(fd, buffer.data(), buffer.size());
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw core::Error(head + std::strerror(errno));
        if (n == 0) break;
        s.update(buffer.data(), std::size_t(n));
        d.bytes += std::uint64_t(n);
    }
    d.sha256 = s.hex();
    return d;
}

}  // namespace platform
