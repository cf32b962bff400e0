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
#include <string>

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
    CHECK(error("t,head_x,head_y,head_z,head_qw,head_qx,head_qy,head_qz\n").find("header column 1 is 't'") !=
          std::string::npos);
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
