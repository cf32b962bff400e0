// The bundled scenes are generated: the committed files must be exactly what
// scripts/make_scenes.py makes, so nobody edits one by hand and the script stays true.
#include <test_files.hpp>
#include <test_paths.hpp>
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include <unistd.h>

namespace fs = std::filesystem;

namespace {

using test_support::slurp;

std::set<std::string> filesUnder(const fs::path& root) {
    std::set<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(root))
        if (e.is_regular_file()) out.insert(fs::relative(e.path(), root).string());
    return out;
}

}  // namespace

TEST_CASE("assets: the committed scenes are exactly what scripts/make_scenes.py makes") {
    const fs::path assets = fs::path(test_support::assetsDir());
    const fs::path script = assets.parent_path() / "scripts" / "make_scenes.py";
    const fs::path out = fs::temp_directory_path() / ("ladarvr_assets_test_" + std::to_string(::getpid()));
    fs::remove_all(out);
    const std::string cmd = "python3 '" + script.string() + "' --out '" + out.string() + "' > /dev/null";
    REQUIRE(std::system(cmd.c_str()) == 0);
    const std::set<std::string> made = filesUnder(out);
    CHECK(made.count("demo/scene.json") == 1);
    CHECK(made.count("hard/scene.json") == 1);
    CHECK(made.count("hilly/scene.json") == 1);
    CHECK(made.count("slopes/scene.json") == 1);
    CHECK(made.count("forest/scene.json") == 1);
    std::set<std::string> committed;
    for (const std::string& f : filesUnder(assets))
        if (f.rfind("common/", 0) == 0 || f.rfind("demo/", 0) == 0 || f.rfind("hard/", 0) == 0 ||
            f.rfind("hilly/", 0) == 0 || f.rfind("slopes/", 0) == 0 || f.rfind("forest/", 0) == 0)
            committed.insert(f);
    CHECK(made == committed);
    std::uintmax_t total = 0;
    for (const std::string& f : made) {
        CAPTURE(f);
        const bool identical = slurp(out / f) == slurp(assets / f);  // not printed: files are big
        CHECK(identical);
        total += fs::file_size(out / f);
    }
    CHECK(total < 3'000'000u);  // keep the repository small
    fs::remove_all(out);
}
