// tests/io/trace_file_test.cpp: a study's head trace (io/trace_file.hpp): rows
// written as the study writes them and read back, and the reading rules at their edges
// (empty lines, equal and decreasing times, extra columns, a non-unit quaternion, the
// study columns), each bad file one line naming the line and the column.
#include <core/error.hpp>
#include <io/trace_file.hpp>

#include <test_files.hpp>

#include <doctest/doctest.h>

#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using doctest::Approx;

namespace {

const std::string kHeader = std::string(io::kTraceHeader) + "\n";
const std::string kHeadOnly = "t_s,head_x,head_y,head_z,head_qw,head_qx,head_qy,head_qz\n";

// The message of parsing `text`, which must start "trace: bad.csv: line " and be one line.
std::string error(const std::string& text) {
    const std::string m = test_support::errorOf([&] { io::parseTrace(text, "bad.csv"); });
    CHECK(m.find('\n') == std::string::npos);
    CHECK(m.rfind("trace: bad.csv: line ", 0) == 0);
    return m;
}

}  // namespace

TEST_CASE("trace: rows as the study writes them, and read back") {
    io::TraceRow a;
    a.t_s = 0.5;
    a.head_world = {1.0, 2.0, 3.0};
    CHECK(io::formatTraceRow(a) ==
          "0.500000,1.000000,2.000000,3.000000,1.000000000,0.000000000,0.000000000,0.000000000,automatic,1,,,\n");
    io::TraceRow b;
    b.t_s = 1.25;
    b.head_world = {-4.5, 0.0, 100.0};
    b.head_orientation = glm::angleAxis(0.3, glm::normalize(glm::dvec3(1, 2, 3)));
    b.mode = io::TraceMode::Free;
    b.scale = 2.5;
    b.hit_world = glm::dvec3(10.0, 20.0, 0.5);
    const std::string row_b = io::formatTraceRow(b);
    CHECK(row_b.ends_with(",free,2.5,10.000000,20.000000,0.500000\n"));

    test_support::TempDir dir("trace_file");
    const io::Trace trace = io::readTrace(dir.write("trace_1.csv", kHeader + io::formatTraceRow(a) + row_b));
    CHECK(trace.study_columns);
    REQUIRE(trace.rows.size() == 2);
    CHECK(trace.rows[0].t_s == 0.5);
    CHECK(trace.rows[0].head_world == glm::dvec3(1.0, 2.0, 3.0));
    CHECK(trace.rows[0].mode == io::TraceMode::Automatic);
    CHECK_FALSE(trace.rows[0].hit_world);
    CHECK(trace.rows[1].mode == io::TraceMode::Free);
    CHECK(trace.rows[1].scale == 2.5);
    CHECK(*trace.rows[1].hit_world == glm::dvec3(10.0, 20.0, 0.5));
    CHECK(std::abs(glm::dot(trace.rows[1].head_orientation, b.head_orientation)) == Approx(1.0));
    CHECK(test_support::errorOf([&] { io::readTrace(dir.path / "missing.csv"); }).find("trace: ") == 0);
}

TEST_CASE("trace: CRLF, a last line without its break, and the eight head columns alone") {
    const io::Trace crlf = io::parseTrace(kHeadOnly.substr(0, kHeadOnly.size() - 1) +
                                              "\r\n0,1,2,3,1,0,0,0\r\n"
                                              "0.1,1,2,3,1,0,0,0",
                                          "crlf.csv");
    CHECK_FALSE(crlf.study_columns);
    REQUIRE(crlf.rows.size() == 2);
    CHECK(crlf.rows[1].t_s == 0.1);
    CHECK(crlf.rows[1].mode == io::TraceMode::Automatic);  // the defaults without the study columns
    CHECK(crlf.rows[1].scale == 1.0);
}

TEST_CASE("trace: empty lines are refused, wherever they are") {
    const std::string good = "0,1,2,3,1,0,0,0,automatic,1,,,\n";
    CHECK(error(kHeader + good + "\n" + good).find("line 3: empty line") != std::string::npos);
    CHECK(error(kHeader + "\n" + good).find("line 2: empty line") != std::string::npos);
    CHECK(error(kHeader + good + "\n").find("line 3: empty line") != std::string::npos);
    CHECK(error(kHeader + good + "\r\n\r\n").find("line 3: empty line") != std::string::npos);
    CHECK(error("").find("line 1: empty file") != std::string::npos);
    CHECK(error(kHeader).find("no samples") != std::string::npos);
}

TEST_CASE("trace: equal times are kept, decreasing or negative ones refused") {
    const std::string same = kHeader + "0.5,1,2,3,1,0,0,0,automatic,1,,,\n0.5,4,5,6,1,0,0,0,free,1,,,\n";
    const io::Trace trace = io::parseTrace(same, "same.csv");
    REQUIRE(trace.rows.size() == 2);
    CHECK(trace.rows[1].head_world.x == 4.0);
    CHECK(error(kHeader + "1,1,2,3,1,0,0,0,automatic,1,,,\n0.5,1,2,3,1,0,0,0,automatic,1,,,\n")
              .find("line 3, column t_s: decreases") != std::string::npos);
    CHECK(error(kHeader + "-1,1,2,3,1,0,0,0,automatic,1,,,\n").find("line 2, column t_s: negative") !=
          std::string::npos);
}

TEST_CASE("trace: extra columns after the study's are ignored, and every row has the header's fields") {
    const io::Trace extra =
        io::parseTrace(std::string(io::kTraceHeader) + ",note\n0,1,2,3,1,0,0,0,free,2,,,,anything\n", "x.csv");
    CHECK(extra.study_columns);
    REQUIRE(extra.rows.size() == 1);
    CHECK(extra.rows[0].mode == io::TraceMode::Free);
    CHECK(extra.rows[0].scale == 2.0);
    // Columns after head_qz that are not the study's are ignored whatever they hold.
    const io::Trace other = io::parseTrace(kHeadOnly.substr(0, kHeadOnly.size() - 1) +
                                               ",mode\n"
                                               "0,1,2,3,1,0,0,0,walk\n",
                                           "o.csv");
    CHECK_FALSE(other.study_columns);
    CHECK(other.rows.size() == 1);
    CHECK(error(kHeader + "0,1,2,3,1,0,0,0\n").find("line 2: 8 fields; allowed 13 (as the header)") !=
          std::string::npos);
    CHECK(error(kHeader + "0,1,2,3,1,0,0,0,automatic,1,,,,\n").find("line 2: 14 fields; allowed 13") !=
          std::string::npos);
}

TEST_CASE("trace: a quaternion within 1e-3 of unit length is normalised, another is refused") {
    const io::Trace near = io::parseTrace(kHeader + "0,1,2,3,1.0005,0,0,0,automatic,1,,,\n", "near.csv");
    CHECK(near.rows[0].head_orientation.w == Approx(1.0).epsilon(1e-12));
    CHECK(glm::length(near.rows[0].head_orientation) == Approx(1.0).epsilon(1e-12));
    CHECK(error(kHeader + "0,1,2,3,2,0,0,0,automatic,1,,,\n").find("line 2, column head_qw: quaternion norm 2") !=
          std::string::npos);
    CHECK(error(kHeader + "0,1,2,3,0,0,0,0,automatic,1,,,\n").find("quaternion norm 0") != std::string::npos);
}

TEST_CASE("trace: a wrong header, number, mode, scale or hit names its line and column") {
    const std::string good = "0,1,2,3,1,0,0,0,automatic,1,,,\n";
    CHECK(error("t_s,head_x,head_y\n0,1,2\n").find("line 1: header column 4 is ''") != std::string::npos);
    CHECK(error("t,head_x,head_y,head_z,head_qw,head_qx,head_qy,head_qz\n")
              .find("line 1: not a trace: the first line does not start with the column t_s; allowed a header") !=
          std::string::npos);
    // A file that is no trace is not quoted: a password file's first line stays out of the message.
    const std::string shadow = error("root:$y$j9T$abcdefgh:20786:0:99999:7:::\n");
    CHECK(shadow.find("not a trace") != std::string::npos);
    CHECK(shadow.find("root") == std::string::npos);
    CHECK(shadow.find("abcdefgh") == std::string::npos);
    const std::string long_column = error("t_s,head_x,head_y,head_z,head_qw,head_qx,secret-secret-secret-secret\n");
    CHECK(long_column.find("header column 7 is 'secret-") != std::string::npos);
    CHECK(long_column.find("secret-secret-secret-secret") == std::string::npos);
    CHECK(error(kHeader + good + "0.1,1,2,x3,1,0,0,0,automatic,1,,,\n")
              .find("line 3, column head_z: 'x3' is not a finite number") != std::string::npos);
    CHECK(error(kHeader + "0,1,2,nan,1,0,0,0,automatic,1,,,\n").find("column head_z") != std::string::npos);
    CHECK(error(kHeader + "0,1,2,3 ,1,0,0,0,automatic,1,,,\n").find("column head_z") != std::string::npos);
    CHECK(error(kHeader + "0,+1,2,3,1,0,0,0,automatic,1,,,\n").find("column head_x") != std::string::npos);
    CHECK(error(kHeader + "0,1e300,2,3,1,0,0,0,automatic,1,,,\n").find("column head_x: out of range") !=
          std::string::npos);
    CHECK(
        error(kHeader + "0,1,2,3,1,0,0,0,walk,1,,,\n").find("line 2, column mode: 'walk'; allowed automatic or free") !=
        std::string::npos);
    CHECK(error(kHeader + "0,1,2,3,1,0,0,0,free,0,,,\n").find("line 2, column scale: '0'; allowed a number > 0") !=
          std::string::npos);
    CHECK(error(kHeader + "0,1,2,3,1,0,0,0,free,x,,,\n").find("column scale: 'x' is not a finite number") !=
          std::string::npos);
    CHECK(error(kHeader + "0,1,2,3,1,0,0,0,free,1,4,,6\n").find("line 2, column hit_y: '' is not a finite number") !=
          std::string::npos);
}

namespace {

// The rows forEachTraceRow hands on for `text` written to a file, and the error, if any.
struct Streamed {
    std::vector<io::TraceRow> rows;
    std::string error;
    bool study_columns = false;
};
Streamed stream(const std::string& text) {
    test_support::TempDir dir("trace_stream");
    const std::filesystem::path file = dir.path / "trace.csv";
    std::ofstream(file, std::ios::binary) << text;
    Streamed s;
    s.error = test_support::errorOf(
        [&] { s.study_columns = io::forEachTraceRow(file, [&](const io::TraceRow& r) { s.rows.push_back(r); }); });
    return s;
}

// A head-only row at time `t_s` (milliseconds written out), `pad` zeros padding head_x.
std::string row(std::size_t t_ms, std::size_t pad = 0) {
    return std::to_string(t_ms / 1000) + "." + std::to_string(1000 + t_ms % 1000).substr(1) + "," +
           std::string(pad, '0') + "1,2,3,1,0,0,0\n";
}

}  // namespace

TEST_CASE("trace: read a block at a time, a file gives what its text gives, lines across blocks included") {
    // Rows of varying length over three blocks, so lines straddle each block boundary.
    std::string text = kHeadOnly;
    for (std::size_t i = 0; text.size() < 3 * io::kTraceBlockBytes; ++i) text += row(i, i % 7);
    text += "9999.000,1,2,3,1,0,0,0";  // the last line without its break
    const io::Trace whole = io::parseTrace(text, "trace.csv");
    const Streamed s = stream(text);
    CHECK(s.error == "(no error)");
    CHECK_FALSE(s.study_columns);
    REQUIRE(s.rows.size() == whole.rows.size());
    for (std::size_t i = 0; i < whole.rows.size(); ++i) {
        CHECK(s.rows[i].t_s == whole.rows[i].t_s);
        CHECK(s.rows[i].head_world == whole.rows[i].head_world);
    }
    CHECK(stream(kHeader + "0.0,1,2,3,1,0,0,0,free,2,4,5,6\r\n").study_columns);
}

TEST_CASE("trace: streamed rows are handed on before the file ends, the same refusals as the whole-text reader") {
    // A bad line after more than a block of good rows: the good ones were handed on first.
    std::string text = kHeadOnly;
    std::size_t good = 0;
    for (; text.size() < 2 * io::kTraceBlockBytes; ++good) text += row(good);
    const std::string bad = text + "1.0,1,2,3,1,0,0,0\n";  // time goes back
    const Streamed s = stream(bad);
    CHECK(s.rows.size() == good);
    // The same words as parseTrace's, after the file's name.
    const std::string whole = error(bad);
    REQUIRE(s.error.find(": line ") != std::string::npos);
    CHECK(s.error.substr(s.error.find(": line ")) == whole.substr(whole.find(": line ")));
    CHECK(s.error.find("line " + std::to_string(good + 2) + ", column t_s: decreases") != std::string::npos);
    CHECK(stream("").error.find("empty file") != std::string::npos);
    CHECK(stream(kHeadOnly).error.find("no samples after the header") != std::string::npos);
    CHECK(stream(kHeadOnly + "\n").error.find("line 2: empty line") != std::string::npos);
    // A line longer than kMaxTraceLineBytes is refused without holding more of it.
    const Streamed long_line = stream(kHeadOnly + std::string(io::kMaxTraceLineBytes + 10, '1'));
    CHECK(long_line.error.find("line 2: longer than 1048576 bytes") != std::string::npos);
}

TEST_CASE("trace: times past the bound, and hits and scales past theirs, are refused on their line") {
    // A replay plays the trace in real time: a time of 1e300 s would hold it for good.
    CHECK(error(kHeader + "0,1,2,3,1,0,0,0,free,1,,,\n1e300,1,2,3,1,0,0,0,free,1,,,\n")
              .find("line 3, column t_s: 1e+300 s; allowed seconds from 0 to 1000000") != std::string::npos);
    CHECK(io::parseTrace(kHeader + "1000000,1,2,3,1,0,0,0,free,1,,,\n", "end.csv").rows.size() == 1);
    CHECK(error(kHeader + "1000000.5,1,2,3,1,0,0,0,free,1,,,\n").find("column t_s") != std::string::npos);
    CHECK(error(kHeader + "0,1,2,3,1,0,0,0,free,1e300,,,\n").find("line 2, column scale: '1e300'; allowed at most") !=
          std::string::npos);
    CHECK(error(kHeader + "0,1,2,3,1,0,0,0,free,1,1e300,0,0\n").find("line 2, column hit_x: out of range") !=
          std::string::npos);
}

TEST_CASE("trace: readTrace holds the rows alone, in one allocation, and at most kMaxTraceRows of them") {
    test_support::TempDir dir("trace_rows");
    std::string text = kHeadOnly;
    for (std::size_t i = 0; i < 1000; ++i) text += row(i);
    const io::Trace trace = io::readTrace(dir.write("t.csv", text));
    REQUIRE(trace.rows.size() == 1000);
    CHECK(trace.rows.capacity() <= 1001);  // counted first, not grown by doubling
    // One row past the bound: refused on that line, naming the bound.
    std::string many = kHeadOnly;
    many.reserve(kHeadOnly.size() + (io::kMaxTraceRows + 1) * 16);
    for (std::size_t i = 0; i <= io::kMaxTraceRows; ++i) many += "0,1,2,3,1,0,0,0\n";
    const std::filesystem::path big = dir.write("big.csv", many);
    CHECK(test_support::errorOf([&] { io::readTrace(big); }) ==
          "trace: " + big.string() + ": line 1048578: more than 1048576 samples; allowed at most 1048576");
    // forEachTraceRow holds none, and reads them all.
    std::size_t seen = 0;
    io::forEachTraceRow(big, [&](const io::TraceRow&) { ++seen; });
    CHECK(seen == io::kMaxTraceRows + 1);
}
