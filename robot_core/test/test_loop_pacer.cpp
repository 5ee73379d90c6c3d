// The loop pacer: a woken loop runs at once, the configured rate stays a ceiling under a flood
// of inputs, and without inputs the loop keeps its period exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "robot_core/loop_pacer.h"

using robot_core::LoopPacer;

namespace {

// Runs a loop from 0 to `end` s: it runs whenever due (checked every `step` s) and is woken at
// each time in `inputs`. Returns the run times.
std::vector<double> simulate(LoopPacer& p, const std::vector<double>& inputs, double end, double step = 1e-4) {
  std::vector<double> runs;
  size_t next_input = 0;
  for (long i = 0; i * step <= end; ++i) {
    const double now = i * step;
    while (next_input < inputs.size() && inputs[next_input] <= now + 1e-12) {
      p.wake();
      ++next_input;
    }
    if (p.due(now)) {
      p.ran(now);
      runs.push_back(now);
    }
  }
  return runs;
}

}  // namespace

TEST(LoopPacer, FirstRunIsAtOnceThenOncePerPeriod) {
  LoopPacer p(0.02);
  EXPECT_TRUE(p.due(0.0));
  p.ran(0.0);
  EXPECT_FALSE(p.due(0.019));
  EXPECT_NEAR(p.next(), 0.02, 1e-12);
}

TEST(LoopPacer, WithoutInputsItKeepsItsRateWhateverEachRunsLateness) {
  LoopPacer p(0.02);
  p.ran(0.0);
  // Each run starts 3 ms late: the schedule does not drift.
  for (int k = 1; k <= 100; ++k) {
    EXPECT_NEAR(p.next(), 0.02 * k, 1e-9);
    p.ran(0.02 * k + 0.003);
  }
}

TEST(LoopPacer, ATimerTickALittleEarlyIsOnTimeSoNoTickIsSkipped) {
  // The first run came 4 ms after its tick; later ticks come 0-1 ms after theirs: every tick
  // runs, and the schedule stays where the first run put it.
  LoopPacer p(0.05);
  p.ran(0.004);
  int runs = 1;
  for (int k = 1; k <= 40; ++k) {
    const double tick = 0.05 * k + (k % 2) * 0.001;
    EXPECT_FALSE(p.due(tick));  // strictly, before next()
    ASSERT_TRUE(p.dueForTick(tick)) << "tick " << k;
    p.ran(tick);
    ++runs;
    EXPECT_NEAR(p.next(), 0.004 + 0.05 * (k + 1), 1e-9);
  }
  EXPECT_EQ(runs, 41);
  EXPECT_FALSE(p.dueForTick(p.next() - 0.03));  // more than half a period early: not yet
}

TEST(LoopPacer, AWokenLoopRunsAtOnceOnItsSpareTokenThenWaitsForTheNext) {
  LoopPacer p(0.02);
  p.ran(0.0);
  p.ran(0.02);
  p.wake();  // 7 ms after a tick: the spare token serves it at once
  EXPECT_TRUE(p.due(0.027));
  p.ran(0.027);
  // 5 ms later the bucket holds 0.35 + 0.25 tokens: the next wake waits for a whole one.
  p.wake();
  EXPECT_FALSE(p.due(0.032));
  EXPECT_NEAR(p.next(), 0.027 + 0.65 * 0.02, 1e-12);
}

TEST(LoopPacer, InputsAtTheLoopRateAreServedWithinTheirJitter) {
  // A sensor at the loop's own rate, phase 7 ms after the loop's, with +-1 ms of jitter: after
  // the first input the loop runs on the inputs, not on its old ticks.
  LoopPacer p(0.02);
  std::vector<double> inputs;
  for (int k = 0; k < 200; ++k) inputs.push_back(0.007 + 0.02 * k + ((k * 7919) % 21 - 10) * 1e-4);
  const auto runs = simulate(p, inputs, 4.0);
  double worst = 0.0;
  for (size_t k = 1; k < inputs.size(); ++k) {
    const auto it = std::lower_bound(runs.begin(), runs.end(), inputs[k] - 1e-9);
    ASSERT_NE(it, runs.end());
    worst = std::max(worst, *it - inputs[k]);
  }
  EXPECT_LT(worst, 0.0002);  // served at once (one step); a plain 50 Hz tick: up to 20 ms
}

TEST(LoopPacer, InputsSlowerThanTheLoopAreServedWithinAPeriodAndKeepItsRate) {
  LoopPacer p(0.02);  // a 50 Hz loop, a 20 Hz sensor
  std::vector<double> inputs;
  for (int k = 0; k < 80; ++k) inputs.push_back(0.013 + 0.05 * k);
  const auto runs = simulate(p, inputs, 4.0);
  for (double t : inputs) {
    const auto it = std::lower_bound(runs.begin(), runs.end(), t - 1e-9);
    ASSERT_NE(it, runs.end());
    EXPECT_LT(*it - t, 0.02);  // at once with a token, else when the next one comes
  }
  EXPECT_GE(runs.size(), 0.98 * 4.0 / 0.02);
  EXPECT_LE(runs.size(), 4.0 / 0.02 + 2);
}

TEST(LoopPacer, AFloodOfInputsDoesNotRaiseTheRate) {
  LoopPacer p(0.02);
  std::vector<double> inputs;
  for (int k = 0; k < 10000; ++k) inputs.push_back(k * 0.0003);  // 3.3 kHz
  const auto runs = simulate(p, inputs, 3.0);
  EXPECT_LE(runs.size(), 3.0 / 0.02 + 2);
  EXPECT_GE(runs.size(), 3.0 / 0.02 - 2);
  // No window of one second holds more than rate + 2 runs.
  for (size_t i = 0; i < runs.size(); ++i) {
    const auto end = std::upper_bound(runs.begin(), runs.end(), runs[i] + 1.0 - 1e-9);
    EXPECT_LE(end - (runs.begin() + i), 52);
  }
}

TEST(LoopPacer, AfterAWokenRunAtItsRateTheNextTickWaitsHalfAPeriodForALateInput) {
  LoopPacer p(0.02);
  p.ran(0.0);
  p.wake();
  p.ran(0.01);                          // woken within 1.2 periods of the last run
  EXPECT_NEAR(p.next(), 0.04, 1e-12);  // the tick of 0.03 waits to 0.04: a late input still wins
  p.ran(0.04);                          // none came: the postponed tick, counted in its slot...
  EXPECT_NEAR(p.next(), 0.05, 1e-12);   // ...so the schedule has not moved
  p.wake();
  p.ran(0.08);                          // woken 1.5 periods after the last run: slower input
  EXPECT_NEAR(p.next(), 0.10, 1e-12);   // no patience: it would pull the loop below its rate
}

TEST(LoopPacer, InputsSlowerThanItsRateDoNotPullTheLoopBelowIt) {
  // Commands every 25, 30 or 50 ms into a 50 Hz loop: the loop still runs 50 times a second.
  for (double gap : {0.025, 0.03, 0.05}) {
    LoopPacer p(0.02);
    std::vector<double> inputs;
    for (int k = 0; k * gap < 4.0; ++k) inputs.push_back(0.005 + gap * k);
    const auto runs = simulate(p, inputs, 4.0);
    EXPECT_GE(runs.size(), 0.98 * 4.0 / 0.02) << "commands every " << gap << " s";
    EXPECT_LE(runs.size(), 4.0 / 0.02 + 2) << "commands every " << gap << " s";
  }
}

namespace {

// The worst wait for a run of the inputs between `from` and `until` s.
double worstWait(const std::vector<double>& inputs, const std::vector<double>& runs, double from, double until = 1e9) {
  double worst = 0.0;
  for (double t : inputs) {
    if (t < from || t >= until) continue;
    const auto it = std::lower_bound(runs.begin(), runs.end(), t - 1e-9);
    if (it == runs.end()) return 1e9;
    worst = std::max(worst, *it - t);
  }
  return worst;
}

// A 50 Hz sensor 7 ms after the loop's phase, and at 1.0 s and 1.5 s a reading from a second
// source: two runs more than the stream's rate.
std::vector<double> streamWithTwoExtras() {
  std::vector<double> inputs;
  for (int k = 0; k < 200; ++k) inputs.push_back(0.007 + 0.02 * k);
  inputs.push_back(1.0);
  inputs.push_back(1.5);
  std::sort(inputs.begin(), inputs.end());
  return inputs;
}

}  // namespace

TEST(LoopPacer, AStreamAsFastAsTheCeilingWaitsForItsTokensForGoodAfterTwoExtraRuns) {
  // Why a woken loop needs a ceiling above its stream: with none, the two extra runs empty the
  // bucket and every later reading waits for its token (here 13 ms of each 20 ms period).
  LoopPacer p(0.02);
  const auto inputs = streamWithTwoExtras();
  const auto runs = simulate(p, inputs, 4.0);
  EXPECT_LT(worstWait(inputs, runs, 0.0, 0.99), 0.0002);  // at once before the extras...
  EXPECT_GT(worstWait(inputs, runs, 3.0), 0.010);          // ...long after them, 13 ms late
  EXPECT_LT(worstWait(inputs, runs, 0.0), 0.02);           // (never more than a period)
}

TEST(LoopPacer, ACeilingAboveTheStreamRefillsWhatExtraRunsTake) {
  LoopPacer p(0.02, 0.01);  // 50 Hz loop, 100 Hz ceiling
  const auto inputs = streamWithTwoExtras();
  const auto runs = simulate(p, inputs, 4.0);
  EXPECT_LT(worstWait(inputs, runs, 0.0), 0.0002);  // every input at once, extras included
  // The runs still follow the stream: about 50 a second, not the ceiling's 100.
  EXPECT_LE(runs.size(), inputs.size() + 2);
}

TEST(LoopPacer, AFloodStaysUnderTheCeiling) {
  LoopPacer p(0.02, 0.01);
  std::vector<double> inputs;
  for (int k = 0; k < 10000; ++k) inputs.push_back(k * 0.0003);
  const auto runs = simulate(p, inputs, 3.0);
  for (size_t i = 0; i < runs.size(); ++i) {
    const auto end = std::upper_bound(runs.begin(), runs.end(), runs[i] + 1.0 - 1e-9);
    EXPECT_LE(end - (runs.begin() + i), 102);  // max_rate + 2 in any second
  }
  EXPECT_GE(runs.size(), 3.0 / 0.01 - 2);
}

TEST(LoopPacer, WithoutInputsACeilingAboveTheRateKeepsThePeriod) {
  LoopPacer p(0.02, 0.01);
  const auto runs = simulate(p, {}, 2.0);
  EXPECT_NEAR(static_cast<double>(runs.size()), 2.0 / 0.02 + 1, 1.0);
}

TEST(LoopPacer, AnInputJustAfterAnEarlyTickRunsAtOnce) {
  // The loop's schedule follows a stream at phase 7 ms while its timer ticks at phase 0: the
  // tick of 0.060 runs 7 ms before its slot (0.067) and counts there; a command at 0.061 must
  // not wait for that slot (it has a token).
  LoopPacer p(0.02, 0.01);
  p.ran(0.007);
  p.ran(0.027);
  p.ran(0.047);
  ASSERT_TRUE(p.dueForTick(0.060));
  p.ran(0.060);
  EXPECT_NEAR(p.next(), 0.087, 1e-12);  // the schedule has not moved
  p.wake();
  EXPECT_TRUE(p.due(0.061));
}
