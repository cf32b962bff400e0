// tests/core/height_span_test.cpp: the span of a cloud's heights without its stray returns,
// on heights built in code (a body, and tails parted from it by gaps of known widths).
#include <core/error.hpp>
#include <core/height_span.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <vector>

namespace {

// `n` heights spread evenly over [a, b].
void addEven(core::HeightSpan& s, int n, double a, double b) {
    for (int k = 0; k < n; ++k) s.add(float(a + (b - a) * (n > 1 ? double(k) / (n - 1) : 0.0)));
}

}  // namespace

TEST_CASE("height span: without strays, the lowest and highest heights, exactly") {
    core::HeightSpan s(20.0);
    addEven(s, 10000, 249.5, 400.25);
    const core::HeightSpan::Span sp = s.span();
    CHECK(sp.lo == 249.5);
    CHECK(sp.hi == 400.25);
    CHECK(sp.strays_low == 0);
    CHECK(sp.strays_high == 0);
    CHECK(s.count() == 10000);
    const core::HeightSpan empty(20.0);
    CHECK(empty.count() == 0);
    CHECK(empty.span().lo == 0.0);
    CHECK(empty.span().hi == 0.0);
}

TEST_CASE("height span: a few returns far above the rest are left out, the body's top kept exactly") {
    // A survey's heights 250-390 m, and birds or clouds at 610 and 800-900 m (as FSite5).
    core::HeightSpan s(20.0);
    addEven(s, 20000, 250.0, 390.0);
    s.add(610.0f);
    addEven(s, 9, 800.0, 900.0);
    const core::HeightSpan::Span sp = s.span();
    CHECK(sp.hi == 390.0);
    CHECK(sp.strays_high == 10);  // the gap nearest the body cuts, the 610 m return with the rest
    CHECK(sp.lo == 250.0);
    CHECK(sp.strays_low == 0);
}

TEST_CASE("height span: a few returns far below are left out too") {
    core::HeightSpan s(20.0);
    addEven(s, 5000, 240.0, 300.0);
    s.add(120.0f);
    s.add(121.5f);
    const core::HeightSpan::Span sp = s.span();
    CHECK(sp.lo == 240.0);
    CHECK(sp.strays_low == 2);
    CHECK(sp.hi == 300.0);
}

TEST_CASE("height span: a tail of more than a thousandth of the heights stays") {
    core::HeightSpan s(20.0);
    addEven(s, 10000, 0.0, 50.0);
    addEven(s, 11, 480.0, 500.0);  // 11 > 10000 / 1000
    CHECK(s.span().hi == 500.0);
    CHECK(s.span().strays_high == 0);
    // One fewer, and it goes.
    core::HeightSpan t(20.0);
    addEven(t, 10000, 0.0, 50.0);
    addEven(t, 10, 480.0, 500.0);
    CHECK(t.span().hi == 50.0);
    CHECK(t.span().strays_high == 10);
}

TEST_CASE("height span: a gap narrower than min_gap, or than half the body's middle span, parts nothing") {
    // Cars 1.5 m above a flat car park, and a return 19 m above it: under the 20 m least gap.
    core::HeightSpan s(20.0);
    addEven(s, 10000, 0.0, 1.0);
    addEven(s, 5, 1.5, 1.6);
    s.add(20.0f);
    CHECK(s.span().hi == 20.0);
    // The same in feet (the least gap 65.6 ft): a return 60 ft above stays.
    core::HeightSpan feet(65.6);
    addEven(feet, 10000, 0.0, 3.0);
    feet.add(63.0f);
    CHECK(feet.span().hi == 63.0);
    // A body 150 m tall (its middle 98 % 147 m): a return 60 m above it stays, 80 m above goes.
    core::HeightSpan t(20.0);
    addEven(t, 10000, 0.0, 150.0);
    t.add(210.0f);
    CHECK(t.span().hi == 210.0);
    core::HeightSpan u(20.0);
    addEven(u, 10000, 0.0, 150.0);
    u.add(230.0f);
    CHECK(u.span().hi == 150.0);
    CHECK(u.span().strays_high == 1);
    // The least gap given when the span is read (the heights' unit learned after them):
    // 20 m in feet is 65.6 ft, so a return 60 ft above a flat survey stays, 70 ft above goes.
    core::HeightSpan sixty(20.0), seventy(20.0);
    addEven(sixty, 10000, 0.0, 3.0);
    sixty.add(63.0f);
    addEven(seventy, 10000, 0.0, 3.0);
    seventy.add(73.0f);
    CHECK(sixty.span().strays_high == 1);  // 60 metres apart
    CHECK(sixty.span(20.0 / 0.3048).strays_high == 0);
    CHECK(seventy.span(20.0 / 0.3048).strays_high == 1);
}

TEST_CASE("height span: heights far apart widen the bins, in bounded memory, whatever their order") {
    // A body 3,000 m tall holds more bins of min_gap / 64 than kMaxBins: they widen. A
    // return at 3e38 (a broken file) is one more bin; the body's ends stay exact.
    std::vector<float> heights;
    for (int k = 0; k < 20000; ++k) heights.push_back(float(100.0 + 3000.0 * k / 19999.0));
    heights.push_back(3e38f);
    heights.push_back(-2e9f);
    core::HeightSpan forwards(20.0), backwards(20.0);
    for (const float z : heights) forwards.add(z);
    for (auto it = heights.rbegin(); it != heights.rend(); ++it) backwards.add(*it);
    for (const core::HeightSpan* s : {&forwards, &backwards}) {
        const core::HeightSpan::Span sp = s->span();
        CHECK(sp.lo == 100.0);
        CHECK(sp.hi == 3100.0);
        CHECK(sp.strays_low == 1);
        CHECK(sp.strays_high == 1);
    }
    // Not-a-number and infinities are skipped.
    forwards.add(std::nanf(""));
    forwards.add(INFINITY);
    CHECK(forwards.count() == heights.size());
}

TEST_CASE("height span: merged spans give the span of all their heights") {
    core::HeightSpan a(20.0), b(20.0), all(20.0);
    addEven(a, 6000, 250.0, 390.0);
    addEven(b, 6000, 255.0, 385.0);
    addEven(b, 5, 850.0, 900.0);
    b.add(1e7f);  // b's bins are wider than a's
    for (core::HeightSpan* s : {&all}) {
        addEven(*s, 6000, 250.0, 390.0);
        addEven(*s, 6000, 255.0, 385.0);
        addEven(*s, 5, 850.0, 900.0);
        s->add(1e7f);
    }
    a.merge(b);
    CHECK(a.count() == all.count());
    CHECK(a.span().hi == all.span().hi);
    CHECK(a.span().hi == 390.0);
    CHECK(a.span().strays_high == 6);
    // Merged the other way (the wider into the narrower's place) the same.
    core::HeightSpan c(20.0);
    addEven(c, 6000, 250.0, 390.0);
    b.merge(c);
    CHECK(b.span().hi == 390.0);
    CHECK(b.span().strays_high == 6);
    CHECK_THROWS_AS(a.merge(core::HeightSpan(10.0)), core::Error);
}

TEST_CASE("height span: refusals") {
    CHECK_THROWS_AS(core::HeightSpan{0.0}, core::Error);
    CHECK_THROWS_AS(core::HeightSpan{-1.0}, core::Error);
    CHECK_THROWS_AS(core::HeightSpan{double(INFINITY)}, core::Error);
}

TEST_CASE("height span: the viewer's sample keeps the strays and the body's ends exact") {
    // 200,000 heights over 250-390 m with 20 strays at 800-900 m among the later ones: one
    // height in 8 inside the body once it is known, every height outside it.
    core::HeightSpan every(20.0), sampled(20.0);
    for (int k = 0; k < 200000; ++k) {
        const float z = float(250.0 + 140.0 * double((k * 7919) % 200000) / 199999.0);
        every.add(z);
        sampled.addSampled(z, 8);
        if (k % 5000 == 4999 && k > 100000) {
            const float stray = float(800.0 + k % 97);
            every.add(stray);
            sampled.addSampled(stray, 8);
        }
    }
    const core::HeightSpan::Span a = every.span(), b = sampled.span();
    CHECK(a.strays_high == 20);
    CHECK(b.strays_high == a.strays_high);
    CHECK(b.hi == a.hi);
    CHECK(b.lo == a.lo);
    // The inside counted in eights: the count is the same to within a bin's sampling.
    CHECK(double(sampled.count()) == doctest::Approx(double(every.count())).epsilon(0.01));
}
