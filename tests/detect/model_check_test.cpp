// tests/detect/model_check_test.cpp: XGBoost's model bytes checked before XGBoost sees
// them. Crafted models are made here from the shipped one (assets/detect/model.ldm) by
// patching its UBJSON and wrapping it in a model file with a fresh length and SHA-256,
// as an attacker would: each crafted case, which crashed or hung XGBoost before the
// check, is refused in one line naming the tree, node or byte, by the checker and by
// BoostedModel::read; the shipped model itself still loads and predicts as before.
#include <detect/boosted_model.hpp>
#include <detect/model_check.hpp>
#include <detect/segment_features.hpp>
#include <platform/sha256.hpp>

#include "test_files.hpp"
#include <test_paths.hpp>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace {

const std::filesystem::path kShipped = std::filesystem::path(test_support::assetsDir()) / "detect" / "model.ldm";
constexpr std::size_t kFeatures = 52;  // the second feature set
constexpr int kMaxTreeDepth = detect::kMaxTreeDepth;

std::string shippedFile() {
    const std::string file = test_support::slurp(kShipped);
    REQUIRE(file.size() > 20);
    return file;
}
std::uint32_t headerLength(const std::string& file) {
    std::uint32_t hl = 0;
    for (int k = 0; k < 4; ++k) hl |= std::uint32_t(std::uint8_t(file[8 + k])) << (8 * k);
    return hl;
}
// XGBoost's UBJSON of the shipped model: what follows the 20 + header bytes.
std::string shippedUbjson() {
    const std::string file = shippedFile();
    return file.substr(20 + headerLength(file));
}

// A model file of the shipped header with `ubjson` as its model: the lengths and the
// SHA-256 made to match, so only the model bytes are wrong.
std::string modelFile(const std::string& ubjson) {
    const std::string file = shippedFile();
    nlohmann::json h = nlohmann::json::parse(file.substr(12, headerLength(file)));
    h["model_bytes"] = ubjson.size();
    h["model_sha256"] = platform::sha256Hex(ubjson);
    const std::string header = h.dump(1);
    std::string out = "LDVRDET1";
    for (int k = 0; k < 4; ++k) out += char((header.size() >> (8 * k)) & 0xFF);
    out += header;
    for (int k = 0; k < 8; ++k) out += char((std::uint64_t(ubjson.size()) >> (8 * k)) & 0xFF);
    return out + ubjson;
}

std::string bigEndian(std::uint64_t v, int bytes) {
    std::string s;
    for (int k = bytes - 1; k >= 0; --k) s += char((v >> (8 * k)) & 0xFF);
    return s;
}
// A key as XGBoost writes it: 'L', its length as a big-endian int64, its bytes.
std::string key(const std::string& name) { return "L" + bigEndian(name.size(), 8) + name; }

// Where the value of the `nth` (from 0) occurrence of `name` starts.
std::size_t valueAt(const std::string& ubj, const std::string& name, std::size_t nth = 0) {
    std::size_t at = std::string::npos;
    for (std::size_t k = 0; k <= nth; ++k) {
        at = ubj.find(key(name), at == std::string::npos ? 0 : at + 1);
        REQUIRE(at != std::string::npos);
    }
    return at + key(name).size();
}
// Where element `k` of the optimized array `name` of tree `tree` starts ("[$l#L" + count).
std::size_t elementAt(const std::string& ubj, const std::string& name, std::size_t tree, std::size_t k) {
    const std::size_t at = valueAt(ubj, name, tree);
    REQUIRE(ubj.compare(at, 2, "[$") == 0);
    REQUIRE(ubj.compare(at + 3, 2, "#L") == 0);
    const std::size_t size = ubj[at + 2] == 'U' ? 1 : ubj[at + 2] == 'L' ? 8 : 4;
    return at + 13 + k * size;
}
// The shipped model with int32 element `k` of `name` of tree `tree` set to v.
std::string withInt32(const std::string& name, std::size_t tree, std::size_t k, std::int32_t v) {
    std::string ubj = shippedUbjson();
    ubj.replace(elementAt(ubj, name, tree, k), 4, bigEndian(std::uint32_t(v), 4));
    return ubj;
}

// A tree object as XGBoost writes it (keys sorted, per-node arrays optimized), of nodes
// with these children; every node splits on feature 0 at 0.5 (a leaf's value).
std::string treeObject(const std::vector<std::int32_t>& left, const std::vector<std::int32_t>& right) {
    const std::size_t n = left.size();
    std::vector<std::int32_t> parents(n, 2147483647);
    for (std::size_t k = 0; k < n; ++k)
        for (const std::int32_t c : {left[k], right[k]})
            if (c > 0 && std::size_t(c) < n) parents[std::size_t(c)] = std::int32_t(k);
    auto ints = [&](const std::vector<std::int32_t>& v) {
        std::string s = "[$l#L" + bigEndian(v.size(), 8);
        for (const std::int32_t x : v) s += bigEndian(std::uint32_t(x), 4);
        return s;
    };
    auto floats = [&](float x) {
        std::uint32_t bits;
        std::memcpy(&bits, &x, 4);
        std::string s = "[$d#L" + bigEndian(n, 8);
        for (std::size_t k = 0; k < n; ++k) s += bigEndian(bits, 4);
        return s;
    };
    const std::string bytes = "[$U#L" + bigEndian(n, 8) + std::string(n, '\0');
    const std::string none = "[$l#L" + bigEndian(0, 8), none64 = "[$L#L" + bigEndian(0, 8);
    auto text = [](const std::string& t) { return "SL" + bigEndian(t.size(), 8) + t; };
    return "{" + key("base_weights") + floats(0.5f) + key("categories") + none + key("categories_nodes") + none +
           key("categories_segments") + none64 + key("categories_sizes") + none64 + key("default_left") + bytes +
           key("id") + std::string("i\0", 2) + key("left_children") + ints(left) + key("loss_changes") + floats(1.0f) +
           key("parents") + ints(parents) + key("right_children") + ints(right) + key("split_conditions") +
           floats(0.5f) + key("split_indices") + ints(std::vector<std::int32_t>(n, 0)) + key("split_type") + bytes +
           key("sum_hessian") + floats(2.0f) + key("tree_param") + "{" + key("num_deleted") + text("0") +
           key("num_feature") + text(std::to_string(kFeatures)) + key("num_nodes") + text(std::to_string(n)) +
           key("size_leaf_vector") + text("1") + "}}";
}
// The shipped model with its tree 0 replaced by `tree`.
std::string withTree0(const std::string& tree) {
    std::string ubj = shippedUbjson();
    const std::size_t begin = valueAt(ubj, "base_weights", 0) - key("base_weights").size() - 1;
    const std::size_t end = valueAt(ubj, "base_weights", 1) - key("base_weights").size() - 1;
    REQUIRE(ubj[begin] == '{');
    REQUIRE(ubj[end] == '{');
    return ubj.replace(begin, end - begin, tree);
}
// A tree `depth` deep: node 2i (i < depth) splits into the leaf 2i + 1 and node 2i + 2.
std::string chainTree(int depth) {
    std::vector<std::int32_t> left(std::size_t(2 * depth + 1), -1), right(std::size_t(2 * depth + 1), -1);
    for (int i = 0; i < depth; ++i) {
        left[std::size_t(2 * i)] = 2 * i + 1;
        right[std::size_t(2 * i)] = 2 * i + 2;
    }
    return treeObject(left, right);
}

struct Case {
    const char* name;
    std::string ubjson;
    const char* fault;
    bool as_file = true;  // also as a model file (an empty model is refused before the check)
};

// Tree 0 of the shipped model: 17 nodes; node 0's children are 1 and 2, node 1's 3 and 4,
// node 3's 7 and 8; node 16, the last, is a leaf.
std::vector<Case> craftedCases() {
    const std::string ok = shippedUbjson();
    std::vector<Case> cases;
    cases.push_back({"child_out_of_range", withInt32("left_children", 0, 0, 99),
                     "tree 0 node 0: left child 99: allowed -1 (a leaf) or 1..16"});
    // The bounds themselves: one past the last node, and the root (never a child).
    cases.push_back({"child_one_past_the_last", withInt32("left_children", 0, 0, 17),
                     "tree 0 node 0: left child 17: allowed -1 (a leaf) or 1..16"});
    cases.push_back({"right_child_one_past_the_last", withInt32("right_children", 0, 0, 17),
                     "tree 0 node 0: right child 17: allowed 1..16 (its left child is 1)"});
    cases.push_back({"child_the_root", withInt32("left_children", 0, 1, 0),
                     "tree 0 node 1: left child 0: allowed -1 (a leaf) or 1..16"});
    cases.push_back({"child_negative", withInt32("left_children", 0, 0, -5),
                     "tree 0 node 0: left child -5: allowed -1 (a leaf) or 1..16"});
    cases.push_back({"right_child_of_leaf", withInt32("right_children", 0, 16, 3),
                     "tree 0 node 16: right child 3: allowed -1 (its left child is -1: a leaf)"});
    cases.push_back(
        {"self_loop", withInt32("left_children", 0, 1, 1), "tree 0 node 1: left child 1 is the node itself"});
    cases.push_back({"two_node_cycle", withInt32("left_children", 0, 3, 1),
                     "tree 0 node 3: left child 1 is reached a second time (a cycle or a shared child)"});
    cases.push_back({"shared_child", withInt32("right_children", 0, 0, 1),
                     "tree 0 node 0: right child 1 is reached a second time"});
    cases.push_back({"wrong_parent", withInt32("parents", 0, 3, 2), "tree 0 node 3: parent 2: allowed 1"});
    cases.push_back({"split_feature", withInt32("split_indices", 0, 0, 52),
                     "tree 0 node 0: split feature 52: allowed 0..51 (the model's 52 features)"});
    cases.push_back(
        {"split_feature_negative", withInt32("split_indices", 7, 0, -1), "tree 7 node 0: split feature -1"});
    {
        std::string ubj = ok;
        ubj[elementAt(ubj, "split_type", 0, 0)] = 1;
        cases.push_back({"categorical_split", ubj, "tree 0 node 0: split type 1: allowed 0 (numeric"});
    }
    {
        std::string ubj = ok;
        const std::size_t at = valueAt(ubj, "categories_nodes");
        REQUIRE(ubj.compare(at, 13, "[$l#L" + bigEndian(0, 8)) == 0);
        ubj.replace(at, 13, "[$l#L" + bigEndian(1, 8) + bigEndian(0, 4));
        cases.push_back({"categorical_data", ubj, "tree 0: categories_nodes: allowed an empty optimized array"});
    }
    {
        std::string ubj = ok;
        const std::size_t at = valueAt(ubj, "tree_info");
        REQUIRE(ubj.compare(at, 3, "[#L") == 0);
        REQUIRE(ubj.compare(at + 11 + 2 * 4, 2, std::string("i\0", 2)) == 0);
        ubj[at + 11 + 2 * 4 + 1] = 5;
        cases.push_back({"tree_group", ubj, "tree 4: output group 5: allowed 0"});
    }
    {
        std::string ubj = ok;
        const std::size_t at = valueAt(ubj, "num_trees");
        REQUIRE(ubj.compare(at, 12, "SL" + bigEndian(3, 8) + "15") == 0);
        ubj[at + 12] = '1';  // "150" -> "151"
        cases.push_back({"num_trees", ubj, "num_trees '151': allowed 150 (the trees the model holds)"});
    }
    {
        // Keys come sorted: the booster's name (after its trees) before the objective's.
        std::string ubj = ok;
        const std::size_t at = valueAt(ubj, "name", 0);
        REQUIRE(ubj.compare(at, 16, "SL" + bigEndian(6, 8) + "gbtree") == 0);
        ubj.replace(at, 16, "SL" + bigEndian(4, 8) + "dart");
        cases.push_back({"dart", ubj, "learner.gradient_booster.name 'dart': allowed gbtree"});
    }
    {
        // Tree 0's tree_param with its key num_deleted renamed num_feature (the same length).
        std::string ubj = ok;
        ubj.replace(valueAt(ubj, "num_deleted") - key("num_deleted").size(), key("num_deleted").size(),
                    key("num_feature"));
        cases.push_back({"duplicate_key", ubj, "key 'num_feature' appears twice in one object; allowed once"});
    }
    {
        std::string ubj = ok;
        const std::size_t at = valueAt(ubj, "base_weights");
        ubj.replace(at + 5, 8, bigEndian(std::uint64_t(1) << 40, 8));
        cases.push_back({"count_too_large", ubj, "a container's count 1099511627776 is more than the"});
    }
    {
        std::string ubj = ok;
        const std::size_t at = valueAt(ubj, "base_weights");
        ubj.replace(at + 5, 8, bigEndian(std::uint64_t(-1), 8));
        cases.push_back({"count_negative", ubj, "a container's count -1: allowed 0 or more"});
    }
    cases.push_back({"too_deep", withTree0(chainTree(kMaxTreeDepth + 1)),
                     "tree 0 node 128: children at depth 65: allowed a depth of at most 64"});
    cases.push_back({"unreached", withTree0(treeObject({-1, -1, -1}, {-1, -1, -1})),
                     "tree 0 node 1 is not reached from the root; allowed every node in the tree"});
    cases.push_back({"too_many_values", "[" + std::string(detect::kMaxModelValues, 'Z') + "]",
                     "byte 524288: more than 524288 values; allowed at most that many"});
    cases.push_back(
        {"deep_nesting", std::string(100000, '['), "byte 64: UBJSON containers nested 65 deep; allowed at most 64"});
    cases.push_back({"trailing_bytes", ok + "Z", "byte 168022: 1 byte after the model's last value; allowed none"});
    cases.push_back({"cut_short", ok.substr(0, ok.size() - 1), "the model ends inside"});
    cases.push_back(
        {"unknown_marker", std::string("{") + key("learner") + "Q", "marker 'Q' (0x51): allowed a UBJSON value"});
    cases.push_back({"no_op", "N" + ok, "byte 0: the UBJSON no-op N: allowed none"});
    cases.push_back({"empty", "", "byte 0: the model ends inside the first value", false});
    return cases;
}

}  // namespace

TEST_CASE("the shipped model passes the check, loads and predicts as before") {
    const std::string ubj = shippedUbjson();
    CHECK_NOTHROW(detect::checkXgboostModel(ubj, kFeatures, "test"));
    REQUIRE(detect::segmentFeatureNames(detect::FeatureSet::kV2).size() == kFeatures);
    const detect::BoostedModel m = detect::BoostedModel::read(kShipped);
    // A row of missing features, one of zeros and one of ones: the margins XGBoost gave
    // for these bytes before the check existed (so the check changes nothing it passes).
    std::vector<float> rows(3 * kFeatures, 0.0f);
    for (std::size_t k = 0; k < kFeatures; ++k) {
        rows[k] = std::numeric_limits<float>::quiet_NaN();
        rows[2 * kFeatures + k] = 1.0f;
    }
    const std::vector<float> margins = m.margins(rows, 1);
    REQUIRE(margins.size() == 3);
    CHECK(margins[0] == doctest::Approx(-5.18611717).epsilon(1e-6));
    CHECK(margins[1] == doctest::Approx(-9.77183247).epsilon(1e-6));
    CHECK(margins[2] == doctest::Approx(-5.47457743).epsilon(1e-6));
}

TEST_CASE("crafted models are refused in one line naming the fault, before XGBoost sees them") {
    test_support::TempDir dir("detect_model_check");
    for (const Case& c : craftedCases()) {
        CAPTURE(std::string(c.name));
        const std::string e = test_support::errorOf([&] { detect::checkXgboostModel(c.ubjson, kFeatures, "where"); });
        CAPTURE(e);
        CHECK(e.starts_with("where: "));
        CHECK(e.find(c.fault) != std::string::npos);
        CHECK(e.find('\n') == std::string::npos);
        if (!c.as_file) continue;
        // As a model file with a valid header and SHA-256: BoostedModel::read refuses it the same way.
        const std::filesystem::path path = dir.path / (std::string(c.name) + ".ldm");
        { std::ofstream(path, std::ios::binary) << modelFile(c.ubjson); }
        const std::string r = test_support::errorOf([&] { detect::BoostedModel::read(path); });
        CAPTURE(r);
        CHECK(r.starts_with("detect: --model " + path.string() + ": "));
        CHECK(r.find(c.fault) != std::string::npos);
        CHECK(r.find('\n') == std::string::npos);
    }
}

TEST_CASE("a tree as deep as the cap passes, and XGBoost predicts down it") {
    test_support::TempDir dir("detect_model_deep");
    const std::string ubj = withTree0(chainTree(kMaxTreeDepth));
    CHECK_NOTHROW(detect::checkXgboostModel(ubj, kFeatures, "test"));
    const std::filesystem::path path = dir.path / "deep.ldm";
    { std::ofstream(path, std::ios::binary) << modelFile(ubj); }
    const detect::BoostedModel m = detect::BoostedModel::read(path);
    const std::vector<float> rows(kFeatures, 1.0f);  // feature 0 above 0.5: right at each node, to the bottom
    CHECK(m.margins(rows, 1).size() == 1);
}

TEST_CASE("the model file wrapper of this test rebuilds the shipped file byte for byte") {
    // So the crafted files above differ from the shipped one in their model bytes only.
    CHECK(modelFile(shippedUbjson()) == shippedFile());
}

TEST_CASE("a model's other fields are checked against what `ladarvr train` writes") {
    const std::string ok = shippedUbjson();
    auto refusal = [](const std::string& ubj, std::size_t features = kFeatures) {
        return test_support::errorOf([&] { detect::checkXgboostModel(ubj, features, "m"); });
    };
    CHECK(refusal(ok, 30).find("model field learner.learner_model_param.num_feature '52': allowed 30") !=
          std::string::npos);
    std::string objective = ok;
    const std::size_t at = valueAt(objective, "name", 1);
    REQUIRE(objective.compare(at, 25, "SL" + bigEndian(15, 8) + "binary:logistic") == 0);
    objective.replace(at + 10, 15, "binary:logitraw");
    CHECK(refusal(objective).find("learner.objective.name 'binary:logitraw': allowed binary:logistic") !=
          std::string::npos);
    std::string id = ok;
    const std::size_t id_at = valueAt(id, "id", 3);
    REQUIRE(id.compare(id_at, 2, std::string("i\x03", 2)) == 0);
    id[id_at + 1] = 2;
    CHECK(refusal(id).find("tree 3: id 2: allowed 3") != std::string::npos);
    std::string nan = withInt32("split_conditions", 2, 4, 0x7fc00000);
    CHECK(refusal(nan).find("tree 2 node 4: ") != std::string::npos);
    CHECK(refusal(nan).find(" nan: allowed a finite number") != std::string::npos);
}

TEST_CASE("the fuzzer's model seeds: the shipped model and its cut pass, the crafted ones are refused") {
    const std::filesystem::path seeds =
        std::filesystem::path(test_support::assetsDir()).parent_path() / "fuzz" / "seeds" / "model";
    int passed = 0, refused = 0;
    for (const auto& entry : std::filesystem::directory_iterator(seeds)) {
        const std::string name = entry.path().filename().string();
        CAPTURE(name);
        const std::string e = test_support::errorOf(
            [&] { detect::checkXgboostModel(test_support::slurp(entry.path()), kFeatures, "seed"); });
        if (name.starts_with("crafted_")) {
            CHECK(e.starts_with("seed: tree 0"));
            ++refused;
        } else {
            CHECK(e == "(no error)");
            ++passed;
        }
    }
    CHECK(passed == 2);
    CHECK(refused == 5);
}
