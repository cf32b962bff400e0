// app/src/view_terrain.cpp: the ground under a viewed cloud file, built on a thread of its
// own (view_terrain.hpp).
#include "view_terrain.hpp"

#include <core/error.hpp>
#include <io/cloud_reader.hpp>
#include <io/copc.hpp>
#include <sim/ground_file.hpp>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <utility>
#include <vector>

namespace app {

namespace fs = std::filesystem;

namespace {

// 1234567 -> "1,234,567", as the sources name their point counts.
std::string withCommas(std::size_t n) {
    std::string digits = std::to_string(n), out;
    for (std::size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

// Cells across a span of `extent` at `cell`, the first cell centred on its start.
long long cellsAcross(double extent, double cell) { return static_cast<long long>(std::floor(extent / cell)) + 1; }

// The cell size at least `cell` whose grid over `w` x `h` has at most `max_cells` cells.
double coarsenedCell(double w, double h, double cell, std::size_t max_cells) {
    for (int tries = 0; tries < 64; ++tries) {
        const double cells = double(cellsAcross(w, cell)) * double(cellsAcross(h, cell));
        if (cells <= double(max_cells)) return cell;
        cell *= std::max(1.01, std::sqrt(cells / double(max_cells)));
    }
    return cell;
}

// Every cell of `z` that `has` says is empty takes the height of the nearest cell that is
// not (two raster sweeps carrying each cell's nearest source, as a chamfer distance
// transform does: exact but for ties, in time linear in the cells).
void fillFromNearest(std::vector<float>& z, const std::vector<std::uint8_t>& has, int nx, int ny) {
    std::vector<std::int32_t> src(z.size(), -1);
    for (std::size_t c = 0; c < z.size(); ++c)
        if (has[c]) src[c] = std::int32_t(c);
    const auto dist2 = [nx](std::int32_t a, std::int32_t b) {
        const long long dx = a % nx - b % nx, dy = a / nx - b / nx;
        return dx * dx + dy * dy;
    };
    const auto relax = [&](int i, int j, int di, int dj) {
        const int ni = i + di, nj = j + dj;
        if (ni < 0 || nj < 0 || ni >= nx || nj >= ny) return;
        const std::int32_t here = j * nx + i, cand = src[std::size_t(nj) * std::size_t(nx) + std::size_t(ni)];
        if (cand < 0) return;
        std::int32_t& mine = src[std::size_t(here)];
        if (mine < 0 || dist2(here, cand) < dist2(here, mine)) mine = cand;
    };
    for (int j = 0; j < ny; ++j) {
        for (int i = 0; i < nx; ++i) {
            relax(i, j, -1, 0);
            relax(i, j, -1, -1);
            relax(i, j, 0, -1);
            relax(i, j, 1, -1);
        }
        for (int i = nx - 1; i >= 0; --i) relax(i, j, 1, 0);
    }
    for (int j = ny - 1; j >= 0; --j) {
        for (int i = nx - 1; i >= 0; --i) {
            relax(i, j, 1, 0);
            relax(i, j, 1, 1);
            relax(i, j, 0, 1);
            relax(i, j, -1, 1);
        }
        for (int i = 0; i < nx; ++i) relax(i, j, -1, 0);
    }
    for (std::size_t c = 0; c < z.size(); ++c)
        if (!has[c] && src[c] >= 0) z[c] = z[std::size_t(src[c])];
}

// The nodes of a COPC file's top levels that hold at most `most_points` together (the
// root always), whole levels only, and only levels its root hierarchy page lists whole.
std::vector<io::CopcNode> topNodes(const io::CopcReader& reader, std::size_t most_points) {
    int deepest = INT_MAX;  // levels at or below a child page's key may be listed in part
    for (const io::CopcPage& page : reader.pages()) deepest = std::min(deepest, page.key.level - 1);
    std::vector<io::CopcNode> nodes = reader.nodes();
    std::stable_sort(nodes.begin(), nodes.end(),
                     [](const io::CopcNode& a, const io::CopcNode& b) { return a.key.level < b.key.level; });
    std::vector<io::CopcNode> chosen;
    std::size_t total = 0;
    for (std::size_t i = 0; i < nodes.size();) {
        const int level = nodes[i].key.level;
        std::size_t end = i, points = 0;
        while (end < nodes.size() && nodes[end].key.level == level) points += std::size_t(nodes[end++].point_count);
        if (!chosen.empty() && (level > deepest || total + points > most_points)) break;
        chosen.insert(chosen.end(), nodes.begin() + std::ptrdiff_t(i), nodes.begin() + std::ptrdiff_t(end));
        total += points;
        i = end;
    }
    return chosen;
}

core::PointCloud copcSample(const fs::path& file, std::size_t most_points, const std::atomic<bool>& stop) {
    const io::CopcReader reader(file, io::CopcHierarchy::by_page, std::uint64_t(1) << 20, "the terrain sample's bound");
    core::PointCloud sample;
    sample.origin = reader.origin();
    const std::vector<io::CopcNode> nodes = topNodes(reader, most_points);
    std::size_t total = 0;
    for (const io::CopcNode& node : nodes) total += std::size_t(node.point_count);
    // Every k-th point where the root alone passes the bound (k = 1 otherwise).
    const std::size_t k = std::max<std::size_t>(1, (total + most_points - 1) / std::max<std::size_t>(1, most_points));
    std::size_t index = 0;
    for (const io::CopcNode& node : nodes) {
        if (stop.load()) break;
        core::PointCloud part = reader.readNodeEntry(node);
        sample.fields = part.fields;
        const glm::dvec3 shift = part.origin - sample.origin;
        for (core::CloudPoint& p : part.points) {
            if (index++ % k != 0 || sample.points.size() >= most_points) continue;
            p.position = glm::vec3(glm::dvec3(p.position) + shift);
            sample.points.push_back(p);
        }
    }
    return sample;
}

core::PointCloud streamedSample(const fs::path& file, std::size_t most_points, const std::atomic<bool>& stop) {
    io::CloudReader reader(file);
    core::PointCloud sample;
    sample.origin = reader.origin();
    sample.fields = reader.fields();
    // Every k-th record: an even sample of the file whatever the order of its points.
    const std::size_t bound = reader.pointsBound();
    const std::size_t k = std::max<std::size_t>(1, (bound + most_points - 1) / std::max<std::size_t>(1, most_points));
    sample.points.reserve(std::min(bound / k + 1, most_points));
    std::vector<core::CloudPoint> chunk;
    std::size_t index = 0;
    while (!stop.load() && reader.nextChunk(chunk)) {
        for (const core::CloudPoint& p : chunk)
            if (index++ % k == 0 && sample.points.size() < most_points) sample.points.push_back(p);
        chunk.clear();
    }
    return sample;
}

// The terrain of `file`, from its class 2 when the sample has enough, else fitted.
viewer::ViewTerrain buildTerrain(const fs::path& file, const sim::CoordinateUnits& units, const std::string& what,
                                 const std::atomic<bool>& stop) {
    const core::PointCloud sample = readTerrainSample(file, kTerrainMostPoints, stop);
    if (stop.load()) return {};
    if (sample.points.empty()) throw core::Error("the cloud has no points");
    if (groundPointCount(sample.points) >= kTerrainLeastGroundPoints) {
        viewer::ViewTerrain t = groundGrid(sample.points, sample.origin, 1.0 / units.horizontal_m);
        t.source = what + " class 2 (" + withCommas(groundPointCount(sample.points)) + " points)";
        return t;
    }
    viewer::ViewTerrain t = fittedGrid(sample.points, sample.origin, units);
    t.source = "a terrain fitted by SMRF on " + withCommas(sample.points.size()) + " of its points";
    return t;
}

}  // namespace

std::size_t groundPointCount(std::span<const core::CloudPoint> points) {
    return std::size_t(std::count_if(points.begin(), points.end(),
                                     [](const core::CloudPoint& p) { return p.label == core::Role::Ground; }));
}

viewer::ViewTerrain groundGrid(std::span<const core::CloudPoint> points, const glm::dvec3& origin, double least_cell,
                               std::size_t max_cells) {
    double x_lo = std::numeric_limits<double>::infinity(), y_lo = x_lo, x_hi = -x_lo, y_hi = -x_lo;
    std::size_t n = 0;
    for (const core::CloudPoint& p : points) {
        if (p.label != core::Role::Ground) continue;
        x_lo = std::min(x_lo, double(p.position.x));
        x_hi = std::max(x_hi, double(p.position.x));
        y_lo = std::min(y_lo, double(p.position.y));
        y_hi = std::max(y_hi, double(p.position.y));
        ++n;
    }
    viewer::ViewTerrain t;
    if (n == 0) return t;
    const double w = x_hi - x_lo, h = y_hi - y_lo;
    // Twice the mean spacing: about four ground points a cell where the ground was seen.
    const double spacing = std::sqrt(std::max(w * h, 1e-12) / double(n));
    const double cell =
        coarsenedCell(w, h, std::max({least_cell, 2.0 * spacing, 1e-6}), std::max<std::size_t>(1, max_cells));
    t.cell = cell;
    t.nx = int(cellsAcross(w, cell));
    t.ny = int(cellsAcross(h, cell));
    const std::size_t cells = std::size_t(t.nx) * std::size_t(t.ny);
    std::vector<double> sum(cells, 0.0);
    std::vector<std::uint32_t> count(cells, 0);
    for (const core::CloudPoint& p : points) {
        if (p.label != core::Role::Ground) continue;
        const int i = std::clamp(int(std::lround((double(p.position.x) - x_lo) / cell)), 0, t.nx - 1);
        const int j = std::clamp(int(std::lround((double(p.position.y) - y_lo) / cell)), 0, t.ny - 1);
        const std::size_t c = std::size_t(j) * std::size_t(t.nx) + std::size_t(i);
        sum[c] += double(p.position.z);
        ++count[c];
    }
    t.z.assign(cells, 0.0f);
    std::vector<std::uint8_t> has(cells, 0);
    for (std::size_t c = 0; c < cells; ++c)
        if (count[c] > 0) {
            t.z[c] = float(sum[c] / double(count[c]) + origin.z);
            has[c] = 1;
        }
    fillFromNearest(t.z, has, t.nx, t.ny);
    t.x0 = x_lo + origin.x;
    t.y0 = y_lo + origin.y;
    return t;
}

viewer::ViewTerrain fittedGrid(std::span<const core::CloudPoint> points, const glm::dvec3& origin,
                               const sim::CoordinateUnits& units, std::size_t max_cells) {
    viewer::ViewTerrain t;
    if (points.empty()) return t;
    sim::SmrfOptions o = sim::inUnits(sim::GroundFileOptions{}, units).smrf;
    double x_lo = std::numeric_limits<double>::infinity(), y_lo = x_lo, x_hi = -x_lo, y_hi = -x_lo;
    for (const core::CloudPoint& p : points) {
        x_lo = std::min(x_lo, double(p.position.x));
        x_hi = std::max(x_hi, double(p.position.x));
        y_lo = std::min(y_lo, double(p.position.y));
        y_hi = std::max(y_hi, double(p.position.y));
    }
    // The raster has a cell of margin on each side; coarser cells keep it within the bound.
    o.cell_m = coarsenedCell(x_hi - x_lo + 2.0 * o.cell_m, y_hi - y_lo + 2.0 * o.cell_m, o.cell_m, max_cells / 2);
    o.window_m = std::max(o.window_m, o.cell_m);
    o.max_cells = max_cells;
    sim::validate(o);
    const std::unique_ptr<sim::TerrainFit> fit = sim::startSmrf(o);
    fit->add(points);
    fit->fit();
    const sim::TerrainGrid& g = fit->surface();
    if (g.empty()) return t;
    t.x0 = g.x0_m + origin.x;
    t.y0 = g.y0_m + origin.y;
    t.cell = g.cell_m;
    t.nx = g.nx;
    t.ny = g.ny;
    t.z.resize(g.z_m.size());
    for (std::size_t c = 0; c < g.z_m.size(); ++c) t.z[c] = float(double(g.z_m[c]) + origin.z);
    return t;
}

core::PointCloud readTerrainSample(const fs::path& file, std::size_t most_points, const std::atomic<bool>& stop) {
    return io::isCopcFile(file) ? copcSample(file, most_points, stop) : streamedSample(file, most_points, stop);
}

bool carriesHeightAboveGround(const fs::path& file) {
    try {
        return io::CloudReader(file).fields().height_above_ground;
    } catch (const core::Error&) {
        return false;
    }
}

TerrainProducer::TerrainProducer(fs::path file, sim::CoordinateUnits units, std::string what,
                                 std::shared_ptr<viewer::TerrainFeed> feed) {
    thread_ = std::thread([this, file = std::move(file), units, what = std::move(what), feed = std::move(feed)] {
        try {
            viewer::ViewTerrain t = buildTerrain(file, units, what, stop_);
            if (stop_.load()) return;
            if (t.empty())
                feed->fail("no terrain could be fitted to the cloud");
            else
                feed->publish(std::move(t));
        } catch (const std::exception& e) {
            feed->fail(e.what());
        }
    });
}

TerrainProducer::~TerrainProducer() {
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
}

StartedTerrain startCloudTerrain(const fs::path& cloud, const fs::path& read, const std::string& what,
                                 const std::string& context) {
    StartedTerrain t;
    if (carriesHeightAboveGround(cloud)) return t;
    t.feed = std::make_shared<viewer::TerrainFeed>();
    sim::CoordinateUnits units;
    try {
        units = sim::readCoordinateUnits(cloud, context.c_str());
    } catch (const core::Error& e) {
        const std::string why = e.what(), prefix = context + ": ";
        t.feed->fail(why.starts_with(prefix) ? why.substr(prefix.size()) : why);
        return t;
    }
    t.producer = std::make_unique<TerrainProducer>(read, units, what, t.feed);
    return t;
}

}  // namespace app
