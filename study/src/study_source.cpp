// study/src/study_source.cpp: clouds for the trials, from files or generated from scenes.
#include <study/study_source.hpp>

#include <core/error.hpp>
#include <detect/boosted_detector.hpp>
#include <detect/cloud_units.hpp>
#include <detect/cluster_detector.hpp>
#include <io/candidates_file.hpp>
#include <io/cloud_io.hpp>
#include <io/scene_file.hpp>
#include <platform/safe_file.hpp>
#include <sim/generator.hpp>
#include <sim/ground_units.hpp>
#include <viewer/cloud_feed.hpp>
#include <viewer/open_point_source.hpp>

#include <cstdio>
#include <exception>
#include <map>
#include <utility>

namespace study {
namespace {

// The candidates a condition's detector finds in a trial's cloud (best first, as `ladarvr
// detect` writes them), once per cloud and detector: found in metres, centres in the
// cloud's coordinates, sizes in metres.
std::vector<core::Candidate> detectedCandidates(const PlanTrial& t, const sim::CoordinateUnits& units) {
    const std::string line = "study: detecting candidates in " + t.cloud.string() + " with " +
                             (t.detector == "baseline" ? std::string("the clustering baseline") : t.detector);
    std::fprintf(stderr, "ladarvr: %s\n", platform::messageLine(line).c_str());
    core::PointCloud cloud = io::readCloud(t.cloud);
    detect::scaleToMetres(cloud, units);
    std::vector<detect::Detection> found;
    if (t.detector == "baseline") {
        found = detect::ClusterDetector(detect::ClusterOptions{}).detect(cloud);
    } else {
        detect::BoostedOptions o;
        o.model = t.detector;
        found = detect::BoostedDetector(o).detect(cloud);
    }
    std::vector<core::Candidate> out;
    out.reserve(found.size());
    for (detect::Detection& d : found) out.push_back(std::move(d.candidate));
    return detect::centresInUnits(std::move(out), cloud.origin, units);
}

}  // namespace

sim::GenerateOptions sceneGenerateOptions(const Plan& plan) {
    sim::GenerateOptions g;
    g.orbit.xres = plan.xres;
    g.orbit.yres = plan.yres;
    g.orbit.views = plan.views;
    if (plan.ground == "white")
        g.white = true;
    else
        g.ground.method = sim::parseGroundMethod(plan.ground, "study: generate.ground");
    sim::validate(g);
    return g;
}

StudySource::StudySource(const Plan& plan, std::vector<int> order, int first, bool with_candidates)
    : plan_(plan), order_(std::move(order)), first_(first) {
    std::map<std::pair<std::string, std::string>, std::vector<core::Candidate>> detected;
    for (const PlanTrial& t : plan_.trials) {
        scenes_.push_back(t.scene.empty() ? nullptr : std::make_shared<const core::Scene>(io::loadScene(t.scene)));
        // The trial's cloud's units (a generated cloud's are metres): the viewer draws the
        // candidates in them.
        const sim::CoordinateUnits units =
            t.cloud.empty() || !with_candidates ? sim::CoordinateUnits{} : sim::readCoordinateUnits(t.cloud, "study");
        if (!with_candidates) {
            candidates_.emplace_back();
        } else if (!t.detector.empty()) {
            if (t.cloud.empty()) throw core::Error("study: a condition's detector runs on cloud files, not scenes");
            const auto key = std::make_pair(t.cloud.string(), t.detector);
            auto it = detected.find(key);
            if (it == detected.end()) it = detected.emplace(key, detectedCandidates(t, units)).first;
            candidates_.push_back(detect::sizesInCloudUnits(it->second, detect::candidateUnits(units), units,
                                                            "study: " + t.cloud.string()));
        } else if (t.candidates.empty()) {
            candidates_.emplace_back();
        } else {
            io::CandidateUnits file_units;
            std::vector<core::Candidate> read = io::readCandidates(t.candidates, &file_units);
            candidates_.push_back(detect::sizesInCloudUnits(std::move(read), file_units, units,
                                                            "study: candidates " + t.candidates.string()));
        }
    }
    sceneGenerateOptions(plan_);  // validated before the window opens
}

StudySource::~StudySource() { join(); }

void StudySource::end(int) { join(); }

void StudySource::join() {
    if (generator_.joinable()) generator_.join();
    terrain_.job.reset();  // stops and joins its thread
    terrain_.feed.reset();
}

viewer::ColourMode StudySource::startColour(int trial) const {
    for (int k = trial; k >= 0; --k)
        if (const std::optional<viewer::ColourMode>& c = planTrial(k).colour) return *c;
    return run_colour_;
}

viewer::TrialSetup StudySource::begin(int trial, viewer::CloudFeed& feed) {
    join();  // end() did already, unless the viewer skipped it
    const std::size_t k = static_cast<std::size_t>(order_[static_cast<std::size_t>(trial)]);
    const PlanTrial& t = plan_.trials[k];
    viewer::TrialSetup setup;
    if (!t.cloud.empty()) {
        // Streamed whole, a COPC file too: a trial's hit and target distance are judged
        // against every target point of the cloud, which resident nodes alone would not
        // give (a study indexes nothing: its clouds are read as the plan names them).
        viewer::OpenSourceOptions open;
        open.feed = &feed;
        viewer::openPointSource(t.cloud, viewer::choosePath(t.cloud, nullptr, viewer::EveryPoint::Needed), open);
        // Its ground, for above-ground colours, while the ready screen is up.
        if (start_terrain_ && startColour(trial) == viewer::ColourMode::AboveGround) {
            terrain_ = start_terrain_(t.cloud);
            setup.terrain = terrain_.feed;
        }
    } else {
        generator_ = std::thread([&feed, scene = scenes_[k], g = sceneGenerateOptions(plan_)] {
            try {
                feed.feedCloud(sim::generateCloud(*scene, g));
            } catch (const std::exception& e) {
                feed.finish(std::string("generate: ") + e.what());
            }
        });
    }
    setup.name = t.name;
    setup.candidates = candidates_[k];
    setup.time_limit_s = t.time_limit_s;
    setup.min_ready_s = t.min_ready_s;
    setup.colour = t.colour;
    setup.eye_dome = t.eye_dome;
    setup.start_mode = t.start_mode;
    setup.tools = t.tools;
    setup.cut = t.cut;
    setup.cut_radius_m = t.cut_radius_m;
    return setup;
}

}  // namespace study
