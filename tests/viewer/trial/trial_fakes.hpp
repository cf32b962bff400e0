// tests/viewer/trial/trial_fakes.hpp: a trial source and an observer in memory, for the
// trial controller's and the questionnaire flow's tests (no cloud is produced).
#pragma once
#include <viewer/trial.hpp>

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace viewer::test {

/// `count` trials named "trial K" with `setup`'s other fields; `questions[gap]` asked at gap.
class FakeTrialSource final : public TrialSource {
  public:
    int count() const override { return trials; }
    TrialSetup begin(int trial, CloudFeed&) override {
        began.push_back(trial);
        TrialSetup s = setup;
        s.name = "trial " + std::to_string(trial);
        return s;
    }
    void end(int trial) override { ended.push_back(trial); }
    std::vector<Question> questions(int gap) override {
        const auto it = asked.find(gap);
        return it == asked.end() ? std::vector<Question>{} : it->second;
    }

    int trials = 2;
    TrialSetup setup;
    std::map<int, std::vector<Question>> asked;
    std::vector<int> began, ended;
};

/// Every call, as "what trial ..." lines, and the last outcome.
class FakeTrialObserver final : public TrialObserver {
  public:
    void onStart(int trial) override { calls.push_back("start " + std::to_string(trial)); }
    void onDesignate(int trial, double, const glm::dvec3& w) override {
        calls.push_back("designate " + std::to_string(trial));
        designated.push_back(w);
    }
    void onWithdraw(int trial, double) override { calls.push_back("withdraw " + std::to_string(trial)); }
    void onVerdict(int trial, double, const core::Candidate& c, Verdict v) override {
        calls.push_back(std::string("verdict ") + std::to_string(trial) + " " + c.id + " " + verdictName(v));
    }
    void onEnd(int trial, const TrialOutcome& o) override {
        calls.push_back(std::string("end ") + std::to_string(trial) + " " + decisionName(o.decision));
        outcome = o;
    }
    void onAnswer(int gap, int question, const Answer& a) override {
        calls.push_back("answer " + std::to_string(gap) + " " + std::to_string(question) + " " + a.response +
                        (a.skipped ? " skipped" : ""));
    }

    std::vector<std::string> calls;
    std::vector<glm::dvec3> designated;
    TrialOutcome outcome;
};

/// A rating item from 0 to 3.
inline Question rating(const std::string& title, int number, int count) {
    Question q;
    q.title = title;
    q.text = "item " + std::to_string(number);
    q.number = number;
    q.count = count;
    return q;
}

}  // namespace viewer::test
