// viewer/src/points/point_budget.cpp: the default point budget by GPU class and the adaptive
// budget (point_budget.hpp).
#include <viewer/point_budget.hpp>

#include <algorithm>
#include <cassert>
#include <cctype>
#include <cmath>
#include <vector>

namespace viewer {

namespace {
std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}
bool has(const std::string& s, const char* word) { return s.find(word) != std::string::npos; }
}  // namespace

const char* gpuClassName(GpuClass c) {
    switch (c) {
        case GpuClass::Software: return "software";
        case GpuClass::Integrated: return "integrated";
        case GpuClass::Discrete: return "discrete";
        case GpuClass::Unknown: return "unknown";
    }
    return "?";
}

GpuClass classifyGpu(const std::string& gl_renderer, const std::string& gl_vendor) {
    const std::string r = lower(gl_renderer), v = lower(gl_vendor);
    if (has(r, "llvmpipe") || has(r, "softpipe") || has(r, "swrast") || has(r, "swiftshader") ||
        has(r, "software rasterizer") || has(r, "basic render"))
        return GpuClass::Software;
    if (has(v, "nvidia") || has(r, "nvidia") || has(r, "geforce") || has(r, "quadro")) return GpuClass::Discrete;
    const bool amd = has(v, "amd") || has(v, "ati technologies") || has(r, "radeon") || has(r, "amd");
    if (amd && (has(r, "radeon rx") || has(r, "radeon pro") || has(r, "firepro") || has(r, "radeon vii")))
        return GpuClass::Discrete;
    if (amd || has(v, "intel") || has(r, "intel") || has(v, "apple") || has(r, "apple") || has(r, "mali") ||
        has(r, "adreno") || has(r, "v3d") || has(r, "powervr"))
        return GpuClass::Integrated;
    return GpuClass::Unknown;
}

std::size_t defaultPointBudget(GpuClass c) {
    switch (c) {
        case GpuClass::Discrete: return 6000000;
        case GpuClass::Integrated: return 1000000;
        case GpuClass::Software:
        case GpuClass::Unknown: return 3000000;
    }
    return 3000000;
}

bool computeRasterizerByDefault(GpuClass c) { return c == GpuClass::Discrete; }

std::size_t adaptiveFloor(std::size_t ceiling) { return std::min(ceiling, std::max<std::size_t>(ceiling / 8, 100000)); }

AdaptiveBudget::AdaptiveBudget(std::size_t floor, std::size_t ceiling)
    : floor_(floor), ceiling_(ceiling), budget_(ceiling) {
    assert(floor > 0 && floor <= ceiling);
}

std::size_t AdaptiveBudget::update(double frame_cost_ms, double frame_budget_ms) {
    if (!(frame_budget_ms > 0.0) || !std::isfinite(frame_cost_ms) || frame_cost_ms < 0.0) return budget_;
    if (settle_ > 0) {
        --settle_;
        return budget_;
    }
    const double load = frame_cost_ms / frame_budget_ms;
    std::size_t next = budget_;
    if (load > kLowerAbove) {
        cool_frames_ = 0;
        next = std::max(floor_, static_cast<std::size_t>(std::llround(double(budget_) * kDrop)));
    } else if (load < kRaiseBelow) {
        if (++cool_frames_ >= kRaiseAfter) {
            cool_frames_ = 0;
            next = std::min(ceiling_, static_cast<std::size_t>(std::llround(double(budget_) * kRaise)));
        }
    } else {
        cool_frames_ = 0;
    }
    if (next != budget_) settle_ = kSettle;
    budget_ = next;
    return budget_;
}

namespace {
double medianOf(std::vector<double> v) {
    if (v.empty()) return 0.0;
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}
Rasterizer other(Rasterizer r) { return r == Rasterizer::Points ? Rasterizer::Compute : Rasterizer::Points; }
}  // namespace

BudgetMeasure::BudgetMeasure(Rasterizer first, bool both) : first_(first), both_(both) {}

Rasterizer BudgetMeasure::rasterizer() const { return phase_ == 1 ? other(first_) : first_; }

bool BudgetMeasure::done() const { return phase_ == 2; }

void BudgetMeasure::add(std::size_t points_drawn, double cost_ms) {
    if (done() || points_drawn == 0 || !std::isfinite(cost_ms) || cost_ms < 0.0) return;
    if (++seen_ > kSettle) {
        Samples& s = samples_[static_cast<int>(rasterizer())];
        s.points.push_back(double(points_drawn));
        s.cost_ms.push_back(cost_ms);
    }
    if (seen_ >= kSettle + kFrames) {
        seen_ = 0;
        phase_ = phase_ == 0 && both_ ? 1 : 2;
    }
}

BudgetMeasure::Choice BudgetMeasure::choice(double frame_budget_ms) const {
    assert(done() && frame_budget_ms > 0.0);
    Choice c;
    double best = -1.0;
    for (int r = 0; r < 2; ++r) {
        const Samples& s = samples_[r];
        if (s.points.empty()) continue;
        const double points = medianOf(s.points);
        const double ms_per_point = std::max(medianOf(s.cost_ms), 1e-6) / std::max(points, 1.0);
        c.ms_per_million[r] = ms_per_point * 1e6;
        if (best < 0.0 || ms_per_point < best) {
            best = ms_per_point;
            c.rasterizer = static_cast<Rasterizer>(r);
        }
    }
    const double per_eye = best > 0.0 ? kShare * frame_budget_ms / best / 2.0 : double(kMostBudget);
    const auto rounded = static_cast<std::size_t>(std::floor(per_eye / 1000.0)) * 1000;
    c.point_budget = std::clamp(rounded, kLeastBudget, kMostBudget);
    return c;
}

}  // namespace viewer
