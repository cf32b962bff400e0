// detect/src/training.cpp: learning the trained detector (detect/training.hpp).
#include <detect/training.hpp>

#include <core/error.hpp>
#include <detect/boosted_detector.hpp>
#include <detect/segment_features.hpp>
#include <io/strict_json.hpp>
#include <platform/safe_file.hpp>
#include <platform/sha256.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace detect {
namespace {

constexpr std::size_t kMaxManifestBytes = std::size_t(1) << 30;
constexpr std::size_t kMaxManifestLineBytes = std::size_t(1) << 20;  // a corpus writes lines of a few KiB
constexpr double kMinTargetShare = 0.1;  // of the cloud's target points, for a positive segment

bool heldOut(std::size_t k, double f) { return std::floor(double(k + 1) * f) > std::floor(double(k) * f); }

}  // namespace

void validate(const TrainOptions& o) {
    for (int k = 0; k < 3; ++k)
        if (!(std::isfinite(o.target_size_m[k]) && o.target_size_m[k] > 0.0 && o.target_size_m[k] <= 1000.0))
            throw core::Error("train: --target-size-m: allowed three sizes in (0, 1000] m");
    if (!(o.holdout_fraction >= 0.0 && o.holdout_fraction <= 0.9))
        throw core::Error("train: --holdout-fraction = " + std::to_string(o.holdout_fraction) + ": allowed [0, 0.9]");
    validate(o.segments);
}

TrainingItem describeLabelledCloud(const core::PointCloud& cloud, const std::string& name, const TrainOptions& o) {
    if (!cloud.fields.label)
        throw core::Error("train: " + name + ": the cloud has no label field; allowed corpus clouds (labelled points)");
    const DescribedSegments d = describeSegments(cloud, o.segments, o.target_size_m, o.boost.threads, o.features);
    TrainingItem item;
    item.name = name;
    std::size_t cloud_target = 0;
    for (const core::CloudPoint& p : cloud.points) cloud_target += p.label == core::Role::Target;
    const std::size_t columns = segmentFeatureNames(o.features).size();
    for (std::size_t s = 0; s < d.segmentation.segments.size(); ++s) {
        const auto& seg = d.segmentation.segments[s];
        std::size_t target = 0;
        for (const std::uint32_t i : seg) target += cloud.points[i].label == core::Role::Target;
        const bool positive = 2 * target > seg.size();
        // A scrap of the target (mostly target, but a small share of its points) is
        // neither a vehicle nor not one: learning it as a positive would teach the trees
        // that any small blob may be the target, as a negative that a vehicle's part is
        // not. Such segments are left out.
        if (positive && double(target) < kMinTargetShare * double(cloud_target)) continue;
        item.rows.insert(item.rows.end(), d.rows.begin() + std::ptrdiff_t(s * columns),
                         d.rows.begin() + std::ptrdiff_t((s + 1) * columns));
        item.labels.push_back(positive ? 1.0f : 0.0f);
    }
    return item;
}

namespace {
// The heap blocks of one listing entry: a string's text once it outgrows the inline
// buffer, plus the allocator's bookkeeping, for the id and for the cloud file's name.
std::size_t listingHeapBytes(const std::string& id, const std::string& cloud) {
    const auto heap = [](std::size_t length) { return length > 15 ? length + 1 + 16 : std::size_t(0); };
    return heap(id.size()) + heap(cloud.size());
}
}  // namespace

CorpusListing listCorpus(const std::filesystem::path& dir, std::size_t budget_bytes) {
    const std::string where = "train: " + platform::printableUtf8(dir.string(), 200);
    const std::string manifest = where + "/manifest.jsonl";
    CorpusListing out;
    out.dir = dir;
    // The manifest's text is held while it is listed, so it counts against the budget too,
    // with the listing's fixed part (two vectors sized to the lines) and each entry's heap.
    const std::string mib = "--memory-mb " + std::to_string(budget_bytes >> 20) + " MiB";
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(dir / "manifest.jsonl", ec);
    if (!ec && size > budget_bytes && size <= kMaxManifestBytes)
        throw core::Error(manifest + ": " + std::to_string(size) + " bytes, more than " + mib +
                          " (the manifest and its listing are held in memory); raise --memory-mb");
    const std::string text =
        platform::readTextFile(dir / "manifest.jsonl", std::min(kMaxManifestBytes, budget_bytes), manifest);
    out.manifest_sha256 = platform::sha256Hex(text);
    const std::size_t lines = std::size_t(std::count(text.begin(), text.end(), '\n')) + 1;
    std::size_t held = text.size() + lines * 2 * sizeof(std::string);
    const auto over = [&](const std::string& what) {
        return core::Error(manifest + ": " + what + " pass " + mib + "; raise --memory-mb");
    };
    if (held > budget_bytes) throw over("its " + std::to_string(lines) + " lines and their listing");
    out.ids.reserve(lines);
    out.cloud_files.reserve(lines);
    std::size_t number = 0;
    for (std::size_t begin = 0; begin < text.size();) {
        std::size_t end = text.find('\n', begin);
        if (end == std::string::npos) end = text.size();
        const std::string_view line(text.data() + begin, end - begin);
        begin = end + 1;
        ++number;
        if (line.empty()) continue;
        const std::string at = manifest + " line " + std::to_string(number);
        if (line.size() > kMaxManifestLineBytes)
            throw core::Error(at + ": " + std::to_string(line.size()) + " bytes; allowed at most " +
                              std::to_string(kMaxManifestLineBytes) + " bytes a line");
        const nlohmann::json j = io::parseStrictJson(line, at);
        if (!j.is_object()) throw core::Error(at + ": not a JSON object");
        if (!j.contains("id") || !j["id"].is_string()) throw core::Error(at + ": no string 'id'");
        const std::string id = j["id"].get<std::string>();
        if (id.empty() || id.size() > 20 ||
            !std::all_of(id.begin(), id.end(), [](char c) { return c >= '0' && c <= '9'; }))
            throw core::Error(at + ": id '" + platform::printableUtf8(id, 30) + "': allowed digits only");
        if (!j.contains("files") || !j["files"].is_object()) throw core::Error(at + ": no 'files' object");
        std::string cloud;
        for (const auto& [name, value] : j["files"].items())
            if (name.rfind("cloud.", 0) == 0 && name.find('/') == std::string::npos) cloud = name;
        if (cloud.empty()) throw core::Error(at + ": 'files' names no cloud file (cloud.pcd, cloud.ply, ...)");
        held += listingHeapBytes(id, cloud);
        if (held > budget_bytes) throw over("its text and its listing up to line " + std::to_string(number));
        out.ids.push_back(id);
        out.cloud_files.push_back(std::move(cloud));
    }
    out.held_bytes = held - text.size();
    if (out.ids.empty()) throw core::Error(manifest + ": no items; allowed a corpus with finished items");
    return out;
}

BoostedModel trainDetector(const std::vector<TrainingItem>& items, const TrainOptions& o,
                           const std::vector<std::string>& manifests_sha256, TrainReport& report) {
    validate(o);
    report = TrainReport{};
    const std::size_t columns = segmentFeatureNames(o.features).size();
    std::vector<float> train_rows, train_labels, held_rows, held_labels;
    for (std::size_t k = 0; k < items.size(); ++k) {
        const TrainingItem& it = items[k];
        const bool held = items.size() > 1 && heldOut(k, o.holdout_fraction);
        auto& rows = held ? held_rows : train_rows;
        auto& labels = held ? held_labels : train_labels;
        rows.insert(rows.end(), it.rows.begin(), it.rows.end());
        labels.insert(labels.end(), it.labels.begin(), it.labels.end());
        ++report.items;
        report.heldout_items += held;
        report.segments += it.labels.size();
        for (const float l : it.labels) report.positives += l > 0.5f;
    }
    report.heldout_segments = held_labels.size();
    for (const float l : held_labels) report.heldout_positives += l > 0.5f;
    std::size_t train_positives = 0;
    for (const float l : train_labels) train_positives += l > 0.5f;
    if (train_positives == 0)
        throw core::Error("train: no training segment is mostly target-labelled (" +
                          std::to_string(train_labels.size()) +
                          " segments); allowed a corpus whose targets stand above the ground");
    if (train_positives == train_labels.size())
        throw core::Error("train: every training segment is the target; allowed a corpus with other objects too");
    (void)columns;

    ModelInfo info;
    info.features = segmentFeatureNames(o.features);
    info.feature_set = o.features;
    info.target_size_m = o.target_size_m;
    info.corpus_manifests_sha256 = manifests_sha256;
    info.segments = o.segments;
    info.items = report.items - report.heldout_items;
    info.segments_total = train_labels.size();
    info.positives = train_positives;
    BoostedModel model = BoostedModel::train(train_rows, train_labels, info, o.boost);

    // Calibration on the held-out items when they hold both classes.
    const bool both = report.heldout_positives > 0 && report.heldout_positives < held_labels.size();
    report.calibrated_on_heldout = both;
    const std::vector<float>& cal_rows = both ? held_rows : train_rows;
    const std::vector<float>& cal_labels = both ? held_labels : train_labels;
    const std::vector<float> margins = model.margins(cal_rows, o.boost.threads);
    fitPlatt(margins, cal_labels, model.info().platt_a, model.info().platt_b);
    double brier = 0, log_loss = 0;
    for (std::size_t k = 0; k < margins.size(); ++k) {
        const double p = model.probability(margins[k]), y = cal_labels[k];
        brier += (p - y) * (p - y);
        log_loss -= y > 0.5 ? std::log(std::max(p, 1e-15)) : std::log(std::max(1.0 - p, 1e-15));
        const int bin = p < 0.1 ? 0 : p < 0.5 ? 1 : p < 0.9 ? 2 : 3;
        ++report.bin_count[bin];
        report.bin_mean_probability[bin] += p;
        report.bin_positive_share[bin] += y;
    }
    for (int b = 0; b < 4; ++b)
        if (report.bin_count[b]) {
            report.bin_mean_probability[b] /= double(report.bin_count[b]);
            report.bin_positive_share[b] /= double(report.bin_count[b]);
        }
    if (!margins.empty()) {
        report.brier = brier / double(margins.size());
        report.log_loss = log_loss / double(margins.size());
    }
    return model;
}

}  // namespace detect
