// viewer/src/run_log.hpp: the machine-readable record of one viewer run (--log-json).
//
// Tests assert on it: session states reached, frames submitted, per-frame eye poses
// (the runtime's, in its reference space, and the world eye positions after the mode's
// rig), mode switches, the fallback reason. Written atomically at the end of the run.
#pragma once
#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

namespace viewer {

/// The process's peak resident set (VmHWM in /proc/self/status), bytes; none where the
/// file or the line is missing. Reads at most 64 KiB. Never throws.
std::optional<std::size_t> peakResidentBytes();

class RunLog {
  public:
    /// Appends a session state name ("IDLE", "READY", ...) in the order reached.
    void state(const std::string& name) { json_["states"].push_back(name); }
    /// A free-form event line ("xr: session lost", "mode: free (key)").
    void event(const std::string& text) { json_["events"].push_back(text); }
    /// Sets a top-level key.
    template <class T>
    void set(const std::string& key, const T& value) {
        json_[key] = value;
    }
    /// Appends one frame record (only the first `max_frames` are kept, to bound the size).
    void frame(nlohmann::json record);
    void modeSwitch(long frame_index, const std::string& from, const std::string& to, const std::string& source);
    /// Writes the JSON atomically (platform::writeFileAtomic); never throws, reports failures.
    bool write(const std::filesystem::path& path) const;
    const nlohmann::json& json() const { return json_; }

    static constexpr std::size_t kMaxFrames = 20000;

  private:
    nlohmann::json json_ = {{"states", nlohmann::json::array()},
                            {"events", nlohmann::json::array()},
                            {"frames", nlohmann::json::array()},
                            {"mode_switches", nlohmann::json::array()}};
};

}  // namespace viewer
