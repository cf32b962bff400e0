// The embedded shaders (<shaders/shaders.hpp>) on the real driver: the #line directives
// of the include resolution make the driver's error name the include file's own line,
// and a compile error quotes which file each source-string number is.
#include <test_paths.hpp>
#include <render/egl_context.hpp>
#include <render/shader.hpp>
#include <shaders/shaders.hpp>

#include <core/error.hpp>

#include <doctest/doctest.h>

#include <fstream>
#include <sstream>
#include <string>

namespace {

// 1-based line of the first line of `path` (under shaders/) that contains `text`; 0 if none.
int lineOf(const std::string& path, const std::string& text) {
    std::ifstream in(std::string(test_support::shadersDir()) + "/" + path);
    REQUIRE(in);
    std::string line;
    for (int n = 1; std::getline(in, line); ++n)
        if (line.find(text) != std::string::npos) return n;
    return 0;
}

}  // namespace

TEST_CASE("embedded shaders: a stage with includes names its files by source-string number") {
    CHECK(shaders::viewer_points_vert.starts_with("#version 450 core\n"));
    CHECK(shaders::viewer_points_vert.find("#line 1 1\n") != std::string_view::npos);
    CHECK(shaders::viewer_points_vert.find("#include") == std::string_view::npos);
    CHECK(shaders::viewer_points_vert_files ==
          "0 = viewer_points.vert, 1 = include/jet.glsl, 2 = include/viewer_point_style.glsl");
    CHECK(shaders::point_splat_vert_files == "0 = point_splat.vert");
    CHECK(shaders::metric_count_mask_comp_files == "0 = metric_count_mask.comp, 1 = include/metric_counts.glsl");
}

TEST_CASE("embedded shaders: the driver's error in an included file points to that file and line") {
    render::EglContext context;
    const std::string good = "int bin = 0;";
    const int line = lineOf("include/jet.glsl", good);
    REQUIRE(line > 0);
    std::string broken(shaders::viewer_points_vert);
    const std::size_t at = broken.find(good);
    REQUIRE(at != std::string::npos);
    broken.replace(at, good.size(), "int bin = undeclared_name;");
    try {
        render::Program bad("broken points", {{GL_VERTEX_SHADER, broken, shaders::viewer_points_vert_files}});
        FAIL("a broken shader compiled");
    } catch (const core::Error& e) {
        const std::string message = e.what();
        CAPTURE(message);
        // Mesa writes "1:10(15): error", NVIDIA "1(10) : error": source string 1, that line.
        const std::string n = std::to_string(line);
        CHECK((message.find("1:" + n + "(") != std::string::npos || message.find("1(" + n + ")") != std::string::npos));
        CHECK(message.find("(source strings: 0 = viewer_points.vert, 1 = include/jet.glsl, 2 = "
                           "include/viewer_point_style.glsl)") != std::string::npos);
        CHECK(message.find('\n') == std::string::npos);
    }
}
