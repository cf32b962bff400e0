// viewer/src/option_names.cpp: the names the viewer's options take on the command line and
// in study files (--colour, --mirror, --rasterizer), both ways. Apart from options.cpp,
// whose checks reach the camera and the pick index, so that a reader of study files
// needs no more of the viewer than these names.
#include <viewer/viewer.hpp>

#include <core/error.hpp>

namespace viewer {

MirrorEyes parseMirrorEyes(const std::string& name) {
    if (name == "left") return MirrorEyes::Left;
    if (name == "right") return MirrorEyes::Right;
    if (name == "both") return MirrorEyes::Both;
    throw core::Error("view: --mirror '" + name + "' is not one of left, right, both");
}

ColourMode parseColourMode(const std::string& name) {
    if (name == "file") return ColourMode::File;
    if (name == "height") return ColourMode::HeightJet;
    if (name == "white") return ColourMode::White;
    if (name == "label") return ColourMode::Label;
    if (name == "above-ground") return ColourMode::AboveGround;
    if (name == "class") return ColourMode::Class;
    if (name == "intensity") return ColourMode::Intensity;
    if (name == "return") return ColourMode::Return;
    throw core::Error("view: --colour '" + name +
                      "' is not one of file, height, white, label, above-ground, class, intensity, return");
}

const char* colourModeName(ColourMode mode) {
    switch (mode) {
        case ColourMode::File: return "file";
        case ColourMode::HeightJet: return "height";
        case ColourMode::White: return "white";
        case ColourMode::Label: return "label";
        case ColourMode::AboveGround: return "above-ground";
        case ColourMode::Class: return "class";
        case ColourMode::Intensity: return "intensity";
        case ColourMode::Return: return "return";
    }
    return "?";
}

ColourMode shownColourMode(ColourMode wanted, const ColourSources& cloud) {
    const bool shown = (wanted != ColourMode::AboveGround || cloud.terrain || cloud.height_above_ground) &&
                       (wanted != ColourMode::File || cloud.rgb) &&
                       (wanted != ColourMode::Intensity || (cloud.intensity && !cloud.height_above_ground)) &&
                       (wanted != ColourMode::Return || (cloud.returns && !cloud.height_above_ground));
    return shown ? wanted : ColourMode::HeightJet;
}

Rasterizer parseRasterizer(const std::string& name) {
    if (name == "points") return Rasterizer::Points;
    if (name == "compute") return Rasterizer::Compute;
    throw core::Error("view: --rasterizer '" + name + "' is not one of points, compute");
}

const char* rasterizerName(Rasterizer rasterizer) { return rasterizer == Rasterizer::Compute ? "compute" : "points"; }

}  // namespace viewer
