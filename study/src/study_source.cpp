// study/src/study_source.cpp: clouds for the trials, from files or generated from scenes.
#include <study/study_source.hpp>

#include <io/candidates_file.hpp>
#include <io/scene_file.hpp>
#include <sim/generator.hpp>
#include <viewer/cloud_feed.hpp>

#include <exception>

namespace study {

StudySource::StudySource(const Plan& plan, std::vector<int> order, int first)
    : plan_(plan), order_(std::move(order)), first_(first) {
    for (const PlanTrial& t : plan_.trials) {
        scenes_.push_back(t.scene.empty() ? nullptr : std::make_shared<const core::Scene>(io::loadScene(t.scene)));
        candidates_.push_back(t.candidates.empty() ? std::vector<core::Candidate>{} : io::readCandidates(t.candidates));
    }
    sim::GenerateOptions check;
    check.orbit.xres = plan_.xres;
    check.orbit.yres = plan_.yres;
    check.orbit.views = plan_.views;
    sim::validate(check);
}

StudySource::~StudySource() { join(); }

void StudySource::end(int) { join(); }

void StudySource::join() {
    if (generator_.joinable()) generator_.join();
}

viewer::TrialSetup StudySource::begin(int trial, viewer::CloudFeed& feed) {
    join();  // end() did already, unless the viewer skipped it
    const std::size_t k = static_cast<std::size_t>(order_[static_cast<std::size_t>(trial)]);
    const PlanTrial& t = plan_.trials[k];
    if (!t.cloud.empty()) {
        feed.startFileLoader(t.cloud);
    } else {
        sim::GenerateOptions g;
        g.orbit.xres = plan_.xres;
        g.orbit.yres = plan_.yres;
        g.orbit.views = plan_.views;
        generator_ = std::thread([&feed, scene = scenes_[k], g] {
            try {
                feed.feedCloud(sim::generateCloud(*scene, g));
            } catch (const std::exception& e) {
                feed.finish(std::string("generate: ") + e.what());
            }
        });
    }
    viewer::TrialSetup setup;
    setup.name = t.name;
    setup.candidates = candidates_[k];
    setup.time_limit_s = t.time_limit_s;
    setup.min_ready_s = t.min_ready_s;
    setup.colour = t.colour;
    setup.eye_dome = t.eye_dome;
    setup.start_mode = t.start_mode;
    return setup;
}

}  // namespace study
