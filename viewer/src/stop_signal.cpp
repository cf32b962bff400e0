// viewer/src/stop_signal.cpp: the stop request flag and its handlers.
#include "stop_signal.hpp"

namespace viewer {

namespace {
volatile std::sig_atomic_t g_received = 0;
extern "C" void onStop(int sig) { g_received = sig; }

bool install(int sig, struct sigaction& old) {
    if (::sigaction(sig, nullptr, &old) != 0) return false;
    if (!(old.sa_flags & SA_SIGINFO) && old.sa_handler == SIG_IGN) return false;  // nohup
    struct sigaction sa{};
    sa.sa_handler = onStop;
    sigemptyset(&sa.sa_mask);
    return ::sigaction(sig, &sa, nullptr) == 0;
}
}  // namespace

StopSignal::StopSignal() {
    g_received = 0;
    int_installed_ = install(SIGINT, old_int_);
    term_installed_ = install(SIGTERM, old_term_);
}

StopSignal::~StopSignal() {
    if (int_installed_) ::sigaction(SIGINT, &old_int_, nullptr);
    if (term_installed_) ::sigaction(SIGTERM, &old_term_, nullptr);
}

int StopSignal::received() { return g_received; }

}  // namespace viewer
