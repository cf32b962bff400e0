// Progress: draws on stderr only when asked (or a tty), ends at 100 %.
#include <platform/progress.hpp>

#include <doctest/doctest.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include <fcntl.h>
#include <unistd.h>

namespace {

// Runs `fn` with stderr redirected to a file and returns what was written.
template <typename Fn>
std::string captureStderr(Fn fn) {
    const std::string path = "/tmp/ladarvr_progress_test_" + std::to_string(::getpid());
    std::fflush(stderr);
    const int saved = ::dup(STDERR_FILENO);
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    ::dup2(fd, STDERR_FILENO);
    ::close(fd);
    fn();
    std::fflush(stderr);
    ::dup2(saved, STDERR_FILENO);
    ::close(saved);
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    std::remove(path.c_str());
    return s.str();
}

}  // namespace

TEST_CASE("progress: forced bar reaches 100 % with its label, silent when not a tty") {
    const std::string drawn = captureStderr([] {
        platform::Progress p("ray cast", 10, true);
        for (int i = 0; i < 10; ++i) p.advance();
        p.finish();
        p.finish();  // idempotent
    });
    CHECK(drawn.find("ray cast [") != std::string::npos);
    CHECK(drawn.find("100%") != std::string::npos);
    CHECK(drawn.back() == '\n');
    CHECK(drawn.find("100%", drawn.find("100%") + 1) == std::string::npos);  // one final line

    const std::string silent = captureStderr([] {
        platform::Progress p("quiet", 5);  // stderr is a file here, not a terminal
        p.advance(5);
    });
    CHECK(silent.empty());
}

TEST_CASE("progress: work that throws ends the bar's line where it stopped, not at 100 %") {
    const std::string drawn = captureStderr([] {
        try {
            platform::Progress p("decode", 10, true);
            p.advance(4);
            throw std::runtime_error("damaged");
        } catch (const std::runtime_error&) {}
    });
    CHECK(drawn.find("decode [") != std::string::npos);
    CHECK(drawn.find("100%") == std::string::npos);
    CHECK(drawn.find(" 40%") != std::string::npos);
    CHECK(drawn.back() == '\n');  // the error line that follows starts a line of its own
}
