// sim/cosim_core.hpp: each check of the harness core fails when it should, on a small
// C++ model (a one-deep register answering requests by tag), and the field report
// names the field that differs.
#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "cosim_core.hpp"
#include "rpu/streams.hpp"

namespace rpu::sim {
namespace {

// Answers each accepted request one cycle later with the request's tag; `extra` makes
// it answer once more after that (a leftover).
struct EchoModel {
  struct Inputs {
    bool rst_n = false;
    bool req_valid = false;
    std::uint32_t tag = 0;
    bool rsp_ready = false;
  };
  struct Outputs {
    bool req_ready = false;
    bool rsp_valid = false;
    std::uint32_t tag = 0;
  };
  bool full = false, extra = false;
  std::uint32_t held = 0;
  Inputs applied;

  Outputs settle(const Inputs& in) {
    applied = in;
    return {!full, full, held};
  }
  void clock() {
    if (!applied.rst_n) {
      full = false;
      return;
    }
    if (full && applied.rsp_ready) full = extra ? std::exchange(extra, false) : false;
    if (!full && applied.req_valid) {
      full = true;
      held = applied.tag;
    }
  }
};

TEST(CosimCore, ResetHoldsRstLowThenReleasesIt) {
  EchoModel m;
  m.full = true;
  Clock clock(m);
  EchoModel::Inputs in;
  in.req_valid = true;
  clock.reset(in);
  EXPECT_TRUE(in.rst_n);
  EXPECT_FALSE(m.full);
  EXPECT_EQ(clock.cycle(), 0u);
}

TEST(CosimCore, PendingByTagPairsInAnyOrderAndRefusesUnknownAndReusedTags) {
  PendingByTag<int> pending("tu_req", "tu_rsp", 8);
  pending.add(3, 30);
  pending.add(5, 50);
  EXPECT_THROW(pending.add(3, 31), CosimFailure);
  EXPECT_EQ(pending.take(5), 50);
  EXPECT_EQ(pending.oldest(), 30);
  try {
    pending.take(7);
    FAIL() << "an unknown tag was taken";
  } catch (const CosimFailure& e) {
    EXPECT_NE(std::string(e.what()).find("tu_rsp with tag 0x07"), std::string::npos) << e.what();
  }
  EXPECT_THROW(pending.check_empty([](int v) { return std::to_string(v); }), CosimFailure);
  EXPECT_EQ(pending.take(3), 30);
  EXPECT_NO_THROW(pending.check_empty([](int v) { return std::to_string(v); }));
}

TEST(CosimCore, WatchdogFiresOnlyWhileSomethingIsOwed) {
  Watchdog w(10);
  for (std::uint64_t c = 0; c < 100; ++c) w.check(c, false, [] { return ""; });
  w.progress(100);
  EXPECT_NO_THROW(w.check(110, true, [] { return "ray 4"; }));
  try {
    w.check(111, true, [] { return "ray 4"; });
    FAIL() << "no time-out";
  } catch (const CosimFailure& e) {
    EXPECT_NE(std::string(e.what()).find("ray 4"), std::string::npos) << e.what();
  }
}

TEST(CosimCore, ExpectQuietCatchesAnAnswerNobodyAskedFor) {
  const auto leftover = [](const EchoModel::Outputs& out) { return out.rsp_valid ? std::string("a rsp") : ""; };
  EchoModel m;
  Clock clock(m);
  EchoModel::Inputs in;
  clock.reset(in);
  in.rsp_ready = true;
  EXPECT_NO_THROW(expect_quiet(clock, in, 8, leftover));
  m.full = m.extra = true;
  EXPECT_THROW(expect_quiet(clock, in, 8, leftover), CosimFailure);
}

TEST(CosimCore, FieldMismatchNamesTheFirstDifferingFieldInCaredBits) {
  streams::IuRsp want{7, 1, 0x3f800000, 2, 3}, got = want;
  EXPECT_EQ(field_mismatch(want, got), "");
  got.u = 9;
  got.v = 4;
  const std::string report = field_mismatch(want, got);
  EXPECT_EQ(report.rfind("iu_rsp.u: expected 0x00000002, got 0x00000009", 0), 0u) << report;
  EXPECT_NE(report.find("v (differs)"), std::string::npos) << report;
  streams::IuRsp care = all_fields<streams::IuRsp>();
  care.u = care.v = 0;
  EXPECT_EQ(field_mismatch(want, got, care), "");
}

TEST(CosimCore, StallsAreSeededAndNearTheirProbability) {
  Stalls a(3, 0.25), b(3, 0.25);
  int stalls = 0;
  for (int i = 0; i < 10000; ++i) {
    const bool s = a();
    EXPECT_EQ(s, b());
    stalls += s;
  }
  EXPECT_NEAR(stalls, 2500, 200);
}

}  // namespace
}  // namespace rpu::sim
