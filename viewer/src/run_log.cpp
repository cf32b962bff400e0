// viewer/src/run_log.cpp
#include "run_log.hpp"

#include <platform/atomic_file.hpp>

#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <vector>

namespace viewer {

std::optional<std::size_t> peakResidentBytes() {
    std::ifstream in("/proc/self/status", std::ios::binary);
    if (!in) return std::nullopt;
    std::vector<char> text(65536);
    in.read(text.data(), static_cast<std::streamsize>(text.size() - 1));
    text[static_cast<std::size_t>(in.gcount())] = '\0';
    const char* at = std::strstr(text.data(), "\nVmHWM:");
    unsigned long long kib = 0;
    if (!at || std::sscanf(at + 7, " %llu kB", &kib) != 1) return std::nullopt;
    return static_cast<std::size_t>(kib) * 1024;
}

void RunLog::frame(nlohmann::json record) {
    auto& frames = json_["frames"];
    if (frames.size() < kMaxFrames) frames.push_back(std::move(record));
}

void RunLog::modeSwitch(long frame_index, const std::string& from, const std::string& to, const std::string& source) {
    json_["mode_switches"].push_back({{"frame", frame_index}, {"from", from}, {"to", to}, {"source", source}});
}

bool RunLog::write(const std::filesystem::path& path) const {
    try {
        platform::writeFileAtomic(path, json_.dump(1) + "\n");
        return true;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ladarvr: view: --log-json: %s\n", e.what());
        return false;
    }
}

}  // namespace viewer
