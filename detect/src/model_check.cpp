// detect/src/model_check.cpp: the UBJSON parser and the checks of XGBoost's model of
// detect/model_check.hpp. No XGBoost here: the fuzz build compiles this file alone.
#include <detect/model_check.hpp>

#include <core/error.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace detect {
namespace {

// ---- UBJSON -------------------------------------------------------------------------

struct Member;

/// One parsed UBJSON value. An optimized array of numbers ("[$l#...") stays a view of its
/// bytes (`raw`: `count` elements of marker `type`), so even a large one allocates nothing.
struct Value {
    enum class Kind : std::uint8_t { Null, Bool, Integer, Number, String, Array, Object };
    Kind kind = Kind::Null;
    char marker = 0;  // the marker it was written with
    char type = 0;    // an optimized array's element marker; 0 otherwise
    bool boolean = false;
    std::int64_t integer = 0;     // Kind::Integer
    double number = 0.0;          // Kind::Number
    std::string_view raw;         // a string's bytes, or an optimized array's elements
    std::size_t count = 0;        // an optimized array's element count
    std::vector<Value> items;     // a plain array's elements
    std::vector<Member> members;  // an object's members, in file order
};
struct Member {
    std::string_view key;
    Value value;
};

// Bytes of a number of marker m; 0 for a marker that is not a number.
std::size_t numberSize(char m) {
    switch (m) {
        case 'i':
        case 'U': return 1;
        case 'I': return 2;
        case 'l':
        case 'd': return 4;
        case 'L':
        case 'D': return 8;
        default: return 0;
    }
}

bool isIntegerMarker(char m) { return m == 'i' || m == 'U' || m == 'I' || m == 'l' || m == 'L'; }

// The number of marker m stored big-endian at p (numberSize(m) bytes) into v.
void decodeNumber(char m, const char* p, Value& v) {
    std::uint64_t u = 0;
    for (std::size_t k = 0; k < numberSize(m); ++k) u = (u << 8) | std::uint8_t(p[k]);
    v.kind = Value::Kind::Integer;
    switch (m) {
        case 'i': v.integer = std::int8_t(u); break;
        case 'U': v.integer = std::uint8_t(u); break;
        case 'I': v.integer = std::int16_t(u); break;
        case 'l': v.integer = std::int32_t(u); break;
        case 'L': v.integer = std::int64_t(u); break;
        case 'd': {
            const std::uint32_t bits = std::uint32_t(u);
            float f;
            std::memcpy(&f, &bits, 4);
            v.kind = Value::Kind::Number;
            v.number = f;
            break;
        }
        default: {  // 'D'
            double d;
            std::memcpy(&d, &u, 8);
            v.kind = Value::Kind::Number;
            v.number = d;
            break;
        }
    }
}

// A marker as a message shows it: 'A' (0x41), or 0x00 for a byte that is not printable.
std::string shownMarker(char m) {
    char buffer[16];
    const unsigned char c = static_cast<unsigned char>(m);
    if (c > 0x20 && c < 0x7f)
        std::snprintf(buffer, sizeof buffer, "'%c' (0x%02x)", m, c);
    else
        std::snprintf(buffer, sizeof buffer, "0x%02x", c);
    return buffer;
}

std::string quoted(std::string_view s) { return "'" + core::printable(s, 40) + "'"; }

class Parser {
  public:
    Parser(std::string_view bytes, const std::string& where) : b_(bytes), where_(where) {}

    /// The one value the bytes hold; nothing may follow it.
    Value document() {
        const std::size_t at = pos_;
        Value v = value(next("the first value"), 0, at);
        if (pos_ != b_.size())
            fail(pos_, std::to_string(b_.size() - pos_) + (b_.size() - pos_ == 1 ? " byte" : " bytes") +
                           " after the model's last value; allowed none");
        return v;
    }

  private:
    std::string_view b_;
    const std::string& where_;
    std::size_t pos_ = 0;
    std::size_t values_ = 0;

    [[noreturn]] void fail(std::size_t at, const std::string& what) const {
        throw core::Error(where_ + ": XGBoost model byte " + std::to_string(at) + ": " + what);
    }
    std::size_t left() const { return b_.size() - pos_; }
    [[noreturn]] void cut(const char* inside) const {
        fail(pos_, std::string("the model ends inside ") + inside + "; the file is cut short or damaged");
    }
    char next(const char* inside) {
        if (pos_ >= b_.size()) cut(inside);
        return b_[pos_++];
    }
    bool peek(char m) const { return pos_ < b_.size() && b_[pos_] == m; }
    std::string_view take(std::size_t n, const char* inside) {
        if (n > left()) cut(inside);
        const std::string_view s = b_.substr(pos_, n);
        pos_ += n;
        return s;
    }
    // A length or count (an integer value), checked against the bytes left before anything
    // is kept: at least `item_bytes` bytes for each of the items it counts.
    std::size_t length(const char* what, std::size_t item_bytes) {
        const std::size_t at = pos_;
        const char m = next(what);
        if (!isIntegerMarker(m))
            fail(at, std::string(what) + " has marker " + shownMarker(m) + "; allowed an integer (i U I l L)");
        Value v;
        decodeNumber(m, take(numberSize(m), what).data(), v);
        if (v.integer < 0) fail(at, std::string(what) + " " + std::to_string(v.integer) + ": allowed 0 or more");
        if (std::uint64_t(v.integer) > left() / item_bytes)
            fail(at, std::string(what) + " " + std::to_string(v.integer) + " is more than the " +
                         std::to_string(left()) + " bytes left can hold; the file is cut short or damaged");
        return std::size_t(v.integer);
    }

    // The value of marker m (already read) that starts at byte `at`, `depth` containers in.
    Value value(char m, int depth, std::size_t at) {
        if (++values_ > kMaxModelValues)
            fail(at, "more than " + std::to_string(kMaxModelValues) +
                         " values; allowed at most that many (a model of 10000 trees holds about 232000)");
        Value v;
        v.marker = m;
        switch (m) {
            case 'Z': return v;
            case 'T':
            case 'F':
                v.kind = Value::Kind::Bool;
                v.boolean = m == 'T';
                return v;
            case 'i':
            case 'U':
            case 'I':
            case 'l':
            case 'L':
            case 'd':
            case 'D': decodeNumber(m, take(numberSize(m), "a number").data(), v); return v;
            case 'C':
                v.kind = Value::Kind::String;
                v.raw = take(1, "a character");
                return v;
            case 'S':
            case 'H': {  // a string, or a high-precision number written as one
                const std::size_t n = length("a string's length", 1);
                v.kind = Value::Kind::String;
                v.raw = take(n, "a string");
                return v;
            }
            case '[':
            case '{': container(v, depth + 1, m == '{', at); return v;
            case 'N': fail(at, "the UBJSON no-op N: allowed none (XGBoost writes none)");
            default: fail(at, "marker " + shownMarker(m) + ": allowed a UBJSON value (Z T F i U I l L d D C S H [ {)");
        }
    }

    void container(Value& v, int depth, bool object, std::size_t at) {
        v.kind = object ? Value::Kind::Object : Value::Kind::Array;
        if (depth > kMaxModelNesting)
            fail(at, "UBJSON containers nested " + std::to_string(depth) + " deep; allowed at most " +
                         std::to_string(kMaxModelNesting));
        char type = 0;
        if (peek('$')) {
            ++pos_;
            const std::size_t type_at = pos_;
            type = next("an optimized container's type");
            if (numberSize(type) == 0)
                fail(type_at,
                     "an optimized container of " + shownMarker(type) + ": allowed the number types i U I l L d D");
            if (!peek('#')) fail(pos_, "an optimized container's type without its count; allowed '$' only before '#'");
        }
        bool counted = false;
        std::size_t count = 0;
        if (peek('#')) {
            ++pos_;
            counted = true;
            // Each item takes at least: its number (typed), its marker (untyped), and in an
            // object a key of at least two bytes (length marker and length).
            const std::size_t item = (type ? numberSize(type) : 1) + (object ? 2 : 0);
            count = length("a container's count", item);
        }
        if (type && !object) {
            v.type = type;
            v.count = count;
            v.raw = take(count * numberSize(type), "an array");
            return;
        }
        std::vector<std::pair<std::string_view, std::size_t>> keys;  // and where each starts
        for (std::size_t k = 0; !counted || k < count; ++k) {
            if (!counted) {
                if (pos_ >= b_.size()) cut(object ? "an object" : "an array");
                if (b_[pos_] == (object ? '}' : ']')) {
                    ++pos_;
                    break;
                }
            }
            const std::size_t item_at = pos_;
            if (object) {
                const std::size_t n = length("a key's length", 1);
                const std::string_view key = take(n, "a key");
                keys.emplace_back(key, item_at);
                const std::size_t value_at = pos_;
                const char m = type ? type : next("an object");
                v.members.push_back(Member{key, value(m, depth, value_at)});
            } else {
                v.items.push_back(value(next("an array"), depth, item_at));
            }
        }
        if (keys.size() > 1) {
            std::sort(keys.begin(), keys.end());
            for (std::size_t k = 1; k < keys.size(); ++k)
                if (keys[k].first == keys[k - 1].first)
                    fail(keys[k].second, "key " + quoted(keys[k].first) + " appears twice in one object; allowed once");
        }
    }
};

// ---- the model ----------------------------------------------------------------------

constexpr std::int64_t kRootParent = 2147483647;  // XGBoost's parent index of a root

const char* typeName(char m) {
    switch (m) {
        case 'U': return "uint8";
        case 'l': return "int32";
        case 'L': return "int64";
        case 'd': return "float32";
        default: return "?";
    }
}

// Element k of an optimized array of integers / of floats.
std::int64_t integerAt(const Value& a, std::size_t k) {
    Value v;
    decodeNumber(a.type, a.raw.data() + k * numberSize(a.type), v);
    return v.integer;
}
double numberAt(const Value& a, std::size_t k) {
    Value v;
    decodeNumber(a.type, a.raw.data() + k * numberSize(a.type), v);
    return v.number;
}

std::string joined(std::initializer_list<std::string_view> names) {
    std::string s;
    for (const std::string_view n : names) s += (s.empty() ? "" : ", ") + std::string(n);
    return s;
}

class Checker {
  public:
    Checker(std::size_t features, const std::string& where) : features_(features), where_(where) {}

    void model(const Value& root) {
        object(root, "model", {"learner", "version"});
        const Value& version = array(field(root, "version"), "model field version");
        if (version.items.size() != 3) fail("model field version: allowed 3 integers");
        for (const Value& v : version.items)
            if (v.kind != Value::Kind::Integer || v.integer < 0 || v.integer > 1000)
                fail("model field version: allowed 3 integers 0..1000");

        const Value& learner = field(root, "learner");
        object(
            learner, "model field learner",
            {"attributes", "feature_names", "feature_types", "gradient_booster", "learner_model_param", "objective"});
        const Value& attributes = field(learner, "attributes");
        if (attributes.kind != Value::Kind::Object) fail("model field learner.attributes: allowed an object");
        for (const Member& m : attributes.members) string(m.value, "model field learner.attributes." + key(m.key));
        const Value& names = array(field(learner, "feature_names"), "model field learner.feature_names");
        if (!names.items.empty() && names.items.size() != features_)
            fail("model field learner.feature_names holds " + std::to_string(names.items.size()) +
                 " names: allowed none or " + std::to_string(features_));
        for (const Value& n : names.items) string(n, "model field learner.feature_names");
        const Value& types = array(field(learner, "feature_types"), "model field learner.feature_types");
        if (!types.items.empty() && types.items.size() != features_)
            fail("model field learner.feature_types holds " + std::to_string(types.items.size()) +
                 " types: allowed none or " + std::to_string(features_));
        for (const Value& t : types.items) {
            const std::string_view s = string(t, "model field learner.feature_types");
            if (s != "q" && s != "float" && s != "int" && s != "i")
                fail("model field learner.feature_types holds " + quoted(s) +
                     ": allowed q, float, int or i (no categorical features; `ladarvr train` makes none)");
        }

        const Value& param = field(learner, "learner_model_param");
        const std::string lp = "learner.learner_model_param";
        object(param, "model field " + lp,
               {"base_score", "boost_from_average", "num_class", "num_feature", "num_target"});
        const double base = decimal(field(param, "base_score"), "model field " + lp + ".base_score");
        if (!(base > 0.0 && base < 1.0))
            fail("model field " + lp + ".base_score " + core::shownNumber(base) +
                 ": allowed (0, 1) (a probability of binary:logistic)");
        whole(field(param, "boost_from_average"), "model field " + lp + ".boost_from_average", 0, 1);
        whole(field(param, "num_class"), "model field " + lp + ".num_class", 0, 1, " (one output group)");
        whole(field(param, "num_target"), "model field " + lp + ".num_target", 1, 1, " (one output group)");
        whole(field(param, "num_feature"), "model field " + lp + ".num_feature", features_, features_,
              " (this build's features)");

        const Value& objective = field(learner, "objective");
        object(objective, "model field learner.objective", {"name", "reg_loss_param"});
        if (string(field(objective, "name"), "model field learner.objective.name") != "binary:logistic")
            fail("model field learner.objective.name " + quoted(field(objective, "name").raw) +
                 ": allowed binary:logistic (what `ladarvr train` fits)");
        const Value& loss = field(objective, "reg_loss_param");
        object(loss, "model field learner.objective.reg_loss_param", {"scale_pos_weight"});
        const double weight =
            decimal(field(loss, "scale_pos_weight"), "model field learner.objective.reg_loss_param.scale_pos_weight");
        if (!(weight > 0.0)) fail("model field learner.objective.reg_loss_param.scale_pos_weight: allowed > 0");

        const Value& booster = field(learner, "gradient_booster");
        object(booster, "model field learner.gradient_booster", {"model", "name"});
        const std::string_view name = string(field(booster, "name"), "model field learner.gradient_booster.name");
        if (name != "gbtree")
            fail("model field learner.gradient_booster.name " + quoted(name) +
                 ": allowed gbtree (`ladarvr train` grows plain trees, not dart or gblinear)");
        trees(field(booster, "model"));
    }

  private:
    std::size_t features_;
    const std::string& where_;

    [[noreturn]] void fail(const std::string& what) const { throw core::Error(where_ + ": " + what); }
    static std::string key(std::string_view k) { return core::printable(k, 40); }

    // v must be an object of exactly `keys` (those in `optional` may be absent); `label`
    // names it in messages ("model field learner.objective", "tree 3").
    void object(const Value& v, const std::string& label, std::initializer_list<std::string_view> keys,
                std::initializer_list<std::string_view> optional = {}) const {
        if (v.kind != Value::Kind::Object) fail(label + ": allowed an object");
        for (const Member& m : v.members)
            if (std::find(keys.begin(), keys.end(), m.key) == keys.end())
                fail(label + ": key " + quoted(m.key) + ": allowed " + joined(keys));
        for (const std::string_view k : keys)
            if (!find(v, k) && std::find(optional.begin(), optional.end(), k) == optional.end())
                fail(label + ": " + std::string(k) + " is missing");
    }
    // The member `k` of an object checked with object() (present unless optional).
    static const Value* find(const Value& object, std::string_view k) {
        for (const Member& m : object.members)
            if (m.key == k) return &m.value;
        return nullptr;
    }
    static const Value& field(const Value& object, std::string_view k) { return *find(object, k); }

    std::string_view string(const Value& v, const std::string& what) const {
        if (v.kind != Value::Kind::String || v.marker != 'S') fail(what + ": allowed a string");
        return v.raw;
    }
    const Value& array(const Value& v, const std::string& what) const {
        if (v.kind != Value::Kind::Array || v.type != 0) fail(what + ": allowed an array");
        return v;
    }
    // XGBoost writes its parameters as strings: a whole number lo..hi in decimal digits.
    std::uint64_t whole(const Value& v, const std::string& what, std::uint64_t lo, std::uint64_t hi,
                        const std::string& why = "") const {
        const std::string_view s = string(v, what);
        std::uint64_t n = 0;
        bool ok = !s.empty() && s.size() <= 18;
        for (const char c : s) {
            if (c < '0' || c > '9') ok = false;
            n = n * 10 + std::uint64_t(c - '0');
        }
        if (!ok || n < lo || n > hi)
            fail(what + " " + quoted(s) + ": allowed " +
                 (lo == hi ? std::to_string(lo) : std::to_string(lo) + ".." + std::to_string(hi)) + why);
        return n;
    }
    // A finite decimal number written as a string ("7.885635E-3"), read whatever the locale.
    double decimal(const Value& v, const std::string& what) const {
        const std::string_view s = string(v, what);
        double d = 0.0;
        const bool chars = !s.empty() && s.size() <= 40 && s.find_first_not_of("0123456789.eE+-") == s.npos;
        const auto [end, ec] = chars ? std::from_chars(s.data(), s.data() + s.size(), d)
                                     : std::from_chars_result{s.data(), std::errc::invalid_argument};
        if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(d))
            fail(what + " " + quoted(s) + ": allowed a finite decimal number");
        return d;
    }
    // A plain array of integers lo..hi.
    const Value& integers(const Value& v, const std::string& what) const {
        array(v, what);
        for (const Value& i : v.items)
            if (i.kind != Value::Kind::Integer) fail(what + ": allowed an array of integers");
        return v;
    }
    // An optimized array of `n` numbers of marker `type`, as XGBoost writes a tree's arrays.
    const Value& typed(const Value& v, const std::string& what, char type, std::size_t n,
                       const char* count_name) const {
        if (v.kind != Value::Kind::Array || v.type != type)
            fail(what + ": allowed an optimized array of " + typeName(type) + " ([$" + type + "#)");
        if (v.count != n)
            fail(what + " holds " + std::to_string(v.count) + " values, " + count_name + " says " + std::to_string(n));
        return v;
    }

    void trees(const Value& model) {
        const std::string mp = "learner.gradient_booster.model";
        object(model, "model field " + mp, {"gbtree_model_param", "iteration_indptr", "tree_info", "trees"},
               {"iteration_indptr"});
        const Value& param = field(model, "gbtree_model_param");
        object(param, "model field " + mp + ".gbtree_model_param", {"num_parallel_tree", "num_trees"});
        whole(field(param, "num_parallel_tree"), "model field " + mp + ".gbtree_model_param.num_parallel_tree", 1, 1,
              " (one tree a round)");
        const Value& list = array(field(model, "trees"), "model field " + mp + ".trees");
        const std::uint64_t n = whole(field(param, "num_trees"), "model field " + mp + ".gbtree_model_param.num_trees",
                                      1, std::numeric_limits<std::int32_t>::max());
        if (n != list.items.size())
            fail("model field " + mp + ".gbtree_model_param.num_trees '" + std::to_string(n) + "': allowed " +
                 std::to_string(list.items.size()) + " (the trees the model holds)");
        const Value& info = integers(field(model, "tree_info"), "model field " + mp + ".tree_info");
        if (info.items.size() != n)
            fail("model field " + mp + ".tree_info holds " + std::to_string(info.items.size()) + " groups for " +
                 std::to_string(n) + " trees");
        for (std::size_t t = 0; t < info.items.size(); ++t)
            if (info.items[t].integer != 0)
                fail("tree " + std::to_string(t) + ": output group " + std::to_string(info.items[t].integer) +
                     ": allowed 0 (binary:logistic has one)");
        if (const Value* indptr = find(model, "iteration_indptr")) {
            integers(*indptr, "model field " + mp + ".iteration_indptr");
            if (indptr->items.size() != n + 1)
                fail("model field " + mp + ".iteration_indptr holds " + std::to_string(indptr->items.size()) +
                     " values: allowed " + std::to_string(n + 1) + " (one tree a round)");
            for (std::size_t k = 0; k < indptr->items.size(); ++k)
                if (indptr->items[k].integer != std::int64_t(k))
                    fail("model field " + mp + ".iteration_indptr[" + std::to_string(k) + "] " +
                         std::to_string(indptr->items[k].integer) + ": allowed " + std::to_string(k) +
                         " (one tree a round)");
        }
        for (std::size_t t = 0; t < list.items.size(); ++t) tree(list.items[t], t);
    }

    void tree(const Value& v, std::size_t t) {
        const std::string at = "tree " + std::to_string(t);
        object(v, at,
               {"base_weights", "categories", "categories_nodes", "categories_segments", "categories_sizes",
                "default_left", "id", "left_children", "loss_changes", "parents", "right_children", "split_conditions",
                "split_indices", "split_type", "sum_hessian", "tree_param"});
        const Value& id = field(v, "id");
        if (id.kind != Value::Kind::Integer || id.integer != std::int64_t(t))
            fail(at + ": id " + (id.kind == Value::Kind::Integer ? std::to_string(id.integer) : "(not an integer)") +
                 ": allowed " + std::to_string(t) + " (its place in the list)");
        const Value& param = field(v, "tree_param");
        object(param, at + ": tree_param", {"num_deleted", "num_feature", "num_nodes", "size_leaf_vector"});
        whole(field(param, "num_deleted"), at + ": tree_param.num_deleted", 0, 0, " (`ladarvr train` deletes none)");
        whole(field(param, "num_feature"), at + ": tree_param.num_feature", features_, features_,
              " (this build's features)");
        whole(field(param, "size_leaf_vector"), at + ": tree_param.size_leaf_vector", 0, 1,
              " (one value a leaf, not a multi-target tree)");
        const std::size_t n = std::size_t(whole(field(param, "num_nodes"), at + ": tree_param.num_nodes", 1,
                                                std::numeric_limits<std::int32_t>::max()));
        // The categorical splits' arrays: empty (`ladarvr train` makes no categorical split).
        const char* categorical[] = {"categories", "categories_nodes", "categories_segments", "categories_sizes"};
        for (const char* name : categorical) {
            const Value& c = field(v, name);
            const char type =
                std::strcmp(name, "categories_segments") == 0 || std::strcmp(name, "categories_sizes") == 0 ? 'L' : 'l';
            if (c.kind != Value::Kind::Array || c.type != type || c.count != 0)
                fail(at + ": " + name +
                     ": allowed an empty optimized array (no categorical splits; `ladarvr train` makes none)");
        }
        auto per_node = [&](const char* name, char type) -> const Value& {
            return typed(field(v, name), at + ": " + name, type, n, "num_nodes");
        };
        const Value& left = per_node("left_children", 'l');
        const Value& right = per_node("right_children", 'l');
        const Value& parents = per_node("parents", 'l');
        const Value& split = per_node("split_indices", 'l');
        const Value& condition = per_node("split_conditions", 'd');
        const Value& default_left = per_node("default_left", 'U');
        const Value& split_type = per_node("split_type", 'U');
        const Value* stats[] = {&per_node("base_weights", 'd'), &per_node("loss_changes", 'd'),
                                &per_node("sum_hessian", 'd')};
        const char* stat_names[] = {"base weight", "loss change", "sum of hessians"};

        const std::string range = n > 1 ? " or 1.." + std::to_string(n - 1) : " (the tree has one node)";
        for (std::size_t k = 0; k < n; ++k) {
            const std::string node = at + " node " + std::to_string(k) + ": ";
            const std::int64_t l = integerAt(left, k), r = integerAt(right, k);
            auto inside = [&](std::int64_t c) { return c >= 1 && c < std::int64_t(n); };
            if (!(l == -1 || inside(l)))
                fail(node + "left child " + std::to_string(l) + ": allowed -1 (a leaf)" + range);
            if (l == -1 && r != -1)
                fail(node + "right child " + std::to_string(r) + ": allowed -1 (its left child is -1: a leaf)");
            if (l != -1 && !inside(r))
                fail(node + "right child " + std::to_string(r) + ": allowed 1.." + std::to_string(n - 1) +
                     " (its left child is " + std::to_string(l) + ")");
            const std::int64_t f = integerAt(split, k);
            if (f < 0 || std::uint64_t(f) >= features_)
                fail(node + "split feature " + std::to_string(f) + ": allowed 0.." + std::to_string(features_ - 1) +
                     " (the model's " + std::to_string(features_) + " features)");
            if (!std::isfinite(numberAt(condition, k)))
                fail(node + (l == -1 ? "leaf value " : "split condition ") + core::shownNumber(numberAt(condition, k)) +
                     ": allowed a finite number");
            if (integerAt(default_left, k) > 1)
                fail(node + "default_left " + std::to_string(integerAt(default_left, k)) + ": allowed 0 or 1");
            if (integerAt(split_type, k) != 0)
                fail(node + "split type " + std::to_string(integerAt(split_type, k)) +
                     ": allowed 0 (numeric; `ladarvr train` makes no categorical split)");
            for (int s = 0; s < 3; ++s)
                if (!std::isfinite(numberAt(*stats[s], k)))
                    fail(node + stat_names[s] + " " + core::shownNumber(numberAt(*stats[s], k)) +
                         ": allowed a finite number");
        }

        // From the root down with an explicit stack: each node reached once (no loop back
        // up, no cycle, no child shared by two parents), its recorded parent the one that
        // reached it, the depth capped; then every node must have been reached.
        if (integerAt(parents, 0) != kRootParent)
            fail(at + " node 0: parent " + std::to_string(integerAt(parents, 0)) + ": allowed " +
                 std::to_string(kRootParent) + " (the root has none)");
        std::vector<std::uint8_t> reached(n, 0);
        std::vector<std::pair<std::size_t, int>> stack{{0, 0}};
        reached[0] = 1;
        std::size_t count = 1;
        while (!stack.empty()) {
            const auto [k, depth] = stack.back();
            stack.pop_back();
            const std::int64_t children[2] = {integerAt(left, k), integerAt(right, k)};
            if (children[0] == -1) continue;
            const std::string node = at + " node " + std::to_string(k) + ": ";
            if (depth + 1 > kMaxTreeDepth)
                fail(node + "children at depth " + std::to_string(depth + 1) + ": allowed a depth of at most " +
                     std::to_string(kMaxTreeDepth));
            for (int side = 0; side < 2; ++side) {
                const std::size_t c = std::size_t(children[side]);
                const char* which = side == 0 ? "left child " : "right child ";
                if (c == k) fail(node + which + std::to_string(c) + " is the node itself; allowed a tree");
                if (reached[c])
                    fail(node + which + std::to_string(c) +
                         " is reached a second time (a cycle or a shared child); allowed a tree");
                if (integerAt(parents, c) != std::int64_t(k))
                    fail(at + " node " + std::to_string(c) + ": parent " + std::to_string(integerAt(parents, c)) +
                         ": allowed " + std::to_string(k) + " (the node whose child it is)");
                reached[c] = 1;
                ++count;
                stack.emplace_back(c, depth + 1);
            }
        }
        if (count != n) {
            const std::size_t k = std::size_t(std::find(reached.begin(), reached.end(), 0) - reached.begin());
            fail(at + " node " + std::to_string(k) + " is not reached from the root; allowed every node in the tree");
        }
    }
};

}  // namespace

void checkXgboostModel(std::string_view ubjson, std::size_t features, const std::string& where) {
    if (features == 0 || features > std::size_t(std::numeric_limits<std::int32_t>::max()))
        throw core::Error(where + ": a model of " + std::to_string(features) + " features; allowed 1 or more");
    const Value root = Parser(ubjson, where).document();
    Checker(features, where).model(root);
}

}  // namespace detect
