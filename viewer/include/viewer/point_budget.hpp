// viewer/point_budget.hpp: how many points a frame may draw per eye: the default chosen
// from the GPU class (the GL_RENDERER / GL_VENDOR strings) and the adaptive budget that
// follows the frame time (Valve's adaptive quality in The Lab: raise quality while the
// frame's CPU + GPU time stays under 70 % of the frame budget, lower it over 90 %).
// BudgetMeasure chooses both from the frame times of the viewer's first frames instead.
// Pure: strings and frame times in, budgets out; the frame loop measures and applies.
#pragma once
#include <viewer/viewer.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace viewer {

/// The GPU classes the default point budget knows.
enum class GpuClass { Software, Integrated, Discrete, Unknown };
const char* gpuClassName(GpuClass c);

/// The class of the GPU a GL context runs on, from its GL_RENDERER and GL_VENDOR strings:
/// llvmpipe, softpipe, SwiftShader and the like are Software; NVIDIA and AMD's Radeon
/// RX / Pro / FirePro cards are Discrete; Intel, other AMD (APUs), Apple, ARM Mali,
/// Qualcomm Adreno, Broadcom and Imagination are Integrated; anything else Unknown.
GpuClass classifyGpu(const std::string& gl_renderer, const std::string& gl_vendor);

/// The point budget per eye for a GPU class when the user gave none: Software and Unknown
/// keep 3 M (the paper's 1.6 M point cloud stays whole, as before this choice existed),
/// Discrete 6 M (a stereo frame of 2 x 6 M points within a 90 Hz frame), Integrated 1 M
/// (Potree's default budget).
std::size_t defaultPointBudget(GpuClass c);

/// Whether the viewer draws points with its compute rasteriser when the user chose none:
/// on Discrete GPUs (measured faster wherever the cloud fills much of the view, several
/// times over at millions of points; BENCHMARKS.md), GL_POINTS elsewhere.
bool computeRasterizerByDefault(GpuClass c);

/// The adaptive point budget: fed each frame's cost (CPU + GPU time spent on it) and the
/// frame budget (the display period), it returns the budget for the next frame, between
/// `floor` and `ceiling` (the user's --point-budget). Over 90 % of the frame budget it
/// lowers the budget at once by kDrop (the next frames must not miss too); under 70 % for
/// kRaiseAfter frames in a row it raises it by kRaise (slowly: a raise that overshoots
/// costs a late frame). After a change it waits kSettle frames before judging again, the
/// frames already in flight having been drawn with the old budget. Deterministic: the
/// same frame times give the same budgets.
class AdaptiveBudget {
  public:
    static constexpr double kLowerAbove = 0.9, kRaiseBelow = 0.7;
    static constexpr double kDrop = 0.8, kRaise = 1.1;
    static constexpr int kRaiseAfter = 4, kSettle = 2;
    /// Starts at `ceiling`; needs 0 < floor <= ceiling (an unlimited budget is not adapted).
    AdaptiveBudget(std::size_t floor, std::size_t ceiling);
    /// One frame: its cost and the frame budget, both in ms (a budget <= 0 changes
    /// nothing). Returns the budget for the next frame.
    std::size_t update(double frame_cost_ms, double frame_budget_ms);
    std::size_t budget() const { return budget_; }
    std::size_t floor() const { return floor_; }
    std::size_t ceiling() const { return ceiling_; }

  private:
    std::size_t floor_, ceiling_, budget_;
    int cool_frames_ = 0;  // under 70 % in a row
    int settle_ = 0;       // frames to wait after a change
};

/// The floor of the adaptive budget under a ceiling of `ceiling` points: an eighth of it,
/// not under 100 000 points (a cloud still legible), never over the ceiling itself.
std::size_t adaptiveFloor(std::size_t ceiling);

/// The default point budget and rasterizer from measurement: the first counted frames that
/// draw points are drawn kFrames with one rasterizer, then (when both are to be compared)
/// kFrames with the other, the first kSettle after each start not judged; each rasterizer's
/// cost per point is the median frame cost over the median points drawn. The faster per
/// point is chosen, and the budget per eye is the points both eyes draw within kShare of
/// the frame budget at its rate, between kLeastBudget and kMostBudget. Deterministic: the
/// same frames give the same choice.
class BudgetMeasure {
  public:
    static constexpr int kFrames = 20, kSettle = 4;
    static constexpr double kShare = 0.7;
    static constexpr std::size_t kLeastBudget = 100000, kMostBudget = 12000000;
    /// Measures `first`, then the other rasterizer too when `both`.
    BudgetMeasure(Rasterizer first, bool both);
    /// The rasterizer the next frame draws with.
    Rasterizer rasterizer() const;
    /// One counted frame drawn with rasterizer(): the points both eyes drew and its cost
    /// (ms); a frame that drew nothing is not counted.
    void add(std::size_t points_drawn, double cost_ms);
    bool done() const;
    struct Choice {
        Rasterizer rasterizer = Rasterizer::Points;
        std::size_t point_budget = 0;             // per eye
        double ms_per_million[2] = {-1.0, -1.0};  // Points, Compute; -1: not measured
    };
    /// The choice for a frame budget of `frame_budget_ms` (> 0); needs done().
    Choice choice(double frame_budget_ms) const;

  private:
    struct Samples {
        std::vector<double> points, cost_ms;
    };
    Rasterizer first_;
    bool both_;
    int phase_ = 0;  // 0: first, 1: second, 2: done
    int seen_ = 0;   // frames with points in this phase, judged or not
    Samples samples_[2];
};

}  // namespace viewer
