// viewer/offscreen_stereo.hpp: the viewer's per-eye drawing without a window or an OpenXR
// session. Both eyes of a head pose are drawn into two offscreen images at headset size by
// the renderer `ladarvr view` uses (streamed cells, frustum culling and point budget,
// eye-dome lighting, mode indicator), so the headset path's GPU work can run, be checked
// and be timed on any GPU with a headless context (render::EglContext).
#pragma once
#include <viewer/mode_controller.hpp>
#include <viewer/point_source.hpp>
#include <viewer/viewer.hpp>

#include <core/frames.hpp>
#include <core/point_cloud.hpp>

#include <glm/glm.hpp>

#include <cstddef>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace viewer {

/// Eye images and optics of the offscreen pair; the defaults are an Index / Vive Pro class HMD.
struct StereoOptions {
    int eye_width_px = 1440, eye_height_px = 1600;  // 16..8192 each
    double ipd_m = 0.064;                           // eye separation along the head's x axis
    /// OpenXR-style FoV angles of both eyes (radians; left and down negative).
    double angle_left_rad = -0.95, angle_right_rad = 0.95;
    double angle_up_rad = 1.0, angle_down_rad = -1.0;
};

/// Throws core::Error("view: offscreen eye size WxH: allowed 16..8192 pixels each") and
/// the like for values out of range.
void validate(const StereoOptions& o);

class OffscreenStereo {
  public:
    /// Needs a current OpenGL 4.5 core context, which must outlive this object. Compiles
    /// the viewer's programs and allocates both eye images. Throws core::Error on bad
    /// options or a shader failure.
    explicit OffscreenStereo(const StereoOptions& options = {});
    ~OffscreenStereo();
    OffscreenStereo(const OffscreenStereo&) = delete;
    OffscreenStereo& operator=(const OffscreenStereo&) = delete;

    /// Puts every point of `cloud` on the GPU, in the viewer's LOD order and cells.
    void upload(const core::PointCloud& cloud);

    /// What one stream() call did and how long each step took (CPU milliseconds).
    struct StreamStep {
        double select_ms = 0.0;  // the source's choice for the last planned view (traversal + scheduling)
        double poll_ms = 0.0;    // taking the nodes that arrived
        double upload_ms = 0.0;  // following residency on the GPU, uploads included
        std::size_t added_nodes = 0;
        std::size_t uploaded_points = 0;
    };
    /// Draws `source`'s resident nodes from now on, besides what upload() put on the GPU;
    /// `source` must outlive this object. Then each stream() does what the viewer's frame
    /// loop does before it plans a frame: hands the source the view planned last
    /// (PointSource::select), takes what arrived (poll) and uploads at most `upload_points`
    /// points into a GPU arena of at most `gpu_bytes` (0 = unlimited; the viewer's
    /// --gpu-mb). Never waits for the source's workers.
    void follow(PointSource& source, std::size_t gpu_bytes = 0);
    StreamStep stream(std::size_t upload_points);
    /// Points that reached the followed source but are not on the GPU yet.
    std::size_t pendingPoints() const;
    /// Bytes of the point buffers on the GPU now and at most so far, and the nodes the
    /// source wants that are resident but found no room in the arena at the last stream().
    std::size_t gpuBytes() const;
    std::size_t gpuBytesPeak() const;
    std::size_t gpuNodesRefused() const;
    std::size_t uploadedPoints() const;
    std::size_t cellCount() const;
    /// Bounds (local frame) of everything uploaded; its centre is the orbit centre.
    const core::Bounds& bounds() const;

    /// World(local)-to-eye view of eye 0 (left) or 1 (right) when the head is at `head`
    /// (pose in the cloud's local frame), and the projection both eyes share.
    glm::dmat4 eyeView(const RigPose& head, int eye) const;
    glm::dmat4 projection() const;

    /// Picks what the following draws show, as the viewer does every frame: cells outside
    /// both eyes' frusta get nothing (when `cull`), the others share `point_budget` points
    /// per eye (0 = unlimited). Without a call, each eye draws every uploaded point of
    /// every cell in its frustum. Never throws.
    void plan(const RigPose& head, std::size_t point_budget, bool cull);
    /// What the operator works on (lod.hpp's LodFocus): from the next plan() its cells are
    /// drawn whole whatever the budget, and the followed source loads its nodes first.
    void setFocus(LodFocus focus);
    /// Draws both eyes into their images. Returns the points drawn, both eyes together.
    /// Never throws (GL errors are logged).
    std::size_t draw(const RigPose& head, const ViewStyle& style, ViewMode mode);
    /// Points the last draw() drew in eye 0 and in eye 1.
    std::array<std::size_t, 2> lastDrawnPerEye() const;
    /// The view the last plan() chose from (both eyes' frusta when culling, their mean
    /// position, the budget), as a point source is handed it.
    const std::optional<SourceView>& lastView() const;

    /// GPU time per pass of the draws (timestamp queries; reading them waits for the GPU):
    /// off by default. `raster_ms` GL_POINTS or the compute depth pass, `colour_ms` the
    /// compute colour pass, `resolve_ms` eye-dome lighting; summed over `eyes` eye draws.
    struct PassTimes {
        double raster_ms = 0.0, colour_ms = 0.0, resolve_ms = 0.0;
        int eyes = 0;
    };
    void setPassTiming(bool on);
    /// The passes' times of the draws since the last call.
    PassTimes takePassTimes();
    /// Whether the compute rasteriser reduces equal pixels within a subgroup (where the
    /// context can); on by default.
    bool subgroupAvailable() const;
    void setSubgroupReduction(bool on);
    /// Pixels of eye 1 (the last drawn) that a point covers: the points drawn per pixel
    /// are lastDrawnPerEye()[1] over it. Waits for the GPU.
    std::size_t coveredPixels() const;

    /// Eye 0's or 1's image as RGBA8, rows bottom-up (glReadPixels order).
    std::vector<std::uint8_t> readEye(int eye) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace viewer
