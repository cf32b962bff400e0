// Candidate detections files: what `ladarvr detect` writes and the viewer reads back.
#include <core/error.hpp>
#include <io/candidates_file.hpp>

#include "../common/test_files.hpp"
#include "../common/test_paths.hpp"

#include <doctest/doctest.h>

namespace {

std::string readError(const std::filesystem::path& p) {
    try {
        io::readCandidates(p);
    } catch (const core::Error& e) {
        return e.what();
    }
    return "(no error)";
}

}  // namespace

TEST_CASE("candidates: written and read back with every field, at georeferenced coordinates") {
    test_support::TempDir dir("candidates_rt");
    std::vector<core::Candidate> in(2);
    in[0] = {"tank-1", {5.4e6 + 0.123, -3.2e5 + 0.456, 101.5}, {7.0, 3.5, 2.5}, 33.0, 0.875};
    in[1] = {"c2", {1.0, 2.0, 3.0}, {1.0, 1.0, 1.0}, -90.0, 0.0};
    const auto file = dir.path / "c.json";
    io::writeCandidates(file, in);
    const auto out = io::readCandidates(file);
    REQUIRE(out.size() == 2);
    for (std::size_t i = 0; i < 2; ++i) {
        CHECK(out[i].id == in[i].id);
        CHECK(out[i].centre_world == in[i].centre_world);  // exact: JSON keeps doubles
        CHECK(out[i].size_m == in[i].size_m);
        CHECK(out[i].yaw_deg == in[i].yaw_deg);
        CHECK(out[i].score == in[i].score);
    }
}

TEST_CASE("candidates: bad files are refused in one line naming the field") {
    test_support::TempDir dir("candidates_bad");
    struct Case {
        const char* text;
        const char* expect;
    };
    const Case cases[] = {
        {"[]", "the top level must be an object with 'candidates'"},
        {R"({"candidates": [], "extra": 1})", "unknown key 'extra'; allowed: candidates"},
        {R"({"candidates": [{"id": "a", "centre": [0,0,0], "size_m": [1,1,1], "score": 1.5}]})",
         "candidates[0].score 1.500000 is not in [0, 1]"},
        {R"({"candidates": [{"id": "a", "centre": [0,0], "size_m": [1,1,1], "score": 0.5}]})",
         "candidates[0].centre must be [x, y, z] in world metres, not an array of 2"},
        {R"({"candidates": [{"id": "a", "centre": [0,0,0], "size_m": [1,0,1], "score": 0.5}]})",
         "candidates[0].size_m must be > 0 metres"},
        {R"({"candidates": [{"centre": [0,0,0], "size_m": [1,1,1], "score": 0.5}]})",
         "candidates[0].id must be a non-empty string"},
        {R"({"candidates": [{"id": "a", "centre": [0,0,0], "size_m": [1,1,1]}]})", "candidates[0]: missing 'score'"},
        {R"({"candidates": [{"id": "a", "centre": [0,0,0], "size_m": [1,1,1], "score": 0.5, "colour": 1}]})",
         "candidates[0]: unknown key 'colour'; allowed: id, centre, size_m, yaw_deg, score"},
        {R"({"candidates": [{"id": "a", "centre": [0,0,0], "size_m": [1,1,1], "score": 0.5, "score": 0.6}]})",
         "duplicate key 'score'"},
        {R"({"candidates": [{"id": "a", "centre": [0,0,0], "size_m": [1,1,1], "score": 0.5},
                            {"id": "a", "centre": [0,0,0], "size_m": [1,1,1], "score": 0.5}]})",
         "candidates[1].id 'a' is given twice; allowed: unique ids"},
        {R"({"candidates": [)", "JSON syntax error"},
    };
    int n = 0;
    for (const Case& c : cases) {
        const auto p = dir.write("bad" + std::to_string(n++) + ".json", c.text);
        const std::string m = readError(p);
        INFO(c.text);
        CHECK(m.find(c.expect) != std::string::npos);
        CHECK(m.find(p.filename().string()) != std::string::npos);
        CHECK(m.find('\n') == std::string::npos);
    }
}

TEST_CASE("candidates: the written text reads back from memory as from the file") {
    std::vector<core::Candidate> in(1);
    in[0] = {"c\xC3\xA9", {-0.0, 1e-300, 4.0e6}, {1e-3, 2.0, 3.0}, 1e9, 1.0};
    const auto out = io::parseCandidates(io::candidatesJson(in), "candidates: mem");
    REQUIRE(out.size() == 1);
    CHECK(out[0].id == in[0].id);
    CHECK(out[0].centre_world == in[0].centre_world);
    CHECK(out[0].size_m == in[0].size_m);
    CHECK(out[0].yaw_deg == in[0].yaw_deg);
    CHECK(io::parseCandidates(R"({"candidates": []})", "candidates: mem").empty());
    CHECK_THROWS_WITH_AS(io::parseCandidates(std::string((std::size_t(16) << 20) + 1, ' '), "candidates: mem"),
                         "candidates: mem: 16777217 bytes; allowed: at most 16777216", core::Error);
}

TEST_CASE("candidates: the fuzz seeds are read, or refused in one line, as fuzz_candidates_file expects") {
    // fuzz/seeds/candidates (fuzz/make_seeds.py): what detect writes, a hand-written file,
    // an empty list, and refused forms.
    const std::filesystem::path seeds = std::filesystem::path(test_support::fuzzSeedsDir()) / "candidates";
    int read = 0, refused = 0;
    for (const auto& entry : std::filesystem::directory_iterator(seeds)) {
        CAPTURE(entry.path().string());
        try {
            const auto list = io::readCandidates(entry.path());
            const auto back = io::parseCandidates(io::candidatesJson(list), "candidates: back");
            CHECK(back.size() == list.size());
            ++read;
        } catch (const core::Error& e) {
            const std::string m = e.what();
            CHECK(m.find('\n') == std::string::npos);
            CHECK(entry.path().filename().string().find("errors") != std::string::npos);
            ++refused;
        }
    }
    CHECK(read >= 3);
    CHECK(refused >= 1);
}
