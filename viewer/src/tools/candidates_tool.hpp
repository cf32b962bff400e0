// viewer/src/tools/candidates_tool.hpp: an ATR's candidate detections (core/candidates.hpp)
// for the operator to validate: oriented boxes coloured by score (red = likely target,
// yellow = unlikely), the one the pointer's ray meets highlighted, confirmed ones green,
// rejected ones grey. Coordinates: world in the file, local (world - origin) here.
#pragma once
#include "ui/overlay_renderer.hpp"
#include "tools/pointer_tool.hpp"

#include <core/candidates.hpp>
#include <viewer/trial.hpp>

#include <nlohmann/json.hpp>

#include <optional>
#include <vector>

namespace viewer {

/// Distance along the ray to where it enters the oriented box (0 when it starts inside),
/// or none when it misses. `direction` unit length; box centre in the ray's frame.
std::optional<double> rayBoxDistance(const LocalRay& ray, const glm::dvec3& centre, const glm::dvec3& size_m,
                                     double yaw_deg);

/// Whether the oriented box meets the cutting volume's sphere (always, with the volume off).
bool boxMeetsCut(const CutVolume& cut, const glm::dvec3& centre, const glm::dvec3& size_m, double yaw_deg);

class CandidatesTool final : public Tool {
  public:
    /// `origin`: world coordinates of the cloud's local frame.
    void set(std::vector<core::Candidate> candidates, const glm::dvec3& origin);
    ToolStage stage() const override { return ToolStage::Aim; }
    bool empty() const { return candidates_.empty(); }
    std::size_t size() const { return candidates_.size(); }
    const core::Candidate& candidate(std::size_t i) const { return candidates_[i]; }
    Verdict verdict(std::size_t i) const { return verdicts_[i]; }
    /// The candidate the ray meets first, if any, among those the cutting volume `cut`
    /// leaves shown; a box wholly outside an enabled `cut` is hidden (not drawn, not pointed).
    void update(const std::optional<LocalRay>& ray, const CutVolume& cut = {});
    void update(const OperatorInput&, const ToolFrame& frame) override {
        update(frame.ray, frame.cut ? *frame.cut : CutVolume{});
    }
    /// Whether box `i` is shown (the cutting volume of the last update meets it).
    bool shown(std::size_t i) const;
    std::optional<std::size_t> pointed() const { return pointed_; }
    /// Gives the pointed candidate a verdict; returns its index, none when no box is pointed at.
    std::optional<std::size_t> decide(Verdict verdict);
    /// Gives the candidate of id `id` a verdict (a replay's recorded one); returns its
    /// index, none when no candidate has that id.
    std::optional<std::size_t> setVerdict(const std::string& id, Verdict verdict);
    /// Colours by score unless reviewed; `highlight` draws every box brighter and thicker.
    void draw(OverlayList& out, bool highlight) const;
    void draw(OverlayList& out) const override { draw(out, highlight_); }
    /// Every box brighter and thicker (the panel's switch).
    bool& highlight() { return highlight_; }
    /// [{"id", "verdict"}, ...] in the file's order.
    nlohmann::json log() const;
    /// The end of the run's "candidates" (log()).
    void logRun(nlohmann::json& summary) const override { summary["candidates"] = log(); }
    /// No candidates until the new trial's are placed.
    void beginTrial() override { set({}, glm::dvec3(0.0)); }
    /// The panel's highlight switch and the number of boxes.
    void describe(PanelView& v) override;

  private:
    std::vector<core::Candidate> candidates_;
    std::vector<Verdict> verdicts_;
    glm::dvec3 origin_{0.0};
    std::optional<std::size_t> pointed_;
    CutVolume cut_;
    bool highlight_ = false;
};

}  // namespace viewer
