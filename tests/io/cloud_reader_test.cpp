// io::CloudReader: every malformed header of the shared table refused with its one
// line, chunked reads equal to whole reads in every format (also across the file
// window and text blocks), non-finite points dropped and counted, zero padding, special
// files, and liblzf on PCL's compressed files.
#include <bad_clouds.hpp>
#include <test_files.hpp>
#include <test_paths.hpp>
#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <io/cloud_reader.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <sys/stat.h>

namespace fs = std::filesystem;
using io::CloudFormat;
using test_support::slurp;
using test_support::TempDir;

namespace {

const fs::path kData = fs::path(test_support::dataDir()) / "io";

void spit(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

std::string errorOf(const fs::path& p) {
    try {
        io::readCloud(p);
    } catch (const core::Error& e) {
        return e.what();
    }
    return "no error";
}

std::string prefixOf(const fs::path& p) { return (p.extension() == ".ply" ? "ply: " : "pcd: ") + p.string() + ": "; }

core::PointCloud knownCloud(std::size_t n) {
    core::PointCloud c;
    c.origin = {1.0e6, -2.0e6, 35.5};
    for (std::size_t i = 0; i < n; ++i) {
        core::CloudPoint p;
        p.position = {float(i) * 0.37f - 1000.0f, -float(i % 1013) * 1.25f, float(i % 7) / 3.0f};
        p.rgb = core::packRgb(std::uint8_t(i), std::uint8_t(i >> 8), std::uint8_t(i * 31));
        p.label = core::Role(i % 3);
        p.view = std::uint16_t(i % 65536);
        p.range_m = 100.0f + float(i) / 8.0f;
        c.points.push_back(p);
    }
    return c;
}

bool samePoints(const std::vector<core::CloudPoint>& a, const std::vector<core::CloudPoint>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (std::memcmp(&a[i].position, &b[i].position, sizeof a[i].position) != 0 || a[i].rgb != b[i].rgb ||
            a[i].label != b[i].label || a[i].view != b[i].view || a[i].range_m != b[i].range_m)
            return false;
    return true;
}

}  // namespace

TEST_CASE("cloud_reader: every bad file of the shared table is refused with its one line") {
    TempDir dir("bad_clouds");
    for (const test_support::BadCloud& bad : test_support::badClouds()) {
        CAPTURE(bad.name);
        const fs::path p = dir.path / bad.name;
        spit(p, bad.bytes);
        CHECK(errorOf(p) == prefixOf(p) + bad.message);
        // In memory too (the fuzzing entry point), with the same message.
        std::string in_memory;
        try {
            io::readCloudData(bad.bytes, bad.name);
        } catch (const core::Error& e) {
            in_memory = e.what();
        }
        CHECK(in_memory == prefixOf(bad.name) + bad.message);
    }
}

TEST_CASE("cloud_reader: a bad header is refused when the reader is opened, before any point") {
    TempDir dir("open_checks");
    for (const test_support::BadCloud& bad : test_support::badClouds()) {
        // Only the records themselves (labels, text values, the end of text data) are
        // checked as they are read; everything else fails in the constructor.
        CAPTURE(bad.name);
        const fs::path p = dir.path / bad.name;
        spit(p, bad.bytes);
        if (bad.in_records) {
            io::CloudReader reader(p);
            std::vector<core::CloudPoint> out;
            CHECK_THROWS_AS(while (reader.nextChunk(out, 1)){}, core::Error);
        } else {
            CHECK_THROWS_AS(io::CloudReader{p}, core::Error);
        }
    }
}

TEST_CASE("cloud_reader: chunked reads give the whole cloud in every format") {
    TempDir dir("chunks");
    // 60,000 points: ~1.4 MB binary and ~4 MB of text, so chunks cross the reader's
    // 1 MiB file window and text tokens cross its blocks.
    const core::PointCloud cloud = knownCloud(60000);
    for (CloudFormat f :
         {CloudFormat::PcdBinary, CloudFormat::PcdAscii, CloudFormat::PlyBinary, CloudFormat::PlyAscii}) {
        const bool ply = f == CloudFormat::PlyBinary || f == CloudFormat::PlyAscii;
        const fs::path p = dir.path / (std::string("c") + std::to_string(int(f)) + (ply ? ".ply" : ".pcd"));
        io::writeCloud(p, cloud, f);
        for (std::size_t chunk : {std::size_t(1), std::size_t(7777), std::size_t(60000), std::size_t(1) << 20}) {
            if (chunk == 1 && (f == CloudFormat::PcdAscii || f == CloudFormat::PlyAscii)) continue;  // slow
            CAPTURE(int(f));
            CAPTURE(chunk);
            io::CloudReader reader(p);
            CHECK(reader.origin() == cloud.origin);
            CHECK(reader.declaredPoints() == 60000);
            CHECK(reader.pointsBound() <= 60000);
            std::vector<core::CloudPoint> all;
            std::size_t calls = 0;
            while (reader.nextChunk(all, chunk)) {
                ++calls;
                CHECK(all.size() == std::min(calls * chunk, std::size_t(60000)));
            }
            CHECK(calls == (60000 + chunk - 1) / chunk);
            CHECK(samePoints(all, cloud.points));
            CHECK(reader.pointsRead() == 60000);
            CHECK(reader.droppedNonFinite() == 0);
            CHECK(reader.warning().empty());
            CHECK_FALSE(reader.nextChunk(all, chunk));  // stays at the end
        }
    }
}

TEST_CASE("cloud_reader: forEachChunk hands every chunk over in order, and errors from either side") {
    TempDir dir("read_ahead");
    // 3 full chunks and a part: the reading thread is ahead of fn at every handover.
    const std::size_t n = 3 * io::CloudReader::kChunkPoints + 12345;
    const core::PointCloud cloud = knownCloud(n);
    const fs::path p = dir.path / "c.pcd";
    io::writeCloud(p, cloud, CloudFormat::PcdBinary);
    {
        io::CloudReader reader(p);
        std::vector<core::CloudPoint> all;
        std::vector<std::size_t> sizes;
        io::forEachChunk(reader, [&](std::vector<core::CloudPoint>& chunk) {
            sizes.push_back(chunk.size());
            all.insert(all.end(), chunk.begin(), chunk.end());
            chunk.clear();  // fn may empty its chunk; the next one is whole regardless
        });
        CHECK(sizes == std::vector<std::size_t>{io::CloudReader::kChunkPoints, io::CloudReader::kChunkPoints,
                                                io::CloudReader::kChunkPoints, 12345});
        CHECK(samePoints(all, cloud.points));
    }
    {
        // fn's error stops the loop after the chunk that threw.
        io::CloudReader reader(p);
        std::size_t calls = 0;
        CHECK_THROWS_WITH_AS(io::forEachChunk(reader,
                                              [&](std::vector<core::CloudPoint>&) {
                                                  if (++calls == 2) throw core::Error("fn: stop");
                                              }),
                             "fn: stop", core::Error);
        CHECK(calls == 2);
    }
    {
        // The reader's error in the second chunk (a word where a number goes) reaches the
        // caller once fn has had the first chunk, whole.
        const core::PointCloud small = knownCloud(io::CloudReader::kChunkPoints + 1000);
        const fs::path text = dir.path / "t.pcd";
        io::writeCloud(text, small, CloudFormat::PcdAscii);
        std::string bytes = slurp(text);
        std::size_t at = bytes.find("DATA ascii\n");
        REQUIRE(at != std::string::npos);
        at += 11;
        for (std::size_t line = 0; line < io::CloudReader::kChunkPoints + 500; ++line) at = bytes.find('\n', at) + 1;
        bytes.replace(at, 1, "x");
        spit(text, bytes);
        std::vector<std::size_t> sizes;
        std::string error;
        try {
            io::CloudReader reader(text);
            io::forEachChunk(reader, [&](std::vector<core::CloudPoint>& chunk) { sizes.push_back(chunk.size()); });
        } catch (const core::Error& e) {
            error = e.what();
        }
        CHECK(sizes == std::vector<std::size_t>{io::CloudReader::kChunkPoints});
        CHECK(error.rfind("pcd: " + text.string() + ": ", 0) == 0);
        CHECK(error.find("of point " + std::to_string(io::CloudReader::kChunkPoints + 500) + " is not a number") !=
              std::string::npos);
    }
}

TEST_CASE("cloud_reader: NaN and inf points are dropped and counted, everywhere") {
    TempDir dir("nonfinite");
    const float inf = std::numeric_limits<float>::infinity(), nan = std::nanf("");
    core::PointCloud cloud = knownCloud(1000);
    cloud.points[3].position.x = inf;
    cloud.points[500].position.z = nan;
    cloud.points[999].range_m = -inf;
    std::vector<core::CloudPoint> finite;
    for (std::size_t i = 0; i < 1000; ++i)
        if (i != 3 && i != 500 && i != 999) finite.push_back(cloud.points[i]);
    for (CloudFormat f :
         {CloudFormat::PcdBinary, CloudFormat::PcdAscii, CloudFormat::PlyBinary, CloudFormat::PlyAscii}) {
        const bool ply = f == CloudFormat::PlyBinary || f == CloudFormat::PlyAscii;
        const fs::path p = dir.path / (std::string("n") + std::to_string(int(f)) + (ply ? ".ply" : ".pcd"));
        io::writeCloud(p, cloud, f);
        CAPTURE(int(f));
        const core::PointCloud back = io::readCloud(p);
        CHECK(samePoints(back.points, finite));
        io::CloudReader reader(p);
        std::vector<core::CloudPoint> out;
        while (reader.nextChunk(out, 100)) {}
        CHECK(out.size() == 997);
        CHECK(reader.pointsRead() == 1000);
        CHECK(reader.droppedNonFinite() == 3);
        CHECK(reader.warning() == prefixOf(p) +
                                      "dropped 3 of 1000 points with a non-finite x, y, z or "
                                      "range (NaN or inf)");
    }
    SUBCASE("text spellings and doubles beyond float range") {
        const std::string pcd =
            "FIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nWIDTH 6\nDATA ascii\n"
            "1 2 3\nnan 0 0\n0 inf 0\n0 0 -inf\n1e39 0 0\n4 5 1e400\n";
        const core::PointCloud r = io::readCloudData(pcd, "spell.pcd");
        REQUIRE(r.points.size() == 1);
        CHECK(r.points[0].position == glm::vec3(1, 2, 3));
        const double big = 1e300;
        std::string bin = "FIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nWIDTH 2\nDATA binary\n";
        for (double v : {1.0, 2.0, 3.0, big, 0.0, 0.0}) bin.append(reinterpret_cast<const char*>(&v), 8);
        const core::PointCloud b = io::readCloudData(bin, "big.pcd");
        REQUIRE(b.points.size() == 1);
        CHECK(b.points[0].position == glm::vec3(1, 2, 3));
    }
}

TEST_CASE("cloud_reader: a file of 0 points is valid and reads as empty") {
    const std::string pcd = test_support::pcdHeader("0", "0");
    io::CloudReader reader(pcd, "empty.pcd");
    std::vector<core::CloudPoint> out;
    CHECK_FALSE(reader.nextChunk(out));
    CHECK(out.empty());
    CHECK(reader.declaredPoints() == 0);
}

TEST_CASE("cloud_reader: zero padding after the data is accepted, up to 64 KiB") {
    const std::string records = test_support::xyzLabelRecords({0, 1, 2});
    const std::string head = test_support::pcdHeader("3", "3");
    CHECK(io::readCloudData(head + records + std::string(4000, '\0'), "pad.pcd").points.size() == 3);
    CHECK_THROWS_WITH_AS(io::readCloudData(head + records + std::string(65537, '\0'), "pad.pcd"),
                         "pcd: pad.pcd: 65537 bytes of data follow the 3 points the header declares; "
                         "the header must count every point",
                         core::Error);
    CHECK_THROWS_WITH_AS(io::readCloudData(head + records + std::string(3, '\0') + "x", "pad.pcd"),
                         doctest::Contains("4 bytes of data follow the 3 points"), core::Error);
}

TEST_CASE("cloud_reader: PCL's files (zero padded, LZF by liblzf) read in chunks") {
    for (const char* name : {"pcl_binary.pcd", "pcl_binary_compressed.pcd", "pcl_ascii.pcd"}) {
        CAPTURE(name);
        const core::PointCloud whole = io::readCloud(kData / name);
        REQUIRE(whole.points.size() == 300);
        io::CloudReader reader(kData / name);
        std::vector<core::CloudPoint> out;
        int calls = 0;
        while (reader.nextChunk(out, 64)) ++calls;
        CHECK(calls == 5);
        CHECK(samePoints(out, whole.points));
        CHECK(out[299].position == glm::vec3(74.75f, -1.5f * float(299 % 17), 14.5f));
    }
}

TEST_CASE("cloud_reader: LZF blocks are decoded by liblzf, bounded by the header's size") {
    // One point of x y z: 12 bytes uncompressed, one LZF literal run of 12 bytes.
    auto file = [](const std::string& block) {
        std::string s = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA binary_compressed\n";
        const std::uint32_t sizes[2] = {std::uint32_t(block.size()), 12};
        s.append(reinterpret_cast<const char*>(sizes), 8);
        return s + block;
    };
    std::string xyz(12, '\0');
    const float v[3] = {1.5f, -2.0f, 8.0f};
    std::memcpy(xyz.data(), v, 12);
    const core::PointCloud ok = io::readCloudData(file(char(11) + xyz), "ok.pcd");
    REQUIRE(ok.points.size() == 1);
    CHECK(ok.points[0].position == glm::vec3(1.5f, -2.0f, 8.0f));
    const char* corrupt = "pcd: c.pcd: binary_compressed: the LZF data are corrupt";
    // A literal run longer than the block (liblzf's input check).
    CHECK_THROWS_WITH_AS(io::readCloudData(file(char(31) + xyz), "c.pcd"), corrupt, core::Error);
    // Fewer bytes than the header implies.
    CHECK_THROWS_WITH_AS(io::readCloudData(file(char(4) + xyz.substr(0, 5)), "c.pcd"), corrupt, core::Error);
    // More bytes than the header implies: liblzf stops at the declared size (E2BIG).
    CHECK_THROWS_WITH_AS(io::readCloudData(file(char(11) + xyz + char(0) + "x"), "c.pcd"), corrupt, core::Error);
    // A back reference before the start of the output.
    CHECK_THROWS_WITH_AS(io::readCloudData(file(std::string("\x20\x05", 2) + xyz), "c.pcd"), corrupt, core::Error);
}

TEST_CASE("cloud_reader: special files and long values are refused with one line") {
    TempDir dir("special");
    CHECK(errorOf(dir.path) == "pcd: " + dir.path.string() + ": is a directory, not a regular file");
    const fs::path fifo = dir.path / "f.pcd";
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    CHECK(errorOf(fifo) == "pcd: " + fifo.string() + ": is not a regular file");  // no hang
    const fs::path missing = dir.path / "none.ply";
    CHECK(errorOf(missing) == "ply: " + missing.string() + ": file does not exist");
    const std::string pcd =
        "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n1 2 " + std::string(5000, '7') + "\n";
    CHECK_THROWS_WITH_AS(io::readCloudData(pcd, "long.pcd"),
                         "pcd: long.pcd: a value longer than 4096 bytes; not a text cloud?", core::Error);
    // The same across the reader's 1 MiB text blocks, from a file.
    const fs::path big = dir.path / "big.pcd";
    spit(big, "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n" + std::string((1 << 20) - 60, ' ') +
                  std::string(10000, '1'));
    CHECK(errorOf(big) == "pcd: " + big.string() + ": a value longer than 4096 bytes; not a text cloud?");
}

TEST_CASE("cloud_reader: a header longer than 1 MiB is refused") {
    std::string pcd = "# " + std::string((1 << 20) + 10, 'c') + "\nFIELDS x y z\n";
    CHECK_THROWS_WITH_AS(io::readCloudData(pcd, "h.pcd"),
                         "pcd: h.pcd: the header is longer than 1 MiB; not a PCD file?", core::Error);
}

TEST_CASE("cloud_reader: a file that does not start like a PCD or PLY file is named so, nothing of it quoted") {
    // A design or an option may name any file; run as root, quoting its first line would
    // show what it holds (a password hash of /etc/shadow).
    const std::string shadow = "root:$6$saltsalt$SECRETHASH:20786:0:99999:7:::\nbin:*:20786:0:99999:7:::\n";
    const auto refused = [](const std::string& bytes, const std::string& name) {
        try {
            io::readCloudData(bytes, name);
        } catch (const core::Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    const std::string not_pcd =
        "line 1: not a PCD file (a PCD header starts with '#' comments and keywords such as VERSION or FIELDS)";
    CHECK(refused(shadow, "shadow.pcd") == "pcd: shadow.pcd: " + not_pcd);
    CHECK(refused("\n  \n" + shadow, "shadow.pcd").find("line 3: not a PCD file") != std::string::npos);
    // Comments first, as a configuration file has them: still not a PCD at its first word.
    const std::string config = refused("# settings\ntoken SECRETTOKEN\n", "config.pcd");
    CHECK(config.find("line 2: not a PCD file") != std::string::npos);
    CHECK(config.find("SECRET") == std::string::npos);
    // Any file not starting with "ply" is read as a PCD whatever its name; one that starts
    // so but has more on its first line is not a PLY file either.
    CHECK(refused(shadow, "shadow.ply") == "pcd: shadow.ply: " + not_pcd);
    CHECK(refused("plywood:SECRET\n", "wood.ply") ==
          "ply: wood.ply: line 1: not a PLY file (a PLY file starts with the line 'ply')");
    // Once the header has begun like a PCD's, an unknown keyword is named, printable and short.
    CHECK(refused("VERSION 0.7\nFIELDSS x y z\n", "typo.pcd") ==
          "pcd: typo.pcd: line 2: unknown header keyword 'FIELDSS'; allowed: VERSION, FIELDS, SIZE, TYPE, COUNT, "
          "WIDTH, HEIGHT, VIEWPOINT, POINTS, DATA");
    CHECK(refused("VERSION 0.7\n" + std::string(60, 'K') + "\n", "long.pcd")
              .find("unknown header keyword '" + std::string(20, 'K') + "...'") != std::string::npos);
    CHECK(refused("ply\nformat ascii 1.0\n" + std::string(60, 'k') + "\n", "long.ply")
              .find("unknown header keyword '" + std::string(20, 'k') + "...'") != std::string::npos);
}

TEST_CASE("cloud_reader: PointFields::Positions gives the same points, views and ranges, other layers skipped") {
    TempDir dir("positions");
    const core::PointCloud cloud = knownCloud(120000);  // several LAZ chunks of 50,000
    for (CloudFormat f : {CloudFormat::Laz, CloudFormat::Copc, CloudFormat::Las}) {
        CAPTURE(int(f));
        const fs::path p = dir.path / (f == CloudFormat::Laz    ? "c.laz"
                                       : f == CloudFormat::Copc ? "c.copc.laz"
                                                                : "c.las");
        io::writeCloud(p, cloud, f);
        const core::PointCloud all = io::readCloud(p);
        io::CloudReader reader(p, io::PointFields::Positions);
        CHECK(reader.origin() == all.origin);
        std::vector<core::CloudPoint> some;
        while (reader.nextChunk(some, 7777)) {}
        REQUIRE(some.size() == all.points.size());
        bool same = true, colours_skipped = false;
        for (std::size_t i = 0; i < some.size(); ++i) {
            same = same && std::memcmp(&some[i].position, &all.points[i].position, sizeof some[i].position) == 0 &&
                   some[i].view == all.points[i].view && some[i].range_m == all.points[i].range_m;
            colours_skipped = colours_skipped || some[i].rgb != all.points[i].rgb;
        }
        CHECK(same);
        // A compressed file of LAS 1.4 point format 7 skips the colour layer; LAS decodes all.
        CHECK(colours_skipped == (f != CloudFormat::Las));
    }
}
