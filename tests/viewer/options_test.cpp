// tests/viewer/options_test.cpp: viewer options and scripts: parsing and clear errors.
#include <viewer/viewer.hpp>

#include <core/error.hpp>

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace viewer;

namespace {
std::filesystem::path writeTemp(const std::string& name, const std::string& text) {
    const auto path =
        std::filesystem::temp_directory_path() / ("ladarvr-viewer-" + std::to_string(::getpid()) + "-" + name);
    std::ofstream(path) << text;
    return path;
}
}  // namespace

TEST_CASE("a script lists key presses by frame") {
    const auto path = writeTemp("ok.txt", "# frame key\n10 space\n\n25 space   # back\n40 escape\n");
    const auto events = readScript(path);
    REQUIRE(events.size() == 3);
    CHECK(events[0].frame == 10);
    CHECK(events[0].key == ScriptEvent::Key::Space);
    CHECK(events[1].frame == 25);
    CHECK(events[2].key == ScriptEvent::Key::Escape);
    CHECK_FALSE(events[2].after_desktop);
    std::filesystem::remove(path);
    // desktop+N: N frames after the drop to desktop mode.
    const auto after = writeTemp("d.txt", "2 space\ndesktop+20 escape\n");
    const auto relative = readScript(after);
    REQUIRE(relative.size() == 2);
    CHECK_FALSE(relative[0].after_desktop);
    CHECK(relative[1].after_desktop);
    CHECK(relative[1].frame == 20);
    CHECK(relative[1].key == ScriptEvent::Key::Escape);
    std::filesystem::remove(after);
}

TEST_CASE("bad script lines name the file and the line and what is allowed") {
    const auto bad_frame = writeTemp("f.txt", "10 space\nten space\n");
    CHECK_THROWS_WITH_AS(readScript(bad_frame), doctest::Contains("line 2: frame 'ten'"), core::Error);
    const auto bad_key = writeTemp("k.txt", "5 jump\n");
    CHECK_THROWS_WITH_AS(readScript(bad_key), doctest::Contains("action 'jump' is not one of space, escape, aim"),
                         core::Error);
    const auto extra = writeTemp("e.txt", "5 space now\n");
    CHECK_THROWS_WITH_AS(readScript(extra), doctest::Contains("unexpected 'now'"), core::Error);
    const auto negative = writeTemp("n.txt", "-3 space\n");
    CHECK_THROWS_AS(readScript(negative), core::Error);
    const auto no_count = writeTemp("c.txt", "desktop+ escape\n");
    CHECK_THROWS_WITH_AS(readScript(no_count), doctest::Contains("line 1: frame 'desktop+'"), core::Error);
    std::filesystem::remove(no_count);
    CHECK_THROWS_WITH_AS(readScript("/nonexistent/script.txt"),
                         doctest::Contains("/nonexistent/script.txt: does not exist"), core::Error);
    for (const auto& p : {bad_frame, bad_key, extra, negative}) std::filesystem::remove(p);
}

TEST_CASE("mirror and colour names") {
    CHECK(parseMirrorEyes("left") == MirrorEyes::Left);
    CHECK(parseMirrorEyes("both") == MirrorEyes::Both);
    CHECK_THROWS_WITH_AS(parseMirrorEyes("up"), doctest::Contains("not one of left, right, both"), core::Error);
    CHECK(parseColourMode("height") == ColourMode::HeightJet);
    CHECK(parseColourMode("label") == ColourMode::Label);
    CHECK(std::string(colourModeName(ColourMode::White)) == "white");
    CHECK(parseColourMode("above-ground") == ColourMode::AboveGround);
    CHECK(std::string(colourModeName(ColourMode::AboveGround)) == "above-ground");
    CHECK_THROWS_WITH_AS(
        parseColourMode("rainbow"),
        doctest::Contains("not one of file, height, white, label, above-ground, class, intensity, return"),
        core::Error);
    for (const ColourMode m : {ColourMode::Class, ColourMode::Intensity, ColourMode::Return})
        CHECK(parseColourMode(colourModeName(m)) == m);
    CHECK(std::string(colourModeName(ColourMode::Return)) == "return");
}

TEST_CASE("the colours shown: a mode the cloud cannot show falls back to the height colours") {
    const ColourSources bare{};                                 // x y z only
    const ColourSources smrf{true, false, true, true};          // our whitened cloud
    const ColourSources survey{false, false, true, true};       // a file from elsewhere
    const ColourSources with_terrain{false, true, true, true};  // ... once its terrain is bound
    CHECK(shownColourMode(ColourMode::AboveGround, bare) == ColourMode::HeightJet);
    CHECK(shownColourMode(ColourMode::AboveGround, smrf) == ColourMode::AboveGround);
    CHECK(shownColourMode(ColourMode::AboveGround, survey) == ColourMode::HeightJet);
    CHECK(shownColourMode(ColourMode::AboveGround, with_terrain) == ColourMode::AboveGround);
    CHECK(shownColourMode(ColourMode::Class, bare) == ColourMode::Class);  // from the labels
    CHECK(shownColourMode(ColourMode::Intensity, bare) == ColourMode::HeightJet);
    CHECK(shownColourMode(ColourMode::Intensity, survey) == ColourMode::Intensity);
    CHECK(shownColourMode(ColourMode::Return, survey) == ColourMode::Return);
    // The heights take the attributes' place on the GPU: a whitened cloud shows neither.
    CHECK(shownColourMode(ColourMode::Intensity, smrf) == ColourMode::HeightJet);
    CHECK(shownColourMode(ColourMode::Return, smrf) == ColourMode::HeightJet);
    // A survey's file without colours (point formats 0, 1, 4, 6, 9) reads white throughout:
    // its file colours are the heights'.
    const ColourSources colourless{false, false, true, true, false};
    CHECK(shownColourMode(ColourMode::File, survey) == ColourMode::File);
    CHECK(shownColourMode(ColourMode::File, colourless) == ColourMode::HeightJet);
    CHECK(shownColourMode(ColourMode::Class, colourless) == ColourMode::Class);
}

TEST_CASE("viewer options are validated before a window opens") {
    ViewerOptions o;
    CHECK_NOTHROW(validate(o));
    o.style.point_size_px = 0.5f;
    CHECK_THROWS_WITH_AS(validate(o), doctest::Contains("--point-size"), core::Error);
    o = {};
    o.frames = -1;
    CHECK_THROWS_WITH_AS(validate(o), doctest::Contains("--frames"), core::Error);
    o = {};
    o.screenshot = "shot.jpg";
    CHECK_THROWS_WITH_AS(validate(o), doctest::Contains(".png"), core::Error);
    o = {};
    o.window_width = 10;
    CHECK_THROWS_AS(validate(o), core::Error);
    o = {};
    o.upload_points_per_frame = 10;
    CHECK_THROWS_WITH_AS(validate(o), doctest::Contains("--upload-budget"), core::Error);
    o = {};
    o.gpu_bytes = 1000;
    CHECK_THROWS_WITH_AS(validate(o), doctest::Contains("--gpu-mb"), core::Error);
    o.gpu_bytes = std::size_t(1) << 14;  // 1/64 MiB, the least
    CHECK_NOTHROW(validate(o));
    o = {};
    o.upload_bytes_per_frame = 100;
    CHECK_THROWS_WITH_AS(validate(o), doctest::Contains("--upload-mb"), core::Error);
}
