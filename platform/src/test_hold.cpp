// platform/src/test_hold.cpp: the FIFO handshake of the test hooks.
#include <platform/test_hold.hpp>

#include <core/error.hpp>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace platform {

void holdOnFifo(const std::string& fifo, const std::string& line, std::string_view hook, std::string_view allowed) {
    struct stat st{};
    if (::stat(fifo.c_str(), &st) != 0 || !S_ISFIFO(st.st_mode))
        throw core::Error(std::string(hook) + ": '" + core::printable(fifo) + "' is not a FIFO; allowed " +
                          std::string(allowed) + " (a test hook)");
    int fd = ::open(fifo.c_str(), O_WRONLY | O_CLOEXEC);  // waits for the test to listen
    if (fd >= 0) {
        [[maybe_unused]] const ssize_t wrote = ::write(fd, line.data(), line.size());
        ::close(fd);
    }
    fd = ::open(fifo.c_str(), O_RDONLY | O_CLOEXEC);  // waits for the test to release it
    if (fd >= 0) {
        char buffer[64];
        while (::read(fd, buffer, sizeof buffer) > 0) {}
        ::close(fd);
    }
}

}  // namespace platform
