// tests/platform/test_hold_test.cpp: the FIFO handshake that holds a run for a test: the
// line arrives, the hold lasts until the FIFO is opened for writing and closed, and a
// path that is not a FIFO is refused in one line.
#include <test_files.hpp>
#include <platform/test_hold.hpp>

#include <doctest/doctest.h>

#include <sys/stat.h>

#include <atomic>
#include <fstream>
#include <string>
#include <thread>

TEST_CASE("test hold: the line is told, and the hold lasts until the FIFO is released") {
    test_support::TempDir dir("test_hold");
    const std::string fifo = (dir.path / "hold").string();
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    std::atomic<bool> returned{false};
    std::thread run([&] {
        platform::holdOnFifo(fifo, "held x\n", "HOOK", "a FIFO");
        returned = true;
    });
    std::string line;
    {
        std::ifstream told(fifo);  // opens once the run writes
        std::getline(told, line);
    }
    CHECK(line == "held x");
    // The run now waits for a writer to come and go: it cannot have returned before that.
    CHECK_FALSE(returned.load());
    { std::ofstream release(fifo); }
    run.join();
    CHECK(returned.load());
}

TEST_CASE("test hold: a path that is not a FIFO is refused in one line") {
    test_support::TempDir dir("test_hold_refused");
    const auto file = dir.write("plain", "x");
    CHECK(test_support::errorOf([&] { platform::holdOnFifo(file.string(), "held\n", "HOOK", "<index>:<a FIFO>"); }) ==
          "HOOK: '" + file.string() + "' is not a FIFO; allowed <index>:<a FIFO> (a test hook)");
    CHECK(test_support::errorOf([&] {
              platform::holdOnFifo((dir.path / "absent").string(), "held\n", "HOOK", "a FIFO");
          }).find("is not a FIFO; allowed a FIFO") != std::string::npos);
}
