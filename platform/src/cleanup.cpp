// cleanup: a lock-free table of the temporaries this process holds, emptied by the
// signal handlers (see platform/cleanup.hpp for the contract).
#include <platform/cleanup.hpp>

#include <array>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <fcntl.h>
#include <unistd.h>

namespace platform {
namespace {

// A slot is free (0), being filled (1), holding a temporary (2) or claimed by the
// remover (3, for good: the process is about to end). Only the owner moves 0->1->2 and
// 2->0; the remover moves 2->3, so it never reads a name that is being rewritten.
enum : int { kFree = 0, kFilling = 1, kHeld = 2, kClaimed = 3 };

struct Slot {
    std::atomic<int> state{kFree};
    int dirfd = -1;
    bool is_dir = false;
    char name[128] = {};
};

constexpr std::size_t kSlots = 256;
std::array<Slot, kSlots> g_slots;
static_assert(std::atomic<int>::is_always_lock_free, "signal handlers need lock-free atomics");

void removePass(bool dirs) noexcept {
    for (Slot& s : g_slots) {
        if (s.state.load(std::memory_order_acquire) != kHeld || s.is_dir != dirs) continue;
        int expected = kHeld;
        if (!s.state.compare_exchange_strong(expected, kClaimed, std::memory_order_acq_rel)) continue;
        ::unlinkat(s.dirfd, s.name, dirs ? AT_REMOVEDIR : 0);
    }
}

extern "C" void onStopSignal(int sig) {
    const int saved_errno = errno;
    removeTemporariesNow();
    std::signal(sig, SIG_DFL);
    errno = saved_errno;
    std::raise(sig);  // delivered with the default action when the handler returns
}

// Checked at every registration (three cheap system calls), so a process that reset a
// signal to its default since, e.g. a forked child, gets the handler again.
void installHandlers() noexcept {
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
        struct sigaction old{};
        if (::sigaction(sig, nullptr, &old) != 0) continue;
        if ((old.sa_flags & SA_SIGINFO) || old.sa_handler != SIG_DFL)
            continue;  // ignored (nohup),
                       // ours or someone else's
        struct sigaction sa{};
        sa.sa_handler = onStopSignal;
        sigemptyset(&sa.sa_mask);
        for (int other : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&sa.sa_mask, other);
        ::sigaction(sig, &sa, nullptr);
    }
}

}  // namespace

void removeTemporariesNow() noexcept {
    removePass(false);
    removePass(true);
}

namespace detail {

int registerTemporary(int dirfd, const char* name, bool is_dir) noexcept {
    static const bool at_exit = std::atexit([] { removeTemporariesNow(); }) == 0;
    (void)at_exit;
    installHandlers();
    if (std::strlen(name) >= sizeof(Slot::name)) return -1;
    for (std::size_t i = 0; i < kSlots; ++i) {
        Slot& s = g_slots[i];
        int expected = kFree;
        if (!s.state.compare_exchange_strong(expected, kFilling, std::memory_order_acq_rel)) continue;
        s.dirfd = dirfd;
        s.is_dir = is_dir;
        std::strcpy(s.name, name);
        s.state.store(kHeld, std::memory_order_release);
        return int(i);
    }
    return -1;
}

void unregisterTemporary(int slot) noexcept {
    if (slot < 0 || std::size_t(slot) >= kSlots) return;
    int expected = kHeld;
    g_slots[std::size_t(slot)].state.compare_exchange_strong(expected, kFree, std::memory_order_acq_rel);
}

}  // namespace detail

Watchdog::Watchdog(double seconds, std::string message, int exit_code) {
    if (!(seconds > 0.0) || seconds > 1e9) return;  // 1e9 s: longer than any run; avoids overflow
    const auto deadline =
        std::chrono::steady_clock::now() +
        std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(seconds));
    thread_ = std::thread([this, deadline, message = std::move(message), exit_code] {
        std::unique_lock lock(mutex_);
        if (wake_.wait_until(lock, deadline, [this] { return cancelled_; })) return;
        const std::string line = "ladarvr: error: " + message + "\n";
        // write(2), not stdio: another thread may hold stderr's lock forever.
        [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, line.data(), line.size());
        removeTemporariesNow();
        ::_exit(exit_code);
    });
}

Watchdog::~Watchdog() {
    if (!thread_.joinable()) return;
    {
        std::lock_guard lock(mutex_);
        cancelled_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

}  // namespace platform
