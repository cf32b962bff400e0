// sim/src/ground_learned.cpp: see sim/ground_learned.hpp. Pass 1 gives every point to
// SMRF's fit (with its variants' terrains, ground_learned_terrains.hpp) and to a sparse
// raster of per-cell statistics (lowest, highest, count, sum and sum of squares of the
// heights); fit() makes SMRF's terrains and, per cell, the neighbourhood measures the
// features read; classify() reads a point's features from those rasters (no search
// among the points) and sums the trees' leaves.
#include "ground_learned_terrains.hpp"
#include "ground_raster.hpp"

#include <sim/ground_learned.hpp>

#include <core/error.hpp>
#include <platform/safe_file.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <unordered_map>

namespace sim {
namespace {

// The other SMRF settings whose terrains the features compare a point with: a wider
// window (larger objects removed), a gentler slope (more removed) and a steeper slope
// with a narrower window (less removed). Their object sets nest around SMRF's own.
const std::vector<SmrfVariant>& variants() {
    static const std::vector<SmrfVariant> v = {{0.15, 36.0}, {0.08, 18.0}, {0.3, 10.0}};
    return v;
}

// Neighbourhood radii, metres, of the "above the lowest point within" features.
constexpr double kLowestRadii_m[] = {2.0, 5.0, 10.0, 20.0};

const char* const kFeatures[] = {
    "height_smrf",         // z - SMRF's terrain
    "smrf_ground",         // SMRF's answer (0 / 1)
    "beyond_limit",        // |height_smrf| - SMRF's tolerance at the point
    "height_wide",         // z - the terrain of a 36 m window
    "height_gentle",       // z - the terrain of slope 0.08
    "height_steep",        // z - the terrain of slope 0.3, window 10 m
    "terrain_slope",       // SMRF's terrain's gradient (rise over run)
    "curvature_1m",        // its Laplacian over 1 cell (1/m)
    "curvature_5m",        // over 5 cells
    "above_lowest_2m",     // z - the lowest point within 2 m (square)
    "above_lowest_5m",     //
    "above_lowest_10m",    //
    "above_lowest_20m",    //
    "above_cell_lowest",   // z - the lowest point of its cell
    "below_cell_highest",  // the highest point of its cell - z
    "roughness_3m",        // spread (sd) of the heights of the points in the 3 x 3 cells
    "above_mean_3m",       // z - their mean
    "above_median_5m",     // z - the median of the cells' lowest points in the 5 x 5 cells
    "below_highest_5m",    // the highest point in the 5 x 5 cells - z
    "gaps_5m",             // share of the 5 x 5 cells without a point
    "density_ratio",       // points in the 5 x 5 cells / the median over the cloud's cells
};
constexpr std::size_t kFeatureCount = sizeof(kFeatures) / sizeof(kFeatures[0]);

struct CellStat {
    float low = kNoPoint, high = -kNoPoint;
    std::uint32_t n = 0;
    double sum = 0, sum2 = 0;
};

// Per-cell statistics of every point, in sparse tiles (only the tiles points fell in).
class CellStats {
  public:
    CellStats(double cell_m, std::size_t max_cells) : inv_cell_(1.0 / cell_m), max_cells_(max_cells) {}
    void add(std::span<const core::CloudPoint> points) {
        for (const core::CloudPoint& p : points) {
            const double fx = std::floor(double(p.position.x) * inv_cell_);
            const double fy = std::floor(double(p.position.y) * inv_cell_);
            if (!(std::abs(fx) < 1e9 && std::abs(fy) < 1e9) || !std::isfinite(p.position.z)) continue;
            const int ix = int(fx), iy = int(fy);
            CellStat& c = tile(ix >> kBits, iy >> kBits)[((iy & (kTile - 1)) << kBits) | (ix & (kTile - 1))];
            const float z = p.position.z;
            c.low = std::min(c.low, z);
            c.high = std::max(c.high, z);
            ++c.n;
            c.sum += z;
            c.sum2 += double(z) * z;
        }
    }
    // The cell (ix, iy) (absolute indices), or an empty one.
    const CellStat& at(int ix, int iy) const {
        static const CellStat kEmpty{};
        const auto it = tiles_.find(key(ix >> kBits, iy >> kBits));
        if (it == tiles_.end()) return kEmpty;
        return data_[std::size_t(it->second) * kTile * kTile +
                     std::size_t(((iy & (kTile - 1)) << kBits) | (ix & (kTile - 1)))];
    }
    void clear() {
        tiles_ = {};
        data_ = {};
    }

  private:
    static constexpr int kBits = 5, kTile = 1 << kBits;
    static std::uint64_t key(int tx, int ty) { return (std::uint64_t(std::uint32_t(tx)) << 32) | std::uint32_t(ty); }
    CellStat* tile(int tx, int ty) {
        const std::uint64_t k = key(tx, ty);
        if (k == last_key_ && last_ != nullptr) return last_;
        auto [it, added] = tiles_.try_emplace(k, std::uint32_t(tiles_.size()));
        if (added) {
            if (std::uint64_t(tiles_.size()) * kTile * kTile > 4 * std::uint64_t(max_cells_) + kTile * kTile)
                throw core::Error("ground: learned: the cloud covers more than " + std::to_string(max_cells_) +
                                  " cells of --smrf-cell-m; allowed at most that many (raise --memory-mb)");
            data_.resize(data_.size() + kTile * kTile);
        }
        last_key_ = k;
        last_ = data_.data() + std::size_t(it->second) * kTile * kTile;
        return last_;
    }
    double inv_cell_;
    std::size_t max_cells_;
    std::unordered_map<std::uint64_t, std::uint32_t> tiles_;
    std::vector<CellStat> data_;
    std::uint64_t last_key_ = 0;
    CellStat* last_ = nullptr;
};

// Running minimum (or maximum) over [i - r, i + r] along rows (step 1) or columns (step
// w) of a w x h raster, in place: each line copied out, its running extreme taken
// (sim::runningExtreme) and copied back.
void extremeAlong(std::vector<float>& v, int w, int h, int r, bool rows, bool take_max) {
    const int n = rows ? w : h, lines = rows ? h : w;
    const std::size_t step = rows ? 1 : std::size_t(w);
    std::vector<float> line(static_cast<std::size_t>(n)), out(static_cast<std::size_t>(n)), scratch;
    for (int l = 0; l < lines; ++l) {
        const std::size_t base = rows ? std::size_t(l) * std::size_t(w) : std::size_t(l);
        for (int i = 0; i < n; ++i) line[std::size_t(i)] = v[base + std::size_t(i) * step];
        sim::runningExtreme(line.data(), out.data(), n, r, take_max, scratch);
        for (int i = 0; i < n; ++i) v[base + std::size_t(i) * step] = out[std::size_t(i)];
    }
}

void squareExtreme(std::vector<float>& v, int w, int h, int r, bool take_max) {
    extremeAlong(v, w, h, r, true, take_max);
    extremeAlong(v, w, h, r, false, take_max);
}

// Box sums over the (2r + 1)^2 cells around each cell (clipped at the edges).
std::vector<double> boxSum(const std::vector<double>& v, int w, int h, int r) {
    std::vector<double> rows(v.size(), 0.0), out(v.size(), 0.0);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            double s = 0;
            for (int d = std::max(0, i - r); d <= std::min(w - 1, i + r); ++d) s += v[std::size_t(j) * w + d];
            rows[std::size_t(j) * w + i] = s;
        }
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            double s = 0;
            for (int d = std::max(0, j - r); d <= std::min(h - 1, j + r); ++d) s += rows[std::size_t(d) * w + i];
            out[std::size_t(j) * w + i] = s;
        }
    return out;
}

// The per-cell measures the features read, on SMRF's grid.
struct CellFeatures {
    std::vector<float> low, high, mean3, sd3, median5, high5, gaps5, density, curv1, curv5;
    std::vector<std::vector<float>> lowest;  // per kLowestRadii_m
};

double bilinear(const TerrainGrid& g, double x, double y) { return g.heightAt(x, y); }

class LearnedFit final : public TerrainFit {
  public:
    LearnedFit(const SmrfOptions& o, std::shared_ptr<const GroundModel> model, double confidence)
        : smrf_(startSmrfTerrains(o, variants())),
          stats_(o.cell_m, o.max_cells),
          model_(std::move(model)),
          confidence_(confidence) {}

    void add(std::span<const core::CloudPoint> points) override {
        smrf_->add(points);
        stats_.add(points);
    }
    void addAll(std::span<const core::CloudPoint> points, int threads) override {
        smrf_->addAll(points, threads);
        stats_.add(points);
    }
    void setFitThreads(int threads) override { smrf_->setFitThreads(threads); }
    void thicknessSamples(const glm::dvec2& lo, const glm::dvec2& hi, std::vector<double>& out) const override {
        smrf_->thicknessSamples(lo, hi, out);
    }
    void setGroundThickness(double sigma_m) override { smrf_->setGroundThickness(sigma_m); }
    void fit() override;
    const TerrainGrid& surface() const override { return smrf_->surface(); }
    bool classify(const glm::vec3& p, float& height_m) const override {
        core::CloudPoint q;
        q.position = p;
        return classify(q, height_m);
    }
    bool classify(const core::CloudPoint& p, float& height_m) const override {
        float row[kFeatureCount];
        const bool smrf_ground = features(p, row);
        height_m = row[0];
        if (!model_) return smrf_ground;
        const double margin = model_->margin(row);
        const bool trees = margin > 0.0;
        return trees != smrf_ground && std::abs(margin) > confidence_ ? trees : smrf_ground;
    }
    /// The point's feature row; returns SMRF's answer.
    bool features(const core::CloudPoint& p, float* row) const;

  private:
    std::unique_ptr<SmrfTerrains> smrf_;
    CellStats stats_;
    std::shared_ptr<const GroundModel> model_;
    double confidence_;
    CellFeatures f_;
};

void LearnedFit::fit() {
    smrf_->fit();
    const TerrainGrid& g = smrf_->surface();
    f_ = CellFeatures{};
    if (g.empty()) return;
    const int w = g.nx, h = g.ny;
    const std::size_t n = std::size_t(w) * std::size_t(h);
    const int ix0 = int(std::lround(g.x0_m / g.cell_m - 0.5)), iy0 = int(std::lround(g.y0_m / g.cell_m - 0.5));
    f_.low.assign(n, kNoPoint);
    f_.high.assign(n, -kNoPoint);
    std::vector<double> count(n), sum(n), sum2(n), observed(n);
    std::vector<std::uint32_t> counts;
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const std::size_t c = std::size_t(j) * std::size_t(w) + std::size_t(i);
            const CellStat& s = stats_.at(ix0 + i, iy0 + j);
            if (s.n == 0) continue;
            f_.low[c] = s.low;
            f_.high[c] = s.high;
            count[c] = s.n;
            sum[c] = s.sum;
            sum2[c] = s.sum2;
            observed[c] = 1;
            counts.push_back(s.n);
        }
    stats_.clear();
    const std::vector<double> n3 = boxSum(count, w, h, 1), s3 = boxSum(sum, w, h, 1), q3 = boxSum(sum2, w, h, 1);
    const std::vector<double> n5 = boxSum(count, w, h, 2), o5 = boxSum(observed, w, h, 2);
    std::nth_element(counts.begin(), counts.begin() + std::ptrdiff_t(counts.size() / 2), counts.end());
    const double median_count = counts.empty() ? 1.0 : std::max(1.0, double(counts[counts.size() / 2]));
    f_.mean3.resize(n);
    f_.sd3.resize(n);
    f_.gaps5.resize(n);
    f_.density.resize(n);
    for (std::size_t c = 0; c < n; ++c) {
        const double m = n3[c] > 0 ? s3[c] / n3[c] : double(g.z_m[c]);
        f_.mean3[c] = float(m);
        f_.sd3[c] = n3[c] > 1 ? float(std::sqrt(std::max(0.0, q3[c] / n3[c] - m * m))) : 0.0f;
        f_.gaps5[c] = float(1.0 - o5[c] / 25.0);
        f_.density[c] = float(n5[c] / (25.0 * median_count));
    }
    // The lowest points within each radius, and the highest within 2 cells.
    const std::vector<float>& levels = smrf_->levels();
    for (const double r_m : kLowestRadii_m) {
        std::vector<float> v = f_.low;
        squareExtreme(v, w, h, std::max(1, int(std::lround(r_m / g.cell_m))), false);
        for (std::size_t c = 0; c < n; ++c)
            if (!std::isfinite(v[c])) v[c] = g.z_m[c];
        f_.lowest.push_back(std::move(v));
    }
    f_.high5 = f_.high;
    squareExtreme(f_.high5, w, h, 2, true);
    // The median of the cells' lowest points (their ground levels) in the 5 x 5 cells.
    f_.median5.resize(n);
    std::vector<float> around;
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            around.clear();
            for (int dj = -2; dj <= 2; ++dj)
                for (int di = -2; di <= 2; ++di) {
                    const int ii = i + di, jj = j + dj;
                    if (ii < 0 || jj < 0 || ii >= w || jj >= h) continue;
                    const float v =
                        levels.empty() ? f_.low[std::size_t(jj) * w + ii] : levels[std::size_t(jj) * w + ii];
                    if (std::isfinite(v)) around.push_back(v);
                }
            const std::size_t c = std::size_t(j) * std::size_t(w) + std::size_t(i);
            if (around.empty()) {
                f_.median5[c] = g.z_m[c];
                continue;
            }
            std::nth_element(around.begin(), around.begin() + std::ptrdiff_t(around.size() / 2), around.end());
            f_.median5[c] = around[around.size() / 2];
        }
    // The terrain's curvature: its Laplacian over 1 and 5 cells.
    const auto laplacian = [&](int step) {
        std::vector<float> out(n, 0.0f);
        const double d2 = double(step) * step * g.cell_m * g.cell_m;
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                const auto z = [&](int ii, int jj) {
                    return double(g.at(std::clamp(ii, 0, w - 1), std::clamp(jj, 0, h - 1)));
                };
                out[std::size_t(j) * w + i] =
                    float((z(i - step, j) + z(i + step, j) + z(i, j - step) + z(i, j + step) - 4 * z(i, j)) / d2);
            }
        return out;
    };
    f_.curv1 = laplacian(1);
    f_.curv5 = laplacian(5);
}

bool LearnedFit::features(const core::CloudPoint& p, float* row) const {
    float h0 = 0;
    const bool ground = smrf_->classify(p, h0);
    const TerrainGrid& g = smrf_->surface();
    std::fill(row, row + kFeatureCount, 0.0f);
    row[0] = h0;
    row[1] = ground ? 1.0f : 0.0f;
    if (g.empty()) return ground;
    const double x = p.position.x, y = p.position.y, z = p.position.z;
    const int i = std::clamp(int(std::lround((x - g.x0_m) / g.cell_m)), 0, g.nx - 1);
    const int j = std::clamp(int(std::lround((y - g.y0_m) / g.cell_m)), 0, g.ny - 1);
    const std::size_t c = std::size_t(j) * std::size_t(g.nx) + std::size_t(i);
    row[2] = float(std::abs(double(h0)) - double(smrf_->limit(c)));
    for (std::size_t k = 0; k < 3; ++k) row[3 + k] = float(z - bilinear(smrf_->variant(k), x, y));
    row[6] = float(g.slopeAt(x, y));
    row[7] = f_.curv1[c];
    row[8] = f_.curv5[c];
    for (std::size_t k = 0; k < 4; ++k) row[9 + k] = float(z - double(f_.lowest[k][c]));
    row[13] = std::isfinite(f_.low[c]) ? float(z - double(f_.low[c])) : 0.0f;
    row[14] = std::isfinite(f_.high[c]) ? float(double(f_.high[c]) - z) : 0.0f;
    row[15] = f_.sd3[c];
    row[16] = float(z - double(f_.mean3[c]));
    row[17] = float(z - double(f_.median5[c]));
    row[18] = std::isfinite(f_.high5[c]) ? float(double(f_.high5[c]) - z) : 0.0f;
    row[19] = f_.gaps5[c];
    row[20] = f_.density[c];
    return ground;
}

[[noreturn]] void badModel(const std::string& where, std::size_t line, const std::string& what) {
    throw core::Error(where + ": line " + std::to_string(line) + ": " + what);
}

}  // namespace

const std::vector<std::string>& learnedFeatureNames() {
    static const std::vector<std::string> names(std::begin(kFeatures), std::end(kFeatures));
    return names;
}

double GroundModel::margin(const float* row) const {
    double sum = 0;
    for (const GroundTree& t : trees) {
        std::size_t k = 0;
        while (t.feature[k] >= 0) {
            const float v = row[t.feature[k]];
            k = std::size_t(std::isnan(v) ? (t.default_left[k] ? t.left[k] : t.right[k])
                                          : (v < t.value[k] ? t.left[k] : t.right[k]));
        }
        sum += double(t.value[k]);
    }
    return sum;
}

std::string serializeGroundModel(const GroundModel& m) {
    std::ostringstream s;
    s << "ladarvr-ground-model " << kGroundModelVersion << "\nfeatures " << kFeatureCount;
    for (const char* name : kFeatures) s << ' ' << name;
    s << "\ntrees " << m.trees.size() << '\n';
    char buf[64];
    for (const GroundTree& t : m.trees) {
        s << "tree " << t.feature.size() << '\n';
        for (std::size_t k = 0; k < t.feature.size(); ++k) {
            std::snprintf(buf, sizeof buf, "%.9g", double(t.value[k]));
            if (t.feature[k] < 0)
                s << "leaf " << buf << '\n';
            else
                s << t.feature[k] << ' ' << buf << ' ' << t.left[k] << ' ' << t.right[k] << ' '
                  << int(t.default_left[k]) << '\n';
        }
    }
    s << "end\n";
    return s.str();
}

GroundModel parseGroundModel(std::string_view text, const std::string& where) {
    std::istringstream in{std::string(text)};
    std::string line;
    std::size_t number = 0;
    const auto next = [&](const char* what) {
        if (!std::getline(in, line)) badModel(where, number + 1, std::string("ends early; expected ") + what);
        ++number;
        return std::istringstream(line);
    };
    {
        std::istringstream l = next("the header");
        std::string magic;
        int version = 0;
        if (!(l >> magic >> version) || magic != "ladarvr-ground-model")
            badModel(where, number, "not a ground model; allowed a file written by bench ground-isprs --write-model");
        if (version != kGroundModelVersion)
            badModel(where, number,
                     "version " + std::to_string(version) + "; allowed " + std::to_string(kGroundModelVersion));
    }
    {
        std::istringstream l = next("the features");
        std::string word;
        std::size_t count = 0;
        if (!(l >> word >> count) || word != "features") badModel(where, number, "expected 'features N names'");
        if (count != kFeatureCount)
            badModel(where, number,
                     std::to_string(count) + " features; allowed " + std::to_string(kFeatureCount) + " (this build's)");
        for (const char* name : kFeatures)
            if (!(l >> word) || word != name)
                badModel(where, number, "feature '" + word + "'; allowed '" + name + "' there (this build's)");
    }
    GroundModel m;
    std::size_t trees = 0;
    {
        std::istringstream l = next("the tree count");
        std::string word;
        if (!(l >> word >> trees) || word != "trees" || trees < 1 || trees > 10000)
            badModel(where, number, "expected 'trees N', N in [1, 10000]");
    }
    for (std::size_t t = 0; t < trees; ++t) {
        std::size_t nodes = 0;
        {
            std::istringstream l = next("a tree");
            std::string word;
            if (!(l >> word >> nodes) || word != "tree" || nodes < 1 || nodes > 65536)
                badModel(where, number, "expected 'tree N', N in [1, 65536]");
        }
        GroundTree tree;
        tree.feature.resize(nodes);
        tree.left.resize(nodes);
        tree.right.resize(nodes);
        tree.value.resize(nodes);
        tree.default_left.resize(nodes);
        for (std::size_t k = 0; k < nodes; ++k) {
            std::istringstream l = next("a node");
            std::string first;
            double value = 0;
            l >> first;
            if (first == "leaf") {
                if (!(l >> value) || !std::isfinite(value)) badModel(where, number, "a leaf needs a finite value");
                tree.feature[k] = -1;
            } else {
                long feature = -1, left = 0, right = 0;
                int default_left = 0;
                char* end = nullptr;
                feature = std::strtol(first.c_str(), &end, 10);
                if (first.empty() || *end != '\0' || !(l >> value >> left >> right >> default_left) ||
                    !std::isfinite(value))
                    badModel(where, number, "expected 'FEATURE SPLIT LEFT RIGHT DEFAULT_LEFT' or 'leaf VALUE'");
                if (feature < 0 || std::size_t(feature) >= kFeatureCount)
                    badModel(
                        where, number,
                        "feature " + std::to_string(feature) + "; allowed 0.." + std::to_string(kFeatureCount - 1));
                if (left <= long(k) || right <= long(k) || left >= long(nodes) || right >= long(nodes) ||
                    (default_left != 0 && default_left != 1))
                    badModel(where, number,
                             "children out of range; allowed " + std::to_string(k + 1) + ".." +
                                 std::to_string(nodes - 1) + " and default 0 or 1");
                tree.feature[k] = std::int32_t(feature);
                tree.left[k] = std::int32_t(left);
                tree.right[k] = std::int32_t(right);
                tree.default_left[k] = std::uint8_t(default_left);
            }
            std::string extra;
            if (l >> extra) badModel(where, number, "'" + extra + "' after the node");
            tree.value[k] = float(value);
        }
        m.trees.push_back(std::move(tree));
    }
    {
        std::istringstream l = next("'end'");
        std::string word;
        if (!(l >> word) || word != "end") badModel(where, number, "expected 'end'");
    }
    return m;
}

GroundModel loadGroundModel(const std::filesystem::path& path) {
    const std::string where = "ground: model " + path.string();
    return parseGroundModel(platform::readTextFile(path, kMaxGroundModelBytes, where), where);
}

std::unique_ptr<TerrainFit> startLearned(const SmrfOptions& o, std::shared_ptr<const GroundModel> model,
                                         double confidence) {
    return std::make_unique<LearnedFit>(o, std::move(model), confidence);
}

std::vector<float> learnedFeatures(std::span<const core::CloudPoint> points, const SmrfOptions& o,
                                   std::vector<std::uint8_t>* smrf_ground) {
    LearnedFit fit(o, nullptr, 0.0);
    fit.add(points);
    fit.fit();
    std::vector<float> rows(points.size() * kFeatureCount);
    if (smrf_ground) smrf_ground->resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        const bool g = fit.features(points[i], rows.data() + i * kFeatureCount);
        if (smrf_ground) (*smrf_ground)[i] = g;
    }
    return rows;
}

}  // namespace sim
