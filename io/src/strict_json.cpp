// strict_json: see io/strict_json.hpp.
#include <core/error.hpp>
#include <io/strict_json.hpp>

#include <memory>
#include <set>
#include <vector>

namespace io {

using core::Error;
namespace {

using nlohmann::json;

// The parser callback that makes JSON stricter than nlohmann is: a key repeated in one
// object (nlohmann keeps the last silently) and a NUL character in a key or string (it
// would cut file names short at the C library) are refused, naming where they are, e.g.
// "meshes[0].file". Throws Error; nlohmann lets the exception through.
class StrictKeys {
  public:
    explicit StrictKeys(std::string scene_name) : name_(std::move(scene_name)) {}

    bool operator()(int /*depth*/, json::parse_event_t event, json& parsed) {
        switch (event) {
            case json::parse_event_t::object_start:
            case json::parse_event_t::array_start:
                countElement();
                if (stack_->size() >= kMaxJsonDepth)
                    throw Error(name_ + ": arrays and objects nested deeper than " + std::to_string(kMaxJsonDepth) +
                                " levels; allowed at most " + std::to_string(kMaxJsonDepth));
                stack_->push_back({event == json::parse_event_t::array_start, 0, {}, {}});
                break;
            case json::parse_event_t::object_end:
            case json::parse_event_t::array_end:
                if (!stack_->empty()) stack_->pop_back();
                break;
            case json::parse_event_t::key: {
                const std::string& key = parsed.get_ref<const std::string&>();
                Frame& top = stack_->back();
                top.key.clear();  // where() names the object, not its previous key
                if (key.find('\0') != std::string::npos)
                    throw Error(name_ + ": " + where() + "a key holds a NUL character (\\u0000): '" +
                                core::printable(key, 40, true) + "'; allowed: keys without NUL");
                if (!top.keys.insert(key).second)
                    throw Error(name_ + ": " + where() + "duplicate key '" + core::printable(key, 40, true) +
                                "'; allowed: each key once per object");
                top.key = key;
                break;
            }
            case json::parse_event_t::value:
                countElement();
                if (parsed.is_string() && parsed.get_ref<const std::string&>().find('\0') != std::string::npos) {
                    throw Error(name_ + ": " + where() + "the string '" +
                                core::printable(parsed.get_ref<const std::string&>(), 60, true) +
                                "' holds a NUL character (\\u0000); allowed: text without NUL");
                }
                break;
        }
        return true;
    }

  private:
    struct Frame {
        bool array = false;
        std::size_t index = 0;  // elements seen so far (arrays)
        std::string key;        // the current key (objects)
        std::set<std::string> keys;
    };
    // An array's element starts: count it, so where() names it.
    void countElement() {
        if (!stack_->empty() && stack_->back().array) ++stack_->back().index;
    }
    // "meshes[0].file: " for the value being parsed, "" at the top level. A path deeper
    // than a message can hold keeps its last kMaxWhereBytes bytes after "...", cut at a
    // character's first byte: the innermost keys say where the fault is.
    std::string where() const {
        std::string w;
        for (const Frame& f : *stack_) {
            if (f.array) {
                if (f.index > 0) w += "[" + std::to_string(f.index - 1) + "]";
            } else if (!f.key.empty()) {
                w += (w.empty() ? "" : ".") + core::printable(f.key, 40, true);
            }
        }
        if (w.size() > kMaxWhereBytes) {
            std::size_t cut = w.size() - kMaxWhereBytes;
            while (cut < w.size() && (static_cast<unsigned char>(w[cut]) & 0xC0) == 0x80) ++cut;
            w = "..." + w.substr(cut);
        }
        return w.empty() ? w : w + ": ";
    }
    static constexpr std::size_t kMaxWhereBytes = 240;
    std::string name_;
    // Shared: nlohmann copies the callback.
    std::shared_ptr<std::vector<Frame>> stack_ = std::make_shared<std::vector<Frame>>();
};

}  // namespace

nlohmann::json parseStrictJson(std::string_view json_text, const std::string& name) {
    // A file that does not start as JSON does is not quoted: a design or a scene naming
    // another file (a password file) would otherwise show its first bytes in the message.
    const std::size_t first = json_text.find_first_not_of(" \t\r\n");
    if (first != std::string_view::npos && json_text[first] != '{' && json_text[first] != '[')
        throw Error(name + ": not JSON: the text starts with neither '{' nor '['; allowed: a JSON object");
    json root;
    try {
        root = json::parse(json_text, StrictKeys(name));
    } catch (const json::parse_error& e) {
        std::string what = e.what();
        // "[json.exception.parse_error.101] parse error at line 3, column 5: ..." -> keep the tail.
        const std::size_t at = what.find("parse error");
        if (at != std::string::npos) what = what.substr(at);
        throw Error(name + ": JSON syntax error: " + core::printable(what, 300));
    } catch (const json::out_of_range& e) {
        // nlohmann reports numbers beyond double range (1e999) here.
        std::string what = e.what();
        const std::size_t at = what.find("number overflow");
        if (at != std::string::npos) what = what.substr(at);
        throw Error(name + ": " + core::printable(what, 300) + ": the number is not finite; allowed: finite numbers");
    } catch (const json::exception& e) {
        throw Error(name + ": invalid JSON: " + core::printable(e.what(), 300));
    }
    return root;
}

std::string jsonTypeName(const json& v) {
    const std::string t = v.type_name();
    return (t == "array" || t == "object" ? "an " : "a ") + t;
}

}  // namespace io
