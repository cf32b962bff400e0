// detect/src/boosted_model.cpp: the model file and XGBoost's C API of
// detect/boosted_model.hpp. XGBoost is used here only.
#include <detect/boosted_model.hpp>
#include <detect/model_check.hpp>
#include <detect/segment_features.hpp>

#include <core/error.hpp>
#include <platform/atomic_file.hpp>
#include <platform/safe_file.hpp>
#include <platform/sha256.hpp>

#include <nlohmann/json.hpp>
#include <xgboost/c_api.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>

namespace detect {
namespace {

constexpr char kMagic[8] = {'L', 'D', 'V', 'R', 'D', 'E', 'T', '1'};
constexpr int kFormat = 1;

[[noreturn]] void xgbFail(const std::string& context) {
    throw core::Error(context + ": XGBoost: " + platform::messageLine(XGBGetLastError(), 300));
}
#define LADARVR_XGB(call, context)         \
    do {                                   \
        if ((call) != 0) xgbFail(context); \
    } while (false)

// RAII for a DMatrix.
struct Matrix {
    DMatrixHandle h = nullptr;
    Matrix(const std::vector<float>& rows, std::size_t columns, const std::string& context) {
        const std::size_t n = columns ? rows.size() / columns : 0;
        LADARVR_XGB(XGDMatrixCreateFromMat(rows.data(), bst_ulong(n), bst_ulong(columns),
                                           std::numeric_limits<float>::quiet_NaN(), &h),
                    context);
    }
    ~Matrix() { XGDMatrixFree(h); }
    Matrix(const Matrix&) = delete;
    Matrix& operator=(const Matrix&) = delete;
};

bool parseVersion(const std::string& s, int v[3]) {
    char tail = 0;
    return std::sscanf(s.c_str(), "%d.%d.%d%c", &v[0], &v[1], &v[2], &tail) == 3 && v[0] >= 0 && v[1] >= 0 && v[2] >= 0;
}

nlohmann::json segmentJson(const SegmentOptions& o) {
    return {{"smrf_cell_m", o.terrain.cell_m},
            {"smrf_slope", o.terrain.slope},
            {"smrf_window_m", o.terrain.window_m},
            {"smrf_threshold_m", o.terrain.threshold_m},
            {"smrf_scalar", o.terrain.scalar},
            {"min_height_m", o.min_height_m},
            {"ground_sigmas", o.ground_sigmas},
            {"voxel_m", o.voxel_m},
            {"cluster_tolerance_m", o.cluster_tolerance_m},
            {"core_points", o.core_points},
            {"min_points", o.min_points},
            {"split_height_m", o.split_height_m},
            {"scale_with_spacing", o.scale_with_spacing},
            {"level_cell_m", o.level_cell_m},
            {"max_vehicle_length_m", o.max_vehicle_length_m},
            {"max_vehicle_width_m", o.max_vehicle_width_m}};
}

}  // namespace

struct BoostedModel::Booster {
    BoosterHandle h = nullptr;
    std::mutex mutex;  // nthread is a parameter of the booster: one prediction at a time
    ~Booster() { XGBoosterFree(h); }
};

std::string xgboostVersion() {
    int major = 0, minor = 0, patch = 0;
    XGBoostVersion(&major, &minor, &patch);
    return std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(patch);
}

BoostedModel::BoostedModel(ModelInfo info, std::unique_ptr<Booster> booster, std::string bytes)
    : info_(std::move(info)), booster_(std::move(booster)), bytes_(std::move(bytes)) {}
BoostedModel::BoostedModel(BoostedModel&&) noexcept = default;
BoostedModel& BoostedModel::operator=(BoostedModel&&) noexcept = default;
BoostedModel::~BoostedModel() = default;

BoostedModel BoostedModel::train(const std::vector<float>& rows, const std::vector<float>& labels, ModelInfo info,
                                 const BoostParams& p) {
    const std::size_t columns = info.features.size();
    if (columns == 0 || rows.size() != labels.size() * columns)
        throw core::Error("train: " + std::to_string(rows.size()) + " feature values for " +
                          std::to_string(labels.size()) + " segments of " + std::to_string(columns) + " features");
    if (labels.empty())
        throw core::Error("train: no segments to learn from; allowed a corpus with objects above ground");
    if (p.rounds < 1 || p.rounds > 10000)
        throw core::Error("train: --rounds " + std::to_string(p.rounds) + ": allowed [1, 10000]");
    if (p.max_depth < 1 || p.max_depth > 16)
        throw core::Error("train: --max-depth " + std::to_string(p.max_depth) + ": allowed [1, 16]");
    if (!(p.eta > 0.0 && p.eta <= 1.0)) throw core::Error("train: --eta " + std::to_string(p.eta) + ": allowed (0, 1]");
    if (!(p.subsample > 0.0 && p.subsample <= 1.0))
        throw core::Error("train: --subsample " + std::to_string(p.subsample) + ": allowed (0, 1]");
    if (p.threads < 1) throw core::Error("train: --threads " + std::to_string(p.threads) + ": allowed >= 1");
    Matrix m(rows, columns, "train");
    LADARVR_XGB(XGDMatrixSetFloatInfo(m.h, "label", labels.data(), bst_ulong(labels.size())), "train");
    auto booster = std::make_unique<Booster>();
    LADARVR_XGB(XGBoosterCreate(&m.h, 1, &booster->h), "train");
    const std::pair<const char*, std::string> params[] = {
        {"objective", "binary:logistic"},
        {"tree_method", "hist"},
        {"max_depth", std::to_string(p.max_depth)},
        {"eta", std::to_string(p.eta)},
        {"subsample", std::to_string(p.subsample)},
        {"nthread", std::to_string(p.threads)},
        {"seed", std::to_string(p.seed % 2147483647u)},
        {"verbosity", "0"},
    };
    for (const auto& [key, value] : params) LADARVR_XGB(XGBoosterSetParam(booster->h, key, value.c_str()), "train");
    for (int round = 0; round < p.rounds; ++round) LADARVR_XGB(XGBoosterUpdateOneIter(booster->h, round, m.h), "train");
    bst_ulong length = 0;
    const char* data = nullptr;
    LADARVR_XGB(XGBoosterSaveModelToBuffer(booster->h, R"({"format": "ubj"})", &length, &data), "train");
    if (length == 0 || length > kMaxModelBytes)
        throw core::Error("train: XGBoost's model is " + std::to_string(length) + " bytes; allowed 1 .. " +
                          std::to_string(kMaxModelBytes) + " (fewer --rounds or a smaller --max-depth)");
    info.library = "xgboost";
    info.library_version = xgboostVersion();
    return BoostedModel(std::move(info), std::move(booster), std::string(data, std::size_t(length)));
}

std::vector<float> BoostedModel::margins(const std::vector<float>& rows, int threads) const {
    const std::size_t columns = info_.features.size();
    if (rows.empty()) return {};
    if (rows.size() % columns != 0) throw core::Error("detect: feature rows do not match the model's feature count");
    std::lock_guard lock(booster_->mutex);
    LADARVR_XGB(XGBoosterSetParam(booster_->h, "nthread", std::to_string(std::max(1, threads)).c_str()), "detect");
    Matrix m(rows, columns, "detect");
    bst_ulong length = 0;
    const float* out = nullptr;
    LADARVR_XGB(XGBoosterPredict(booster_->h, m.h, 1 /* margin */, 0, 0, &length, &out), "detect");
    if (length != rows.size() / columns)
        throw core::Error("detect: XGBoost returned " + std::to_string(length) + " margins");
    return std::vector<float>(out, out + length);
}

double BoostedModel::probability(double margin) const {
    return 1.0 / (1.0 + std::exp(-(info_.platt_a * margin + info_.platt_b)));
}

std::string BoostedModel::serialize() const {
    const ModelInfo& i = info_;
    nlohmann::json h;
    h["format"] = kFormat;
    h["library"] = i.library;
    h["library_version"] = i.library_version;
    h["features"] = i.features;
    h["target_size_m"] = {i.target_size_m.x, i.target_size_m.y, i.target_size_m.z};
    h["corpus_manifests_sha256"] = i.corpus_manifests_sha256;
    h["calibration"] = {{"a", i.platt_a}, {"b", i.platt_b}};
    h["segmentation"] = segmentJson(i.segments);
    h["training"] = {{"items", i.items}, {"segments", i.segments_total}, {"positives", i.positives}};
    h["model_bytes"] = bytes_.size();
    h["model_sha256"] = platform::sha256Hex(bytes_);
    const std::string header = h.dump(1);
    std::string out(kMagic, sizeof kMagic);
    const std::uint32_t hl = std::uint32_t(header.size());
    for (int k = 0; k < 4; ++k) out += char((hl >> (8 * k)) & 0xFF);
    out += header;
    const std::uint64_t ml = bytes_.size();
    for (int k = 0; k < 8; ++k) out += char((ml >> (8 * k)) & 0xFF);
    out += bytes_;
    return out;
}

void BoostedModel::write(const std::filesystem::path& path) const { platform::writeFileAtomic(path, serialize()); }

BoostedModel BoostedModel::read(const std::filesystem::path& path) {
    const std::string where = "detect: --model " + platform::printableUtf8(path.string(), 200);
    auto bad = [&](const std::string& what) -> core::Error { return core::Error(where + ": " + what); };
    const std::string file = platform::readTextFile(path, 12 + 8 + kMaxHeaderBytes + kMaxModelBytes, where);
    if (file.size() < 20 || std::memcmp(file.data(), kMagic, sizeof kMagic) != 0)
        throw bad("not a ladarvr detector model (no LDVRDET1 magic); allowed a file written by `ladarvr train`");
    std::uint32_t hl = 0;
    for (int k = 0; k < 4; ++k) hl |= std::uint32_t(std::uint8_t(file[8 + k])) << (8 * k);
    if (hl < 2 || hl > kMaxHeaderBytes)
        throw bad("header length " + std::to_string(hl) + ": allowed 2 .. " + std::to_string(kMaxHeaderBytes) +
                  " (1 MiB); the file is damaged or not written by `ladarvr train`");
    if (std::size_t(hl) + 20 > file.size())
        throw bad("header length " + std::to_string(hl) + " does not fit the file's " + std::to_string(file.size()) +
                  " bytes; the file is cut short or damaged");
    std::uint64_t ml = 0;
    for (int k = 0; k < 8; ++k) ml |= std::uint64_t(std::uint8_t(file[12 + hl + k])) << (8 * k);
    if (ml < 1 || ml > kMaxModelBytes || ml != file.size() - 20 - hl)
        throw bad("model length " + std::to_string(ml) + " does not match the " +
                  std::to_string(file.size() - 20 - hl) + " bytes after the header; the file is cut short or damaged");
    const nlohmann::json h = nlohmann::json::parse(file.begin() + 12, file.begin() + 12 + hl, nullptr, false);
    if (h.is_discarded() || !h.is_object()) throw bad("the header is not a JSON object; the file is damaged");
    auto field = [&](const char* key, nlohmann::json::value_t type) -> const nlohmann::json& {
        const auto it = h.find(key);
        if (it == h.end()) throw bad(std::string("header field '") + key + "' is missing");
        const bool ok = it->type() == type || (type == nlohmann::json::value_t::number_float && it->is_number()) ||
                        (type == nlohmann::json::value_t::number_unsigned && it->is_number_unsigned());
        if (!ok) throw bad(std::string("header field '") + key + "' has the wrong type");
        return *it;
    };
    using T = nlohmann::json::value_t;
    if (field("format", T::number_unsigned).get<std::uint64_t>() != std::uint64_t(kFormat))
        throw bad("format " + h["format"].dump() + ": this build reads format " + std::to_string(kFormat));
    ModelInfo i;
    i.library = field("library", T::string).get<std::string>();
    if (i.library != "xgboost") throw bad("library '" + platform::printableUtf8(i.library, 40) + "': allowed xgboost");
    i.library_version = field("library_version", T::string).get<std::string>();
    int fv[3], rv[3];
    const std::string runtime = xgboostVersion();
    if (!parseVersion(i.library_version, fv)) throw bad("library_version is not major.minor.patch");
    parseVersion(runtime, rv);
    if (fv[0] != rv[0] || std::lexicographical_compare(rv, rv + 3, fv, fv + 3))
        throw bad("trained with XGBoost " + platform::printableUtf8(i.library_version, 20) + ", this build has " +
                  runtime + "; allowed the same major version, not newer; retrain with `ladarvr train`");
    for (const auto& f : field("features", T::array)) {
        if (!f.is_string()) throw bad("header field 'features' holds a non-string");
        i.features.push_back(f.get<std::string>());
    }
    if (const std::optional<FeatureSet> set = featureSetOf(i.features)) {
        i.feature_set = *set;
    } else {
        // Against this build's newest list: the first feature that differs, by position
        // (a reordered list has the same count).
        const std::vector<std::string>& ours = segmentFeatureNames(kCurrentFeatures);
        const std::vector<std::string>& first_set = segmentFeatureNames(FeatureSet::kV1);
        const auto [mine, theirs] = std::mismatch(i.features.begin(), i.features.end(), ours.begin(), ours.end());
        const std::size_t k = std::size_t(mine - i.features.begin());
        const std::string first = mine != i.features.end() && theirs != ours.end()
                                      ? "features[" + std::to_string(k) + "] is '" +
                                            platform::printableUtf8(*mine, 60) + "', this build's is '" + *theirs + "'"
                                      : "";
        if (i.features.size() == ours.size() || i.features.size() == first_set.size())
            throw bad(first + "; retrain with `ladarvr train`");
        throw bad("its " + std::to_string(i.features.size()) + " features differ from this build's " +
                  std::to_string(first_set.size()) + " or " + std::to_string(ours.size()) +
                  (first.empty() ? "" : " (" + first + ")") + "; retrain with `ladarvr train`");
    }
    const auto& size = field("target_size_m", T::array);
    if (size.size() != 3) throw bad("target_size_m must hold 3 numbers");
    for (int k = 0; k < 3; ++k) {
        if (!size[k].is_number() || !(size[k].get<double>() > 0.0 && size[k].get<double>() <= 1000.0))
            throw bad("target_size_m must hold 3 numbers in (0, 1000]");
        i.target_size_m[k] = size[k].get<double>();
    }
    for (const auto& s : field("corpus_manifests_sha256", T::array)) {
        if (!s.is_string() || s.get<std::string>().size() != 64)
            throw bad("corpus_manifests_sha256 holds a non-digest");
        i.corpus_manifests_sha256.push_back(s.get<std::string>());
    }
    const auto& cal = field("calibration", T::object);
    if (!cal.contains("a") || !cal.contains("b") || !cal["a"].is_number() || !cal["b"].is_number() ||
        !std::isfinite(cal["a"].get<double>()) || !std::isfinite(cal["b"].get<double>()))
        throw bad("calibration must hold finite numbers a and b");
    i.platt_a = cal["a"].get<double>();
    i.platt_b = cal["b"].get<double>();
    const auto& seg = field("segmentation", T::object);
    auto num = [&](const char* key) {
        if (!seg.contains(key) || !seg[key].is_number()) throw bad(std::string("segmentation.") + key + " is missing");
        return seg[key].get<double>();
    };
    i.segments.terrain.cell_m = num("smrf_cell_m");
    i.segments.terrain.slope = num("smrf_slope");
    i.segments.terrain.window_m = num("smrf_window_m");
    i.segments.terrain.threshold_m = num("smrf_threshold_m");
    i.segments.terrain.scalar = num("smrf_scalar");
    i.segments.min_height_m = num("min_height_m");
    // Files written before the threshold followed the ground's thickness were trained without it.
    i.segments.ground_sigmas = seg.contains("ground_sigmas") ? num("ground_sigmas") : 0.0;
    // ... and before sparse voxels stopped joining segments, every voxel joined.
    const double core_points = seg.contains("core_points") ? num("core_points") : 1.0;
    if (!(core_points >= 1 && core_points <= 1000 && core_points == std::floor(core_points)))
        throw bad("segmentation.core_points: allowed an integer in [1, 1000]");
    i.segments.core_points = int(core_points);
    i.segments.voxel_m = num("voxel_m");
    i.segments.cluster_tolerance_m = num("cluster_tolerance_m");
    const double min_points = num("min_points");
    if (!(min_points >= 1 && min_points <= 1e9)) throw bad("segmentation.min_points: allowed [1, 1e9]");
    i.segments.min_points = int(min_points);
    // ... and before tall segments were split, none was.
    i.segments.split_height_m = seg.contains("split_height_m") ? num("split_height_m") : 0.0;
    // A file written before the lengths followed the point spacing was trained on dense
    // clouds, where the scale is 1: it is read as scaling, so it forms segments on sparse ones.
    if (seg.contains("scale_with_spacing") && !seg["scale_with_spacing"].is_boolean())
        throw bad("segmentation.scale_with_spacing: allowed true or false");
    i.segments.scale_with_spacing = seg.value("scale_with_spacing", true);
    // ... and before the terrain was levelled on the ground's own points, it was not.
    i.segments.level_cell_m = seg.contains("level_cell_m") ? num("level_cell_m") : 0.0;
    // ... and before oversized segments were split, none was.
    i.segments.max_vehicle_length_m = seg.contains("max_vehicle_length_m") ? num("max_vehicle_length_m") : 0.0;
    if (seg.contains("max_vehicle_width_m")) i.segments.max_vehicle_width_m = num("max_vehicle_width_m");
    try {
        validate(i.segments);
    } catch (const core::Error& e) {
        throw bad(std::string("segmentation: ") + e.what());
    }
    const auto& tr = field("training", T::object);
    for (const char* key : {"items", "segments", "positives"})
        if (!tr.contains(key) || !tr[key].is_number_unsigned())
            throw bad(std::string("training.") + key + " is missing");
    i.items = tr["items"].get<std::size_t>();
    i.segments_total = tr["segments"].get<std::size_t>();
    i.positives = tr["positives"].get<std::size_t>();
    if (field("model_bytes", T::number_unsigned).get<std::uint64_t>() != ml)
        throw bad("header says " + h["model_bytes"].dump() + " model bytes, the file holds " + std::to_string(ml));
    std::string bytes = file.substr(20 + hl);
    if (field("model_sha256", T::string).get<std::string>() != platform::sha256Hex(bytes))
        throw bad("the model bytes do not match their SHA-256; the file is damaged");
    // XGBoost trusts its model (a child index out of range reads out of bounds, a child
    // leading back up loops forever), and the SHA-256 above is the file's own: the trees
    // are checked here, before XGBoost parses them.
    checkXgboostModel(bytes, i.features.size(), where);
    auto booster = std::make_unique<Booster>();
    LADARVR_XGB(XGBoosterCreate(nullptr, 0, &booster->h), where);
    LADARVR_XGB(XGBoosterLoadModelFromBuffer(booster->h, bytes.data(), bst_ulong(bytes.size())), where);
    bst_ulong columns = 0;
    LADARVR_XGB(XGBoosterGetNumFeature(booster->h, &columns), where);
    if (columns != i.features.size())
        throw bad("XGBoost's model has " + std::to_string(columns) + " features, the header " +
                  std::to_string(i.features.size()));
    return BoostedModel(std::move(i), std::move(booster), std::move(bytes));
}

void fitPlatt(const std::vector<float>& margins, const std::vector<float>& labels, double& a, double& b) {
    a = 1.0;
    b = 0.0;
    double positives = 0;
    for (const float l : labels) positives += l > 0.5f;
    const double negatives = double(labels.size()) - positives;
    if (positives == 0 || negatives == 0) return;
    // Platt's targets (1999): (N+ + 1) / (N+ + 2) and 1 / (N- + 2), then Newton's method on
    // the log loss with a small ridge (Lin, Lin, Weng 2007's safeguards, simplified).
    const double hi = (positives + 1.0) / (positives + 2.0), lo = 1.0 / (negatives + 2.0);
    double A = 1.0, B = 0.0;
    auto loss = [&](double aa, double bb) {
        double s = 0;
        for (std::size_t k = 0; k < margins.size(); ++k) {
            const double t = labels[k] > 0.5f ? hi : lo;
            const double z = aa * margins[k] + bb;
            // log(1 + exp(-z)) + (1 - t) z, stable for both signs.
            s += (z >= 0 ? std::log1p(std::exp(-z)) : -z + std::log1p(std::exp(z))) + (1.0 - t) * z;
        }
        return s;
    };
    double current = loss(A, B);
    for (int iter = 0; iter < 100; ++iter) {
        double g1 = 0, g2 = 0, h11 = 1e-12, h22 = 1e-12, h21 = 0;
        for (std::size_t k = 0; k < margins.size(); ++k) {
            const double t = labels[k] > 0.5f ? hi : lo;
            const double p = 1.0 / (1.0 + std::exp(-(A * margins[k] + B)));
            const double d = p - t, w = p * (1.0 - p);
            g1 += d * margins[k];
            g2 += d;
            h11 += w * margins[k] * margins[k];
            h22 += w;
            h21 += w * margins[k];
        }
        if (std::abs(g1) < 1e-9 && std::abs(g2) < 1e-9) break;
        const double det = h11 * h22 - h21 * h21;
        if (!(det > 0)) break;
        const double dA = -(h22 * g1 - h21 * g2) / det, dB = -(-h21 * g1 + h11 * g2) / det;
        double step = 1.0;
        while (step > 1e-8) {
            const double next = loss(A + step * dA, B + step * dB);
            if (next < current + 1e-4 * step * (g1 * dA + g2 * dB)) {
                A += step * dA;
                B += step * dB;
                current = next;
                break;
            }
            step /= 2;
        }
        if (step <= 1e-8) break;
    }
    if (std::isfinite(A) && std::isfinite(B)) {
        a = A;
        b = B;
    }
}

}  // namespace detect
