// corpus: one item, from its plan to its folder and manifest line. The cloud is made in
// memory (its points per label are counted there) and written with the other files into
// a hidden folder that moves into place whole (platform/output_folder.hpp).
#include <corpus/item.hpp>

#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <io/scene_file.hpp>
#include <metric/clouds.hpp>
#include <metric/report.hpp>
#include <metric/visibility.hpp>
#include <platform/output_folder.hpp>
#include <platform/sha256.hpp>
#include <platform/test_hold.hpp>

#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>

namespace corpus {

namespace fs = std::filesystem;
using nlohmann::json;

bool isItemFile(const std::string& name) {
    return name == "scene.json" || name == "cloud.pcd" || name == "cloud.ply" || name == "cloud.las" ||
           name == "cloud.laz" || name == "summary.json" || name == "views.csv";
}

namespace {

json optional(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }
json finite(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }
json triple(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

// The test hook that holds a build mid-item (see item.hpp): with
// LADARVR_TEST_HOLD_ITEM="<index>:<fifo>", item <index> stops with its files written
// in its hidden folder and not yet moved into place, tells the FIFO "held <id>", then
// waits until something opens the FIFO for writing and closes it.
void holdForTest(std::size_t index, const std::string& id) {
    const char* hook = std::getenv("LADARVR_TEST_HOLD_ITEM");
    if (!hook) return;
    const std::string text = hook;
    const std::size_t colon = text.find(':');
    if (colon == std::string::npos || text.substr(0, colon) != std::to_string(index)) return;
    platform::holdOnFifo(text.substr(colon + 1), "held " + id + "\n", "corpus: LADARVR_TEST_HOLD_ITEM",
                         "<index>:<a FIFO>");
}

}  // namespace

ItemOutcome buildItem(const Planner& planner, std::size_t index, const fs::path& out, int threads) {
    const auto t0 = std::chrono::steady_clock::now();
    const Spec& spec = planner.spec();
    ItemPlan plan = planner.plan(index);
    const fs::path items = fs::absolute(out / "items").lexically_normal();
    const fs::path folder = items / plan.id;
    plan.options.threads = threads;
    plan.options.progress = false;

    // The scene is loaded from the absolute-path text (the item folder may not exist yet);
    // the file written names the same meshes relative to the item folder.
    const core::Scene scene = io::loadSceneJson(plan.sceneText({}), folder / "scene.json");
    core::Bounds target_box;
    for (const core::Mesh& m : scene.meshes)
        if (m.role == core::Role::Target)
            for (const glm::vec3& v : m.vertices) target_box.extend(scene.origin + glm::dvec3(v));

    sim::GenerateStats st;
    core::PointCloud cloud = sim::generateCloud(scene, plan.options, &st);
    std::uint64_t per_label[core::kRoleCount] = {0, 0, 0};
    for (const core::CloudPoint& p : cloud.points) ++per_label[std::size_t(p.label) % core::kRoleCount];

    platform::AtomicFolder files(folder, isItemFile);
    std::vector<std::string> names = {"scene.json", spec.cloudName()};
    files.writeFile("scene.json", plan.sceneText(folder));
    io::writeCloud(files.path(spec.cloudName()), cloud, spec.format);
    files.adopt(spec.cloudName());
    cloud.points = {};
    double metric_mean = std::nan(""), exact_mean = std::nan(""), visible_mean = std::nan("");
    int views_used = 0;
    if (spec.metric.enabled) {
        metric::MetricClouds clouds = metric::generateClouds(scene, plan.options);
        metric::Evaluator evaluator(clouds, &scene);
        metric::MetricOptions mo;
        mo.orbit.views = spec.metric.views;
        mo.width = spec.metric.width;
        mo.height = spec.metric.height;
        mo.picture_view = -1;
        const metric::MetricResult result = evaluator.run(mo);
        files.writeFile("summary.json", metric::summaryJson(result));
        files.writeFile("views.csv", metric::viewsCsv(result));
        names.insert(names.end(), {"summary.json", "views.csv"});
        metric_mean = result.metric_mean;
        exact_mean = result.has_exact ? result.exact_mean : std::nan("");
        visible_mean = result.visible_mean;
        views_used = result.views_used;
    }
    // Sizes and digests of the files as written (read back from the page cache), then
    // the folder moves into place.
    json listed = json::object();
    for (const std::string& name : names) {
        const platform::FileDigest d = platform::sha256File(files.path(name), "corpus");
        listed[name] = {{"bytes", d.bytes}, {"sha256", d.sha256}};
    }
    holdForTest(index, plan.id);
    files.commit();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    json line;
    line["id"] = plan.id;
    line["index"] = plan.index;
    line["seed"] = spec.seed;
    line["item_seed"] = plan.item_seed;
    json values = json::object();
    for (const auto& [key, v] : plan.values) values[key] = v;
    line["values"] = values;
    json target = json::object();
    if (!target_box.empty()) {
        target["file"] = plan.target_file;
        target["position"] = triple(plan.target_position_world);
        target["yaw_deg"] = plan.target_yaw_deg;
        target["box_min"] = triple(target_box.lo);
        target["box_max"] = triple(target_box.hi);
        target["placement_draws"] = plan.placement_draws;
    }
    line["target"] = target;
    line["centre"] = triple(st.centre);
    line["environment_kept"] = plan.environment_kept;
    line["environment_total"] = plan.environment_total;
    line["generate"] = plan.generateArgs();
    line["points_per_label"] = {{"ground", per_label[0]}, {"environment", per_label[1]}, {"target", per_label[2]}};
    line["points"] = st.points;
    line["misses"] = st.misses;
    line["rays"] = st.rays;
    line["ground_precision"] = optional(st.ground_precision);
    line["ground_recall"] = optional(st.ground_recall);
    line["target_kept_coloured"] = optional(st.target_kept);
    line["environment_kept_coloured"] = optional(st.environment_kept);
    line["metric"] = finite(metric_mean);
    line["exact"] = finite(exact_mean);
    line["visible"] = finite(visible_mean);
    line["metric_views_used"] = views_used;
    line["files"] = listed;
    line["seconds"] = seconds;

    ItemOutcome o;
    o.id = plan.id;
    o.manifest_line = line.dump();
    o.seconds = seconds;
    o.points = st.points;
    o.metric = metric_mean;
    return o;
}

}  // namespace corpus
