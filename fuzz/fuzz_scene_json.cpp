// fuzz/fuzz_scene_json.cpp: libFuzzer target for io::loadSceneJson. The JSON names
// meshes relative to tests/data/scenes/basic/ (box.obj, ground.obj), so valid inputs load
// real meshes through Assimp. The contract: a Scene or an core::Error, nothing else
// (no other exception type, no crash, no sanitizer report).
#include <core/error.hpp>
#include "check_message.hpp"
#include <io/scene_file.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    // Mesh paths only resolve inside the test scene directory; absolute or ../ paths
    // reach the rest of the file system, which is Assimp's attack surface, not ours.
    if (text.find('/') != std::string_view::npos || text.find('\\') != std::string_view::npos) return -1;
    io::SceneLoadOptions options;
    options.skip_nonfinite = (size % 2) == 1;
    try {
        const core::Scene scene = io::loadSceneJson(text, LADARVR_TEST_DATA_DIR "/scenes/basic/fuzz.json", options);
        // An accepted scene has finite vertices and in-range indices.
        for (const core::Mesh& m : scene.meshes) {
            for (const glm::vec3& v : m.vertices)
                if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) std::abort();
            for (const glm::uvec3& t : m.triangles)
                if (t.x >= m.vertices.size() || t.y >= m.vertices.size() || t.z >= m.vertices.size()) std::abort();
        }
    } catch (const core::Error& e) {
        fuzz::checkMessage(e.what());
        // LADARVR_FUZZ_VERBOSE=1 shows why an input was refused (to check the seeds).
        if (std::getenv("LADARVR_FUZZ_VERBOSE")) std::fprintf(stderr, "refused: %s\n", e.what());
    }
    return 0;
}
