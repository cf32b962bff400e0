// viewer/src/run_log.cpp
#include "run_log.hpp"

#include <platform/atomic_file.hpp>

#include <cstdio>
#include <exception>

namespace viewer {

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
