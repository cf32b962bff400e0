// viewer/src/points/point_attributes.cpp: a point's class, stretched intensity and returns
// in one word for the viewer's GPU record.
#include "points/point_attributes.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

namespace viewer {

std::uint32_t packAttributes(std::uint8_t cls, std::uint8_t intensity, unsigned return_number, unsigned returns) {
    return std::uint32_t(cls) | (std::uint32_t(intensity) << 8) | (std::min(return_number, 7u) << 16) |
           (std::min(returns, 7u) << 19);
}

std::uint8_t classOfPacked(float packed) {
    return packed >= 0.0f && packed < float(1u << 22) ? std::uint8_t(std::uint32_t(packed) & 0xFFu) : 0;
}

std::uint8_t classOfLabel(core::Role label) {
    switch (label) {
        case core::Role::Ground: return 2;
        case core::Role::Environment: return 1;
        case core::Role::Target: return 64;
    }
    return 1;
}

std::uint8_t IntensityStretch::apply(std::uint16_t intensity) const {
    if (hi <= lo) return intensity <= lo ? 0 : 255;
    const double t = std::clamp((double(intensity) - lo) / (hi - lo), 0.0, 1.0);
    return std::uint8_t(std::lround(t * 255.0));
}

std::optional<IntensityStretch> IntensityStretch::of(std::span<const core::CloudPoint> points) {
    if (points.empty()) return std::nullopt;
    std::vector<std::uint16_t> values(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) values[i] = points[i].intensity;
    auto percentile = [&](double q) {
        const auto k = static_cast<std::ptrdiff_t>(std::floor(q * double(values.size() - 1)));
        std::nth_element(values.begin(), values.begin() + k, values.end());
        return double(values[std::size_t(k)]);
    };
    IntensityStretch s;
    s.lo = percentile(0.02);
    s.hi = percentile(0.98);
    return s;
}

void PointAttributes::pack(std::span<core::CloudPoint> points, std::span<const unsigned char> records,
                           std::size_t stride) {
    if (!stretch_) stretch_ = IntensityStretch::of(points);
    if (!stretch_) return;
    const bool side = stride >= sizeof(core::ForeignPoint);
    const std::size_t with_records = side ? std::min(points.size(), records.size() / stride) : 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        core::CloudPoint& p = points[i];
        std::uint8_t cls = classOfLabel(p.label);
        if (i < with_records) {
            core::ForeignPoint f;
            std::memcpy(&f, records.data() + i * stride, sizeof f);
            cls = f.classification;
        }
        p.height_above_ground_m = float(packAttributes(cls, stretch_->apply(p.intensity), p.return_number, p.returns));
    }
}

}  // namespace viewer
