// detect/src/parts.hpp: work cut into parts that run on threads of their own.
#pragma once

#include <algorithm>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace detect {

/// Calls fn(part) for every part in [0, parts), part 0 on the calling thread and each
/// other on a thread of its own, and returns when all are done; the first exception
/// thrown by a part reaches the caller. Each part writes only to places of its own.
template <class Fn>
void runParts(std::size_t parts, const Fn& fn) {
    if (parts <= 1) {
        fn(std::size_t(0));
        return;
    }
    std::exception_ptr error;
    std::mutex mutex;
    const auto guarded = [&](std::size_t part) {
        try {
            fn(part);
        } catch (...) {
            const std::lock_guard<std::mutex> lock(mutex);
            if (!error) error = std::current_exception();
        }
    };
    std::vector<std::thread> pool;
    pool.reserve(parts - 1);
    for (std::size_t p = 1; p < parts; ++p) pool.emplace_back(guarded, p);
    guarded(0);
    for (std::thread& t : pool) t.join();
    if (error) std::rethrow_exception(error);
}

/// The first index of part `part` when `n` items are cut into `parts` even runs.
inline std::size_t partStart(std::size_t n, std::size_t parts, std::size_t part) {
    return n / parts * part + std::min(part, n % parts);
}

}  // namespace detect
