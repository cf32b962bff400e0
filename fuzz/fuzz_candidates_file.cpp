// fuzz/fuzz_candidates_file.cpp: libFuzzer target for io::parseCandidates, the reader of
// the candidates file that `view --candidates` and a study plan's trials name (a detector's
// output, or one a researcher wrote by hand). The contract: either candidates that obey
// the file's rules (at most 100,000, ids non-empty and unique, centres and sizes finite
// and within the frame's bounds, sizes > 0, yaw finite, score in [0, 1]) and that read back
// the same from the text io::candidatesJson writes for them (what `ladarvr detect` writes);
// or one printable error line naming the file and the field.
#include <core/error.hpp>
#include <core/frames.hpp>
#include <io/candidates_file.hpp>
#include "check_message.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace {

bool within(const glm::dvec3& v, double bound) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::abs(v.x) <= bound &&
           std::abs(v.y) <= bound && std::abs(v.z) <= bound;
}

void checkCandidates(const std::vector<core::Candidate>& list) {
    if (list.size() > 100000) std::abort();
    std::set<std::string> ids;
    for (const core::Candidate& c : list) {
        if (c.id.empty() || !ids.insert(c.id).second) std::abort();
        if (!within(c.centre_world, core::kMaxWorldCoordinate_m)) std::abort();
        if (!within(c.size_m, core::kMaxLocalCoordinate_m)) std::abort();
        if (!(c.size_m.x > 0 && c.size_m.y > 0 && c.size_m.z > 0)) std::abort();
        if (!std::isfinite(c.yaw_deg)) std::abort();
        if (!(c.score >= 0.0 && c.score <= 1.0)) std::abort();
    }
}

bool same(const core::Candidate& a, const core::Candidate& b) {
    return a.id == b.id && a.centre_world == b.centre_world && a.size_m == b.size_m && a.yaw_deg == b.yaw_deg &&
           a.score == b.score;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    std::vector<core::Candidate> list;
    try {
        list = io::parseCandidates(text, "candidates: fuzz.json");
    } catch (const core::Error& e) {
        fuzz::checkMessage(e.what());
        // LADARVR_FUZZ_VERBOSE=1 shows why an input was refused (to check the seeds).
        if (std::getenv("LADARVR_FUZZ_VERBOSE")) std::fprintf(stderr, "refused: %s\n", e.what());
        return 0;
    }
    checkCandidates(list);
    // What the writer makes of accepted candidates reads back as the same candidates.
    std::vector<core::Candidate> back;
    try {
        back = io::parseCandidates(io::candidatesJson(list), "candidates: written.json");
    } catch (const core::Error& e) {
        std::fprintf(stderr, "written candidates refused: %s\n", e.what());
        std::abort();
    }
    if (back.size() != list.size()) std::abort();
    for (std::size_t i = 0; i < list.size(); ++i)
        if (!same(list[i], back[i])) std::abort();
    return 0;
}
