// tests/test_main.cpp: doctest's main for every test executable, which also fails a run
// that ran no test case. ctest runs one test case per entry by its name
// (doctest_discover_tests); a name that does not reach doctest whole (CMake cuts a
// name at ';') would otherwise match nothing and pass without running.
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <cstdio>

namespace {

struct RunCount {
    bool ran = false;  // a test run ended (not a listing or --help)
    unsigned matched = 0;
};
RunCount g_run;

// A listener beside the reporter: it only records how many test cases the filters kept.
struct MatchedListener : doctest::IReporter {
    explicit MatchedListener(const doctest::ContextOptions&) {}
    void report_query(const doctest::QueryData&) override {}
    void test_run_start() override {}
    void test_run_end(const doctest::TestRunStats& stats) override {
        g_run.ran = true;
        g_run.matched = stats.numTestCasesPassingFilters;
    }
    void test_case_start(const doctest::TestCaseData&) override {}
    void test_case_reenter(const doctest::TestCaseData&) override {}
    void test_case_end(const doctest::CurrentTestCaseStats&) override {}
    void test_case_exception(const doctest::TestCaseException&) override {}
    void subcase_start(const doctest::SubcaseSignature&) override {}
    void subcase_end() override {}
    void log_assert(const doctest::AssertData&) override {}
    void log_message(const doctest::MessageData&) override {}
    void test_case_skipped(const doctest::TestCaseData&) override {}
};

}  // namespace

REGISTER_LISTENER("matched", 1, MatchedListener);

int main(int argc, char** argv) {
    doctest::Context context(argc, argv);
    const int status = context.run();
    if (context.shouldExit() || !g_run.ran) return status;
    if (g_run.matched == 0) {
        std::fprintf(stderr,
                     "test_main: no test case matches the filters given; allowed a name as doctest lists it "
                     "(a name with ';' is cut by CMake: use ',')\n");
        return 1;
    }
    return status;
}
