// The chip's co-simulation (docs/chip.md): a frame of firmware over a scene on
// the Verilated chip of a named configuration (rtl/rpu_top.sv), every core in lockstep
// with the functional model (sim/spu_checker.hpp) and the framebuffer compared with
// the functional model's at the end; the memory port served by the cycle model's DRAM.
//
//   chip_cosim --config default --scene cornell --width 16 --height 12 [--isect woop]
//   chip_cosim --config tiny --write-vectors FILE --write-framebuffer FILE   (rtl/flow.py synth --unit chip)
#include <chrono>
#include <cstdio>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "asm/builtin_firmware.hpp"
#include "asm/firmware_file.hpp"
#include "chip_run.hpp"
#include "common/error.hpp"
#include "common/hardware_config.hpp"
#include "common/output_file.hpp"
#include "cosim_core.hpp"
#include "device/device.hpp"
#include "functional/scene_image.hpp"
#include "harness_outputs.hpp"
#include "kdtree/kdtree.hpp"
#include "scene/resolve.hpp"

namespace {

using namespace rpu;
using namespace rpu::sim;

struct Options {
  std::string config = "tiny";
  std::string scene = "cornell";
  std::string firmware;
  std::string isect = "woop";
  int width = 8, height = 6, spp = 1, max_depth = 2;
  std::uint64_t watchdog = 1'000'000;
  std::uint64_t seed = 1;
  std::string trace, vectors, framebuffer;
};

using ChipModel = Model<harness::Chip>;

int run(const Options& o, std::unique_ptr<ChipModel>& model) {
  const spec::HardwareConfig& config = hardware_config(o.config);
  const fp::Format format = fp::format_by_name(std::string(config.format));
  const ModelInfo* info = find_model<harness::Chip>({{"config", o.config}, {"isect", o.isect}});
  if (!info) {
    throw Error(fmt::format("no chip model for configuration '{}' with the {} test in this build (built: {})",
                            o.config, o.isect, built_models<harness::Chip>()));
  }
  model = make_model<harness::Chip>(*info, o.seed, o.trace);
  if (!o.framebuffer.empty()) check_output_path(o.framebuffer);
  std::unique_ptr<OutputFile> vectors;
  RecordingModel<harness::Chip>* recorder = nullptr;
  if (!o.vectors.empty()) {
    vectors = std::make_unique<OutputFile>(o.vectors);
    auto recording = std::make_unique<RecordingModel<harness::Chip>>(std::move(model), vectors->stream());
    recording->start();
    recorder = recording.get();
    model = std::move(recording);
  }
  KdBuildConfig build = kd_build_config_for(config);
  build.format = format;
  const Scene scene = functional::chip_space_scene(resolve_scene(o.scene), format);
  const IsectMode mode = o.isect == "woop" ? IsectMode::kWoop : IsectMode::kWatertight;
  const functional::SceneImage si = functional::make_scene_image(scene, build, mode);
  const isa::Firmware firmware =
      o.firmware.empty() ? isa::builtin_firmware("whitted.s") : isa::load_firmware_or_assemble(o.firmware);
  const device::Launch launch{o.width, o.height, o.spp, o.max_depth, 1};
  const std::vector<std::uint8_t> launch_block = device::make_launch_block(
      si.image.bytes, si.layout, launch, device::shader_table(firmware, shader_names(scene)));

  ChipFrame frame;
  frame.config = &config;
  frame.format = format;
  frame.image = si.image.bytes;
  frame.layout = &si.layout;
  frame.firmware = &firmware;
  frame.launch_block = launch_block;
  frame.launch = launch;
  frame.watchdog = o.watchdog;
  ChipRunOptions options;
  options.lockstep = true;
  const auto start = std::chrono::steady_clock::now();
  const ChipRunResult r = run_chip_frame(*model, *info, frame, options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::uint64_t instructions = 0;
  for (const std::uint64_t n : r.retired) instructions += n;
  fmt::print("chip_cosim ok: config {}, {} ({}, {}), {}x{} pixels, {} cycles, {} steps in lockstep, {} instructions, "
             "{} rays, {:.2f} s, {:.0f} cycles/s\n",
             o.config, o.scene, format.name(), o.isect, o.width, o.height, r.cycles, r.lockstep_steps, instructions,
             r.closest_rays + r.any_rays, seconds, static_cast<double>(r.cycles) / std::max(seconds, 1e-9));
  if (r.fault) fmt::print("the frame faulted at pixel {}, the same on both\n", r.fault->pixel);
  if (vectors) {
    vectors->commit();
    fmt::print("chip_cosim: wrote {} cycles' ports to {}\n", recorder->cycles(), o.vectors);
  }
  if (!o.framebuffer.empty()) {
    OutputFile file(o.framebuffer);
    file.stream().write(reinterpret_cast<const char*>(r.framebuffer.data()),
                        static_cast<std::streamsize>(r.framebuffer.size()));
    file.commit();
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Co-simulate the RTL chip in lockstep with the functional model (docs/rtl.md)"};
  Options o;
  app.add_option("--config", o.config, "named hardware configuration (spec/configs.toml)");
  app.add_option("--scene", o.scene, "scene file or built-in scene, as rpu render takes it");
  app.add_option("--firmware", o.firmware, "firmware (.s or .rfw); default the built-in whitted.s");
  app.add_option("--isect", o.isect, "intersection test")->check(CLI::IsMember({"woop", "watertight"}));
  app.add_option("--width", o.width, "pixels")->check(CLI::Range(1, 4096));
  app.add_option("--height", o.height, "pixels")->check(CLI::Range(1, 4096));
  app.add_option("--spp", o.spp, "samples per pixel")->check(CLI::Range(1, 1024));
  app.add_option("--max-depth", o.max_depth, "bounces")->check(CLI::Range(0, 64));
  app.add_option("--watchdog", o.watchdog, "instructions a thread may retire for one pixel")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{0xffffffff}));
  app.add_option("--seed", o.seed, "seed of the RTL's initial values");
  app.add_option("--trace", o.trace, "write FST waveforms here");
  app.add_option("--write-vectors", o.vectors, "write every cycle's ports here (rtl/flow.py's netlist testbench)");
  app.add_option("--write-framebuffer", o.framebuffer,
                 "write the framebuffer the chip wrote here, pixels x 16 bytes as in device memory");
  CLI11_PARSE(app, argc, argv);
  report_sigbus_as_write_failure("chip_cosim");
  std::unique_ptr<ChipModel> model;
  return run_harness("chip_cosim", o.trace, o.vectors, model,
                     [&o](std::unique_ptr<ChipModel>& m) { return run(o, m); });
}
