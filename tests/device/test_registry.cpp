// The device registry (device/registry.hpp): this build's backends by name, the devices
// they make, and each backend's own options refused on another.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "common/error.hpp"
#include "common/hardware_config.hpp"
#include "device/registry.hpp"

namespace rpu::device {
namespace {

// The message of the rpu::Error `f` throws, or "" if it throws none.
template <class F>
std::string error_of(F f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Registry, ListsTheFunctionalAndCycleBackendsFirst) {
  const std::vector<std::string> names = Registry().names();
  ASSERT_GE(names.size(), 2u);
  EXPECT_EQ(names[0], "functional");
  EXPECT_EQ(names[1], "cycle");
}

TEST(Registry, MakesADeviceOfTheNamedBackend) {
  for (const char* name : {"functional", "cycle"}) {
    EXPECT_EQ(make_device(name, hardware_config("tiny"), fp::kFp32)->backend(), name);
  }
  EXPECT_EQ(error_of([] { make_device("warp-drive", hardware_config("tiny"), fp::kFp32); }).rfind(
                "no device backend 'warp-drive' in this build (it has functional, cycle", 0),
            0u);
}

// Options that only one backend reads are refused with any other, each given one named.
TEST(Registry, ABackendsOwnOptionsNeedThatBackend) {
  const auto refused = [](const std::string& args, std::string_view chosen) {
    CLI::App app;
    Registry registry;
    registry.add_options(app);
    app.parse(args, false);
    return error_of([&] { registry.refuse_others(chosen); });
  };
  EXPECT_EQ(refused("--heatmap h.png", "functional"), "--heatmap needs --backend cycle");
  EXPECT_EQ(refused("--trace t.json --trace-window 0 9", "reference"), "--trace and --trace-window need --backend cycle");
  EXPECT_EQ(refused("--heatmap h.png --trace t.json --trace-window 0 9", "functional"),
            "--heatmap, --trace and --trace-window need --backend cycle");
  EXPECT_EQ(refused("--heatmap h.png --trace-window 0 9", "cycle"), "");
}

// A trace window must be non-empty and choose the cycles of a trace.
TEST(Registry, TheCycleBackendRefusesAnEmptyTraceWindowOrOneWithoutATrace) {
  const auto checked = [](const std::string& args) {
    CLI::App app;
    Registry registry;
    registry.add_options(app);
    app.parse(args, false);
    return error_of([&] { registry.find("cycle")->check(RenderSettings{}, "1"); });
  };
  EXPECT_EQ(checked("--trace t.json --trace-window 5 5"), "--trace-window 5 5: the window is empty");
  EXPECT_EQ(checked("--trace-window 0 10"), "--trace-window needs --trace: it chooses the cycles --trace records");
  EXPECT_EQ(checked("--trace t.json --trace-window 0 10"), "");
}

}  // namespace
}  // namespace rpu::device
