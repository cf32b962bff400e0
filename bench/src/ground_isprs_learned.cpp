// bench/src/ground_isprs_learned.cpp: see ground_isprs_learned.hpp. XGBoost's C API
// learns the trees (binary logistic, histogram method, a fixed seed); its JSON model is
// turned into sim::GroundModel's trees, and the margins of both are compared on the
// training rows so that the file says what XGBoost learned.
#include "ground_isprs_learned.hpp"
#include "xgboost_handles.hpp"

#include <core/error.hpp>

#include <nlohmann/json.hpp>
#include <xgboost/c_api.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

namespace bench {
namespace {

constexpr const char* kXgbContext = "bench ground-isprs";

[[noreturn]] void xgbFail(const char* what) { xgboostFail(kXgbContext, what); }
#define LADARVR_XGB(call, what)         \
    do {                                \
        if ((call) != 0) xgbFail(what); \
    } while (false)

// A number XGBoost's JSON model writes as a string, maybe in brackets ("[5E-1]").
double jsonNumber(const nlohmann::json& j) {
    if (j.is_number()) return j.get<double>();
    std::string s = j.get<std::string>();
    std::erase_if(s, [](char c) { return c == '[' || c == ']'; });
    return std::strtod(s.c_str(), nullptr);
}

sim::GroundModel fromXgboost(const XgbBooster& b) {
    bst_ulong length = 0;
    const char* data = nullptr;
    LADARVR_XGB(XGBoosterSaveModelToBuffer(b.h, R"({"format": "json"})", &length, &data), "save");
    const nlohmann::json j = nlohmann::json::parse(std::string(data, std::size_t(length)));
    const nlohmann::json& trees = j.at("learner").at("gradient_booster").at("model").at("trees");
    sim::GroundModel m;
    for (const nlohmann::json& t : trees) {
        sim::GroundTree tree;
        const auto& left = t.at("left_children");
        const auto& right = t.at("right_children");
        const auto& index = t.at("split_indices");
        const auto& cond = t.at("split_conditions");
        const auto& dl = t.at("default_left");
        const std::size_t n = left.size();
        for (std::size_t k = 0; k < n; ++k) {
            const int l = left[k].get<int>();
            tree.feature.push_back(l < 0 ? -1 : index[k].get<int>());
            tree.left.push_back(l < 0 ? 0 : l);
            tree.right.push_back(l < 0 ? 0 : right[k].get<int>());
            tree.value.push_back(cond[k].get<float>());
            tree.default_left.push_back(dl[k].get<int>() != 0 ? 1 : 0);
        }
        m.trees.push_back(std::move(tree));
    }
    // The intercept: base_score is a probability; its logit is added to every margin.
    const double base = jsonNumber(j.at("learner").at("learner_model_param").at("base_score"));
    if (base > 0.0 && base < 1.0 && std::abs(base - 0.5) > 1e-9) {
        sim::GroundTree bias;
        bias.feature = {-1};
        bias.left = {0};
        bias.right = {0};
        bias.value = {float(std::log(base / (1.0 - base)))};
        bias.default_left = {0};
        m.trees.push_back(bias);
    }
    return m;
}

}  // namespace

LearnedSample describeSample(const std::string& name, const std::vector<core::CloudPoint>& points,
                             const std::vector<std::uint8_t>& truth, const sim::SmrfOptions& o) {
    LearnedSample s;
    s.name = name;
    s.site = name.size() >= 6 ? name[4] - '0' : 0;
    s.truth = truth;
    s.rows = sim::learnedFeatures(points, o, &s.smrf);
    return s;
}

sim::GroundModel learnGroundModel(const std::vector<const LearnedSample*>& samples, const TreeParams& p) {
    const std::size_t columns = sim::learnedFeatureNames().size();
    std::vector<float> rows, labels, weights;
    double total = 0;
    for (const LearnedSample* s : samples) total += double(s->truth.size());
    const double mean_points = total / double(std::max<std::size_t>(1, samples.size()));
    for (const LearnedSample* s : samples) {
        rows.insert(rows.end(), s->rows.begin(), s->rows.end());
        for (const std::uint8_t t : s->truth) labels.push_back(t ? 1.0f : 0.0f);
        weights.insert(weights.end(), s->truth.size(), float(mean_points / double(s->truth.size())));
    }
    for (std::size_t c : p.left_out)
        for (std::size_t r = 0; r < labels.size(); ++r) rows[r * columns + c] = 0.0f;
    XgbMatrix m(rows, columns, kXgbContext);
    LADARVR_XGB(XGDMatrixSetFloatInfo(m.h, "label", labels.data(), bst_ulong(labels.size())), "labels");
    LADARVR_XGB(XGDMatrixSetFloatInfo(m.h, "weight", weights.data(), bst_ulong(weights.size())), "weights");
    XgbBooster b;
    LADARVR_XGB(XGBoosterCreate(&m.h, 1, &b.h), "create");
    const std::pair<const char*, std::string> params[] = {
        {"objective", "binary:logistic"},
        {"tree_method", "hist"},
        {"max_depth", std::to_string(p.max_depth)},
        {"eta", std::to_string(p.eta)},
        {"subsample", std::to_string(p.subsample)},
        {"base_score", "0.5"},
        {"nthread", std::to_string(p.threads)},
        {"seed", std::to_string(p.seed % 2147483647u)},
        {"verbosity", "0"},
    };
    for (const auto& [key, value] : params) LADARVR_XGB(XGBoosterSetParam(b.h, key, value.c_str()), "parameter");
    for (int round = 0; round < p.rounds; ++round) LADARVR_XGB(XGBoosterUpdateOneIter(b.h, round, m.h), "train");
    sim::GroundModel model = fromXgboost(b);
    // Our trees must give XGBoost's margins.
    bst_ulong length = 0;
    const float* out = nullptr;
    LADARVR_XGB(XGBoosterPredict(b.h, m.h, 1 /* margin */, 0, 0, &length, &out), "predict");
    for (std::size_t r = 0; r < std::size_t(length); r += 97)
        if (std::abs(model.margin(rows.data() + r * columns) - double(out[r])) > 1e-3)
            throw core::Error("bench ground-isprs: the trees read from XGBoost's model give margin " +
                              std::to_string(model.margin(rows.data() + r * columns)) + " on row " + std::to_string(r) +
                              ", XGBoost " + std::to_string(out[r]));
    return model;
}

std::vector<std::uint8_t> refinedLabels(const LearnedSample& s, const std::vector<float>& margins, double confidence) {
    std::vector<std::uint8_t> found(margins.size());
    for (std::size_t i = 0; i < margins.size(); ++i) {
        const bool trees = margins[i] > 0.0f;
        found[i] = (bool(s.smrf[i]) != trees && std::abs(double(margins[i])) > confidence) ? trees : s.smrf[i];
    }
    return found;
}

std::vector<std::vector<float>> leaveOneSiteOut(const std::vector<LearnedSample>& samples, const TreeParams& p) {
    const std::size_t columns = sim::learnedFeatureNames().size();
    std::vector<std::vector<float>> found(samples.size());
    std::vector<int> sites;
    for (const LearnedSample& s : samples)
        if (std::find(sites.begin(), sites.end(), s.site) == sites.end()) sites.push_back(s.site);
    for (const int site : sites) {
        std::vector<const LearnedSample*> train;
        for (const LearnedSample& s : samples)
            if (s.site != site) train.push_back(&s);
        const sim::GroundModel model = learnGroundModel(train, p);
        for (std::size_t k = 0; k < samples.size(); ++k) {
            if (samples[k].site != site) continue;
            const LearnedSample& s = samples[k];
            found[k].resize(s.truth.size());
            for (std::size_t i = 0; i < s.truth.size(); ++i)
                found[k][i] = float(model.margin(s.rows.data() + i * columns));
        }
    }
    return found;
}

}  // namespace bench
