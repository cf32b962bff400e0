// viewer/src/pcd_stream.cpp: streaming reader for the binary PCD files the generator writes.
#include "pcd_stream.hpp"

#include <engine/error.hpp>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace viewer {

namespace {
struct Field {
    std::string name;
    int size = 4;
    char type = 'F';
    int count = 1;
    std::size_t offset = 0;
};

std::uint32_t readUnsigned(const char* p, int size) {
    switch (size) {
        case 1: return static_cast<std::uint8_t>(*p);
        case 2: { std::uint16_t v; std::memcpy(&v, p, 2); return v; }
        default: { std::uint32_t v; std::memcpy(&v, p, 4); return v; }
    }
}
}  // namespace

bool streamBinaryPcd(const std::filesystem::path& path, CloudFeed& feed, std::size_t chunk_points) {
    if (path.extension() != ".pcd") return false;
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    std::vector<Field> fields;
    std::size_t points = 0;
    bool has_points = false;
    glm::dvec3 origin(0.0);
    std::string line;
    for (int guard = 0; guard < 64 && std::getline(in, line); ++guard) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream ls(line);
        std::string key;
        ls >> key;
        if (key == "#") {
            std::string a, b;
            ls >> a >> b;
            if (a == "ladarvr" && b == "origin") ls >> origin.x >> origin.y >> origin.z;
        } else if (key == "FIELDS") {
            std::string n;
            while (ls >> n) fields.push_back({n});
        } else if (key == "SIZE") {
            for (auto& f : fields) ls >> f.size;
        } else if (key == "TYPE") {
            for (auto& f : fields) ls >> f.type;
        } else if (key == "COUNT") {
            for (auto& f : fields) ls >> f.count;
        } else if (key == "POINTS") {
            has_points = static_cast<bool>(ls >> points);
        } else if (key == "DATA") {
            std::string kind;
            ls >> kind;
            if (kind != "binary") return false;
            break;
        }
    }
    if (!has_points || fields.empty() || !in) return false;
    std::size_t stride = 0;
    const Field *x = nullptr, *y = nullptr, *z = nullptr, *rgb = nullptr, *label = nullptr,
                *view = nullptr, *range = nullptr;
    for (auto& f : fields) {
        if (f.size != 1 && f.size != 2 && f.size != 4 && f.size != 8) return false;
        f.offset = stride;
        stride += static_cast<std::size_t>(f.size) * static_cast<std::size_t>(f.count);
    }
    for (const auto& f : fields) {
        if (f.count != 1) continue;
        if (f.name == "x") x = &f;
        else if (f.name == "y") y = &f;
        else if (f.name == "z") z = &f;
        else if ((f.name == "rgb" || f.name == "rgba") && f.size == 4) rgb = &f;
        else if (f.name == "label" && f.type != 'F' && f.size <= 4) label = &f;
        else if (f.name == "view" && f.type != 'F' && f.size <= 4) view = &f;
        else if (f.name == "range" && f.type == 'F' && f.size == 4) range = &f;
    }
    for (const Field* f : {x, y, z})
        if (!f || f->type != 'F' || f->size != 4) return false;

    feed.setOrigin(origin);
    feed.setFields({rgb != nullptr, label != nullptr, view != nullptr, range != nullptr});
    chunk_points = std::max<std::size_t>(chunk_points, 1);
    std::vector<char> raw;
    for (std::size_t done = 0; done < points;) {
        const std::size_t n = std::min(chunk_points, points - done);
        raw.resize(n * stride);
        in.read(raw.data(), static_cast<std::streamsize>(raw.size()));
        if (static_cast<std::size_t>(in.gcount()) != raw.size())
            throw engine::Error("pcd: " + path.string() + ": data ends after " +
                                std::to_string(done + static_cast<std::size_t>(in.gcount()) / stride) +
                                " of " + std::to_string(points) + " points (truncated file)");
        std::vector<engine::CloudPoint> chunk(n);
        for (std::size_t i = 0; i < n; ++i) {
            const char* p = raw.data() + i * stride;
            auto& out = chunk[i];
            std::memcpy(&out.position.x, p + x->offset, 4);
            std::memcpy(&out.position.y, p + y->offset, 4);
            std::memcpy(&out.position.z, p + z->offset, 4);
            if (rgb) out.rgb = readUnsigned(p + rgb->offset, 4) & 0xFFFFFFu;
            if (label) {
                const std::uint32_t l = readUnsigned(p + label->offset, label->size);
                out.label = l <= 2 ? static_cast<engine::Role>(l) : engine::Role::Environment;
            }
            if (view) out.view = static_cast<std::uint16_t>(readUnsigned(p + view->offset, view->size));
            if (range) std::memcpy(&out.range_m, p + range->offset, 4);
        }
        feed.append(std::move(chunk));
        done += n;
    }
    return true;
}

}  // namespace viewer
