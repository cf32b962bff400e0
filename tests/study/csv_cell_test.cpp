// Tests of study/src/csv_cell.cpp: a text cell of the study's CSV files shows as text in a
// spreadsheet (no formula, no control or bidirectional character), quoted only when it
// must be, and unchanged when it is plain or already made safe.
#include <study/csv_cell.hpp>

#include <doctest/doctest.h>

#include <string>

TEST_CASE("csv cell: plain text is kept, commas and quotes are quoted (RFC 4180)") {
    CHECK(study::csvCell("a.pcd") == "a.pcd");
    CHECK(study::csvCell("P01") == "P01");
    CHECK(study::csvCell("a,b") == "\"a,b\"");
    CHECK(study::csvCell("say \"x\"") == "\"say \"\"x\"\"\"");
    CHECK(study::csvCell("") == "");
    CHECK(study::csvCell("Pr\u00fcfung \u6e2c\u8a66") == "Pr\u00fcfung \u6e2c\u8a66");  // UTF-8 text is text
}

TEST_CASE("csv cell: a cell that starts like a formula gets a leading quote mark") {
    CHECK(study::csvCell("=HYPERLINK(\"http://x\",\"y\")") == "\"'=HYPERLINK(\"\"http://x\"\",\"\"y\"\")\"");
    CHECK(study::csvSafeText("=1+2") == "'=1+2");
    CHECK(study::csvSafeText("+1") == "'+1");
    CHECK(study::csvSafeText("-2+3") == "'-2+3");
    CHECK(study::csvSafeText("@SUM(A1)") == "'@SUM(A1)");
    CHECK(study::csvSafeText("a=b") == "a=b");  // only the first character counts
    // A leading tab or carriage return is written as an escape, so it cannot lead.
    CHECK(study::csvSafeText("\t=1") == "\\x09=1");
    CHECK(study::csvSafeText("\r=1") == "\\x0d=1");
}

TEST_CASE("csv cell: control and bidirectional characters and broken UTF-8 are escaped") {
    CHECK(study::csvSafeText("a\x1b[2Jb") == "a\\x1b[2Jb");
    CHECK(study::csvSafeText("line\nbreak") == "line\\x0abreak");
    CHECK(study::csvSafeText(std::string("nul\0x", 5)) == "nul\\x00x");
    CHECK(study::csvSafeText("del\x7f") == "del\\x7f");
    CHECK(study::csvSafeText("c1\u0085") == "c1\\u0085");
    CHECK(study::csvSafeText("gpj.\u202eexe") == "gpj.\\u202eexe");
    for (const char* bidi :
         {"\u200e", "\u200f", "\u202a", "\u202b", "\u202c", "\u202d", "\u2066", "\u2067", "\u2068", "\u2069"})
        CHECK(study::csvSafeText(bidi).starts_with("\\u20"));
    CHECK(study::csvSafeText("bad\xff\xc3") == "bad\\xff\\xc3");
    CHECK(study::csvSafeText("\xc0\xaf") == "\\xc0\\xaf");           // overlong '/'
    CHECK(study::csvSafeText("\xed\xa0\x80") == "\\xed\\xa0\\x80");  // a UTF-16 surrogate
    // A line break inside a cell is escaped, so a row stays one line.
    CHECK(study::csvCell("two\nlines, one cell") == "\"two\\x0alines, one cell\"");
}

TEST_CASE("csv cell: made safe once, made safe again changes nothing") {
    for (const std::string s : {"=1+2", "-x", "a\x1b", "\u202e=1", "'=x", "plain", "@", "\xff"}) {
        CAPTURE(s);
        const std::string once = study::csvSafeText(s);
        CHECK(study::csvSafeText(once) == once);
    }
}
