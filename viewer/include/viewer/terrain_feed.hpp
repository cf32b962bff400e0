// viewer/terrain_feed.hpp: a terrain surface handed to the viewer while it runs, so that
// `--colour above-ground` shows the height above the ground of any cloud: one whose
// producer classified its ground (LAS class 2) or one whose terrain is fitted in the
// background after the window opens. The producer (the `view` command) publishes once
// from any thread; the frame loop takes it once, when it is there.
#pragma once
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace viewer {

/// Ground heights on a regular grid in the cloud's world coordinates (the file's own
/// coordinates, before the point source's origin is taken off): cell (i, j) has its centre
/// at (x0 + i * cell, y0 + j * cell) and height z[j * nx + i]. Every cell has a height.
struct ViewTerrain {
    double x0 = 0.0, y0 = 0.0, cell = 1.0;
    int nx = 0, ny = 0;
    std::vector<float> z;
    /// Where it came from, for the run log and the panel ("the file's class 2",
    /// "a terrain fitted by SMRF on 1,000,000 of its points").
    std::string source;

    bool empty() const { return nx <= 0 || ny <= 0 || z.size() != std::size_t(nx) * std::size_t(ny); }
};

/// One terrain, published once by a producer thread and taken once by the frame loop;
/// or a reason why there is none.
class TerrainFeed {
  public:
    void publish(ViewTerrain terrain) {
        std::lock_guard lock(mutex_);
        terrain_ = std::move(terrain);
        done_ = true;
    }
    /// No terrain will come; `why` is said once in the run log and on stderr.
    void fail(std::string why) {
        std::lock_guard lock(mutex_);
        failure_ = std::move(why);
        done_ = true;
    }
    /// The terrain the first time it is asked for after publish(); empty before and after.
    std::optional<ViewTerrain> take() {
        std::lock_guard lock(mutex_);
        return std::exchange(terrain_, std::nullopt);
    }
    /// The failure's reason the first time it is asked for after fail(); empty otherwise.
    std::optional<std::string> takeFailure() {
        std::lock_guard lock(mutex_);
        return std::exchange(failure_, std::nullopt);
    }
    /// True once publish() or fail() was called.
    bool done() const {
        std::lock_guard lock(mutex_);
        return done_;
    }

  private:
    mutable std::mutex mutex_;
    std::optional<ViewTerrain> terrain_;
    std::optional<std::string> failure_;
    bool done_ = false;
};

}  // namespace viewer
