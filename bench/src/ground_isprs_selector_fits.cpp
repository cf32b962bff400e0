// bench/src/ground_isprs_selector_fits.cpp: see ground_isprs_selector_fits.hpp. XGBoost's C
// API learns the trees (histogram method, a fixed seed, one thread: a few thousand rows at
// most); no model is kept.
#include "ground_isprs_selector_fits.hpp"

#include "common.hpp"
#include "ground_isprs_selector.hpp"
#include "xgboost_handles.hpp"

#include <core/error.hpp>
#include <core/point_cloud.hpp>
#include <sim/ground.hpp>
#include <sim/ground_file.hpp>

#include <xgboost/c_api.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

namespace bench {
namespace {

constexpr const char* kXgbContext = "bench ground-isprs --selector";

[[noreturn]] void xgbFail(const char* what) { xgboostFail(kXgbContext, what); }
#define LADARVR_SELECTOR_XGB(call, what) \
    do {                                 \
        if ((call) != 0) xgbFail(what);  \
    } while (false)

}  // namespace

std::string TreeShape::describe() const {
    const TreeShape d;
    if (max_depth == d.max_depth && rounds == d.rounds && min_child_weight == d.min_child_weight) return "";
    return ", depth " + std::to_string(max_depth) + ", " + std::to_string(rounds) + " rounds, min child weight " +
           fmt("%g", min_child_weight);
}

std::vector<float> learnAndPredict(const std::vector<float>& train, const std::vector<float>& labels,
                                   const std::vector<float>& weights, const std::vector<float>& test,
                                   std::size_t columns, int classes, const TreeShape& shape) {
    XgbMatrix m(train, columns, kXgbContext), t(test, columns, kXgbContext);
    LADARVR_SELECTOR_XGB(XGDMatrixSetFloatInfo(m.h, "label", labels.data(), bst_ulong(labels.size())), "labels");
    LADARVR_SELECTOR_XGB(XGDMatrixSetFloatInfo(m.h, "weight", weights.data(), bst_ulong(weights.size())), "weights");
    XgbBooster b;
    LADARVR_SELECTOR_XGB(XGBoosterCreate(&m.h, 1, &b.h), "create");
    std::vector<std::pair<const char*, std::string>> params = {
        {"tree_method", "hist"}, {"max_depth", std::to_string(shape.max_depth)},
        {"eta", "0.1"},          {"subsample", "0.8"},
        {"nthread", "1"},        {"min_child_weight", std::to_string(shape.min_child_weight)},
        {"seed", "1"},           {"verbosity", "0"},
    };
    if (classes == 2) {
        params.push_back({"objective", "binary:logistic"});
        params.push_back({"base_score", "0.5"});
    } else {
        params.push_back({"objective", "multi:softprob"});
        params.push_back({"num_class", std::to_string(classes)});
    }
    for (const auto& [key, value] : params)
        LADARVR_SELECTOR_XGB(XGBoosterSetParam(b.h, key, value.c_str()), "parameter");
    for (int round = 0; round < shape.rounds; ++round)
        LADARVR_SELECTOR_XGB(XGBoosterUpdateOneIter(b.h, round, m.h), "train");
    bst_ulong length = 0;
    const float* out = nullptr;
    LADARVR_SELECTOR_XGB(XGBoosterPredict(b.h, t.h, 0, 0, 0, &length, &out), "predict");
    return std::vector<float>(out, out + length);
}

SampleFits fitSample(const std::vector<core::CloudPoint>& points) {
    SampleFits f;
    const std::size_t n = points.size();
    for (const SelectorSet& s : selectorSets()) {
        sim::SmrfOptions o = sim::surveySmrfOptions();
        o.slope = s.slope, o.window_m = s.window_m, o.threshold_m = s.threshold_m, o.scalar = s.scalar;
        const std::unique_ptr<sim::TerrainFit> fit = sim::startSmrf(o);
        fit->add(points);
        fit->fit();
        f.ground.emplace_back(n);
        f.height_m.emplace_back(n);
        for (std::size_t i = 0; i < n; ++i) f.ground.back()[i] = fit->classify(points[i], f.height_m.back()[i]);
        if (f.ground.size() > 1) continue;
        const sim::TerrainGrid& g = fit->surface();
        for (const core::CloudPoint& p : points) {
            const double x = p.position.x, y = p.position.y, z = g.heightAt(x, y);
            const double around =
                (g.heightAt(x - 2, y) + g.heightAt(x + 2, y) + g.heightAt(x, y - 2) + g.heightAt(x, y + 2)) / 4.0;
            f.slope.push_back(float(g.slopeAt(x, y)));
            f.rough_m.push_back(float(std::abs(z - around)));
            f.terrain_m.push_back(float(z));
        }
    }
    double x0 = std::numeric_limits<double>::max(), y0 = x0;
    for (const core::CloudPoint& p : points)
        x0 = std::min(x0, double(p.position.x)), y0 = std::min(y0, double(p.position.y));
    for (const core::CloudPoint& p : points)
        f.cell.push_back((std::uint64_t(double(p.position.y) - y0) << 32) | std::uint64_t(double(p.position.x) - x0));
    std::vector<std::uint64_t> cells = f.cell;
    std::sort(cells.begin(), cells.end());
    const std::size_t occupied = std::size_t(std::unique(cells.begin(), cells.end()) - cells.begin());
    f.points_per_cell = occupied > 0 ? double(n) / double(occupied) : 0.0;
    return f;
}

Counts meanOf(const std::vector<Counts>& c) {
    Counts m;
    for (const Counts& x : c) {
        m.type1 += x.type1 / double(c.size());
        m.type2 += x.type2 / double(c.size());
        m.total += x.total / double(c.size());
        m.kappa += x.kappa / double(c.size());
    }
    return m;
}

std::string pastCsf(const std::vector<AdaptiveSample>& samples, const std::vector<Counts>& c) {
    std::string past;
    for (std::size_t k = 0; k < samples.size(); ++k)
        if (const double csf = csfPublishedTotal(samples[k].name); csf >= 0 && c[k].total > csf + 1.0)
            past += (past.empty() ? "" : " ") + samples[k].name.substr(4);
    return past.empty() ? "none" : past;
}

void printLine(const std::string& what, const std::vector<AdaptiveSample>& samples, const std::vector<Counts>& c) {
    const Counts m = meanOf(c);
    std::printf("| %s | %.2f | %.2f | %.2f | %.1f | %s |\n", what.c_str(), m.type1, m.type2, m.total, m.kappa,
                pastCsf(samples, c).c_str());
    std::fflush(stdout);
}

}  // namespace bench
