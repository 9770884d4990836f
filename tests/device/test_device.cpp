// The Device API with the functional backend: loading, launching, statistics, and
// how a faulting shader is reported.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "asm/assembler.hpp"
#include "common/hardware_config.hpp"
#include "device/device.hpp"
#include "device/render_frame.hpp"
#include "functional/scene_image.hpp"
#include "scene/resolve.hpp"

namespace rpu::device {
namespace {

isa::Firmware assemble_text(const std::string& text) {
  return isa::assemble("test.s", [&](const std::filesystem::path&) { return std::optional<std::string>(text); });
}

struct Fixture {
  Scene scene = resolve_scene("tests/isa/scenes/one_triangle.json");
  functional::SceneImage si = functional::make_scene_image(scene, kd_build_config_for("default"), IsectMode::kWoop);
};

// Per pixel: one closest-hit ray from the camera position along -z, its t stored as
// the pixel's red channel. 13 instructions per pixel.
const char* kOneRayPerPixel = R"(
raygen:
        li      r15.x, DEVICE_LAUNCH_BASE
        ldf     r0.xyz, [r15 + LAUNCH_ORIGIN_AT]
        li      r0.w, 0
        lif     r1.xy, 0.0
        lif     r1.z, -1.0
        lif     r1.w, inf
        trace   r2, r0, r1
        ld1     r3.x, [r15 + LAUNCH_FRAMEBUFFER_AT]
        rdsr    r4, pixel
        shli    r4.x, r4.z, 4
        iadd    r3.x, r3.x, r4.x
        st      [r3], r2
        halt
hit_whitted:
        ret
)";

TEST(FunctionalDevice, StatisticsCountEveryInstructionAndRay) {
  const Fixture f;
  const auto dev = make_functional_device(hardware_config("tiny"), fp::kFp32);
  RenderSettings s;
  s.width = 5;
  s.height = 3;
  s.spp = 1;
  render_frame(*dev, f.scene, f.si.image, assemble_text(kOneRayPerPixel), s);
  const functional::ShaderStats st = dev->stats().shader;
  EXPECT_EQ(st.pixels, 15u);
  EXPECT_EQ(st.instructions(), 15u * 13u);
  EXPECT_EQ(st.closest_rays, 15u);
  EXPECT_EQ(st.any_rays, 0u);
  const auto cls = [&](spec::isa::Class c) { return st.retired[static_cast<std::size_t>(c)]; };
  EXPECT_EQ(cls(spec::isa::Class::kTrace), 15u);
  EXPECT_EQ(cls(spec::isa::Class::kMem), 15u * 3u);      // ldf, ld1, st
  EXPECT_EQ(cls(spec::isa::Class::kSpecial), 15u);       // rdsr
  EXPECT_EQ(cls(spec::isa::Class::kBranch), 15u);        // halt
  // No divergence: every issue step of a full chunk (2 on tiny) runs both threads;
  // the last chunk of 15 pixels holds one.
  EXPECT_EQ(st.chunk_issues, 8u * 13u);
  for (const glm::vec4& p : dev->read_framebuffer()) EXPECT_EQ(p.x, 5.0f);  // the triangle at z = 0
}

TEST(FunctionalDevice, FirmwareWithoutTheScenesShaderIsRefused) {
  const Fixture f;
  const auto dev = make_functional_device(hardware_config("tiny"), fp::kFp32);
  dev->load_image(f.si.image.bytes, f.scene.source);
  try {
    dev->load_firmware(assemble_text("raygen:\n halt\n"), shader_names(f.scene));
    FAIL() << "firmware without hit_whitted was accepted";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "the firmware has no code label 'hit_whitted' for the scene's shader 'whitted'");
  }
}

TEST(FunctionalDevice, LaunchBeforeLoadingIsAnError) {
  const auto dev = make_functional_device(hardware_config("tiny"), fp::kFp32);
  EXPECT_THROW(dev->launch({4, 4, 1, 0, 1}), Error);
}

// Pixels from 5 on load from an unmapped address. Whatever the host threads do, the
// error names pixel 5, the first in pixel order.
TEST(FunctionalDevice, TheFirstFaultingPixelIsReportedWhateverTheHostThreads) {
  const Fixture f;
  const char* firmware = R"(
raygen:
        rdsr    r0, pixel
        ilti    r1.x, r0.z, 5
        bnz     r1.x, fine
        li      r2.x, 0x30000000
        ld      r3, [r2]
fine:
        halt
hit_whitted:
        ret
)";
  for (const int threads : {1, 2}) {
    FunctionalOptions o;
    o.host_threads = threads;
    const auto dev = make_functional_device(hardware_config("default"), fp::kFp32, o);
    RenderSettings s;
    s.width = 16;
    s.height = 16;
    s.spp = 1;
    try {
      render_frame(*dev, f.scene, f.si.image, assemble_text(firmware), s);
      FAIL() << "the fault was not reported";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("shader fault in thread 33 (core 1, chunk 0, lane 1; pixel 5, 0) at pc 4 (ld r3, [r2])"),
                std::string::npos)
          << m;
      EXPECT_NE(m.find("load of 16 bytes at address 0x30000000 is outside the device memory"), std::string::npos)
          << m;
    }
  }
}

// Issue 14 (4): firmware without raygen is refused when it is loaded, before the
// frame's host threads make their shader cores.
TEST(FunctionalDevice, FirmwareWithoutRaygenIsRefusedWhenLoaded) {
  const Fixture f;
  FunctionalOptions o;
  o.host_threads = 4;
  const auto dev = make_functional_device(hardware_config("default"), fp::kFp32, o);
  dev->load_image(f.si.image.bytes, f.scene.source);
  try {
    dev->load_firmware(assemble_text("main:\n halt\nhit_whitted:\n ret\n"), shader_names(f.scene));
    FAIL() << "firmware without raygen was accepted";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "the firmware has no code label 'raygen' (the ray-generation entry point every thread starts at)");
  }
}

// Any exception on any host thread, not only a shader fault, reaches wait() as it would
// on one thread, instead of ending the process: here the progress callback's.
TEST(FunctionalDevice, AnErrorOnAnyHostThreadIsReportedAsOnOne) {
  const Fixture f;
  for (const int threads : {1, 2, 4}) {
    FunctionalOptions o;
    o.host_threads = threads;
    const auto dev = make_functional_device(hardware_config("default"), fp::kFp32, o);
    dev->load_image(f.si.image.bytes, f.scene.source);
    dev->load_firmware(assemble_text(kOneRayPerPixel), shader_names(f.scene));
    dev->launch({16, 16, 1, 0, 1}, [](std::size_t, std::size_t) { throw std::runtime_error("the display went away"); });
    try {
      dev->wait();
      FAIL() << "the callback's exception was lost on " << threads << " host threads";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "the display went away") << threads << " host threads";
    }
  }
}

// A device destroyed while its frame runs waits for the frame instead of leaving it to
// call into a destroyed backend ("pure virtual method called").
TEST(FunctionalDevice, DestroyingADeviceDuringItsFrameWaitsForTheFrame) {
  const Fixture f;
  FunctionalOptions o;
  o.watchdog = 200'000;
  for (int i = 0; i < 3; ++i) {
    const auto dev = make_functional_device(hardware_config("tiny"), fp::kFp32, o);
    dev->load_image(f.si.image.bytes, f.scene.source);
    dev->load_firmware(assemble_text("raygen:\nloop:\n iaddi r1.x, r1.x, 1\n bra loop\nhit_whitted:\n ret\n"),
                       shader_names(f.scene));
    dev->launch({4, 4, 1, 0, 1});
  }
}

}  // namespace
}  // namespace rpu::device
