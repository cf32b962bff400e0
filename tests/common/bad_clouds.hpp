// tests/common/bad_clouds.hpp: one table of malformed cloud files with the exact message
// each must be refused with. tests/io/cloud_reader_test.cpp runs it through
// io::readCloud and tests/viewer/points/cloud_feed_test.cpp through the viewer's loader, so
// both are shown to refuse exactly the same files with exactly the same line.
#pragma once
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace test_support {

struct BadCloud {
    const char* name;         // file name, also the test's label
    std::string bytes;        // the file
    std::string message;      // what follows "pcd: <path>: " / "ply: <path>: "
    bool in_records = false;  // found while decoding the points, not when opening
};

/// Binary PCD records of x y z (float) label (uint8).
inline std::string xyzLabelRecords(std::initializer_list<std::uint8_t> labels) {
    std::string out;
    float v = 0.0f;
    for (std::uint8_t l : labels) {
        for (int k = 0; k < 3; ++k) out.append(reinterpret_cast<const char*>(&v), 4);
        out += char(l);
        v += 1.0f;
    }
    return out;
}

/// A binary PCD header for x y z label; `extra` goes before VERSION, the counts are text.
inline std::string pcdHeader(const std::string& width, const std::string& points, const std::string& extra = "",
                             const std::string& sizes = "4 4 4 1", const std::string& types = "F F F U",
                             const std::string& height = "1", const std::string& data = "binary") {
    return "# .PCD v0.7\n" + extra + "VERSION 0.7\nFIELDS x y z label\nSIZE " + sizes + "\nTYPE " + types +
           "\nCOUNT 1 1 1 1\nWIDTH " + width + "\nHEIGHT " + height + "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + points +
           "\nDATA " + data + "\n";
}

inline std::vector<BadCloud> badClouds() {
    const std::string three = xyzLabelRecords({0, 1, 2});
    const std::string ply_head =
        "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
        "property float y\nproperty float z\nproperty uchar label\nend_header\n";
    // Our own files (the ladarvr origin comment) hold roles 0..2 only; other files' labels
    // from 3 on are ASPRS classes (docs/formats.md).
    const std::string ply_ours_head =
        "ply\nformat binary_little_endian 1.0\ncomment ladarvr origin 0 0 0\nelement vertex 2\n"
        "property float x\nproperty float y\nproperty float z\nproperty uchar label\nend_header\n";
    return {
        {"label7.pcd", pcdHeader("3", "3", "# ladarvr origin 0 0 0\n") + xyzLabelRecords({0, 7, 2}),
         "point 1: label 7 is not 0 (ground), 1 (environment) or 2 (target)", true},
        {"origin_two_values.pcd", pcdHeader("3", "3", "# ladarvr origin 1 2\n") + three,
         "line 2: the ladarvr origin needs 3 numbers X Y Z"},
        {"origin_nan.pcd", pcdHeader("3", "3", "# ladarvr origin 1 nan 3\n") + three,
         "line 2: the ladarvr origin value 'nan' is not a finite number"},
        {"type_f_size_1.pcd", pcdHeader("3", "3", "", "4 4 4 1", "F F F F") + three,
         "field 'label': TYPE F needs SIZE 4 or 8, not 1"},
        {"points_not_width_height.pcd", pcdHeader("3", "2") + three, "POINTS 2 is not WIDTH x HEIGHT = 3"},
        {"fields_size_mismatch.pcd", pcdHeader("3", "3", "", "4 4 4") + three, "SIZE has 3 entries but FIELDS has 4"},
        {"width_height_overflow.pcd", pcdHeader("4294967296", "0", "", "4 4 4 1", "F F F U", "4294967296") + three,
         "WIDTH x HEIGHT overflows"},
        {"width_minus_one.pcd", pcdHeader("-1", "3") + three, "line 7: WIDTH needs one non-negative integer"},
        {"truncated.pcd", pcdHeader("3", "3") + three.substr(0, 30),
         "truncated: the header says 3 points of 13 bytes but only 30 bytes of data follow the header"},
        {"points_fewer_than_data.pcd", pcdHeader("2", "2") + three,
         "13 bytes of data follow the 2 points the header declares; the header must count every point"},
        {"huge_count_small_file.pcd", pcdHeader("99999999999", "99999999999") + three,
         "truncated: the header says 99999999999 points of 13 bytes but only 39 bytes of data follow "
         "the header"},
        {"ascii_extra_values.pcd", pcdHeader("1", "1", "", "4 4 4 1", "F F F U", "1", "ascii") + "1 2 3 0\n4 5 6 1\n",
         "line 13: data follow the 1 points the header declares; the header must count every point", true},
        {"ascii_bad_value.pcd", pcdHeader("2", "2", "", "4 4 4 1", "F F F U", "1", "ascii") + "1 2 3 0\n4 x 6 1\n",
         "line 13: value 'x' of point 1 is not a number", true},
        {"ascii_cut.pcd", pcdHeader("2", "2", "", "4 4 4 1", "F F F U", "1", "ascii") + "1 2 3 0\n4 5\n",
         "truncated: the header says 2 points but the data end at line 14 inside point 1", true},
        {"ply_label7.ply", ply_ours_head + xyzLabelRecords({0, 7}),
         "point 1: label 7 is not 0 (ground), 1 (environment) or 2 (target)", true},
        {"ply_trailing.ply", ply_head + three,
         "13 bytes of data follow the 2 vertices the header declares; the header must count every point"},
    };
}

}  // namespace test_support
