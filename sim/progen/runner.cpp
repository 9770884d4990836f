#include "progen/runner.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "common/error.hpp"
#include "fp/fast32.hpp"
#include "kdtree/kdtree.hpp"
#include "scene/resolve.hpp"

namespace rpu::progen {

namespace {

functional::SceneImage scene_image(const spec::HardwareConfig& config, fp::Format format, const std::string& name) {
  const KdBuildConfig build = kd_build_config_for(config);
  return functional::make_scene_image(functional::chip_space_scene(resolve_scene(name), format), build,
                                      IsectMode::kWoop);
}

}  // namespace

Runner::Runner(const spec::HardwareConfig& config, const RunnerOptions& options)
    : config_(config),
      format_(fp::format_by_name(config.format)),
      scene_(scene_image(config, format_, options.scene)) {
  launch_.width = options.width > 0 ? options.width : config.chunk_size;
  launch_.height = options.height > 0 ? options.height : 2;
  launch_.spp = 1;
  launch_.max_depth = 0;
  tracer_ = std::make_unique<functional::Tracer>(scene_.image.bytes, scene_.layout, format_, config.stack_depth);
}

std::vector<std::uint32_t> Runner::shader_table(const Program& program, const isa::Firmware& firmware) const {
  std::vector<std::uint32_t> table;
  for (const std::string& name : program.shader_names()) {
    const auto s = firmware.symbols.find("hit_" + name);
    if (s == firmware.symbols.end() || s->second.kind != isa::Symbol::Kind::kCode) {
      throw Error(fmt::format("progen seed {}: the firmware has no code label 'hit_{}'", program.seed, name));
    }
    table.push_back(s->second.value);
  }
  return table;
}

functional::DeviceMemory Runner::memory(const Program& program, const isa::Firmware& firmware) const {
  return functional::DeviceMemory(
      scene_.image.bytes,
      device::make_launch_block(scene_.image.bytes, scene_.layout, launch_, shader_table(program, firmware)),
      firmware.data, static_cast<std::uint32_t>(launch_.width * launch_.height));
}

functional::ShaderCoreConfig Runner::core_config(const Program& program) const {
  return functional::ShaderCoreConfig::of(config_, program.watchdog());
}

functional::PixelMap Runner::pixel_map() const {
  return functional::PixelMap::of(config_, static_cast<std::uint64_t>(launch_.width) *
                                                static_cast<std::uint64_t>(launch_.height));
}

Outcome Runner::run(const Program& program, StepObserver* observer) const {
  const isa::Firmware firmware = program.firmware();
  functional::DeviceMemory memory = this->memory(program, firmware);
  functional::ShaderCore core(firmware, memory, *tracer_, format_, core_config(program));
  functional::ShaderStats stats;
  functional::StepRecord record;
  Outcome out;
  // One flush scope for the whole run: the core's fp32 fast path needs it, and setting
  // it per step costs more than the step (ShaderCore::step).
  const fp::fast32::FlushScope flush;
  const functional::PixelMap map = pixel_map();
  std::vector<functional::ShaderCore::Lane> lanes;
  for (std::uint64_t k = 0; k < map.blocks(); ++k) {
    map.lanes(k, lanes);
    functional::ShaderCore::Chunk chunk;
    core.start(chunk, lanes, stats);
    if (observer) observer->start_chunk(chunk);
    while (!chunk.done()) {
      if (observer) observer->before_step(chunk);
      core.step(chunk, stats, observer ? &record : nullptr);
      if (observer) observer->after_step(record, chunk);
    }
    for (const functional::ShaderCore::Thread& t : chunk.threads()) {
      out.most_instructions = std::max(out.most_instructions, t.retired);
    }
    // Chunks run in pixel order, so the first chunk with a fault has the first faulting
    // pixel, and no later pixel could be reported.
    if (const functional::ShaderFault* f = chunk.fault()) {
      out.fault = f->what();
      out.fault_pixel = f->pixel();
      break;
    }
  }
  out.steps = stats.chunk_issues;
  out.instructions = stats.instructions();
  return out;
}

std::string unexpected(const Program& program, const Outcome& outcome) {
  if (program.fault == FaultClass::kNone) {
    if (outcome.fault) return fmt::format("expected every thread to halt, but: {}", *outcome.fault);
    const std::uint64_t bound = program.cost().instructions;
    if (outcome.most_instructions > bound) {
      return fmt::format("a thread retired {} instructions, more than the program's bound {}",
                         outcome.most_instructions, bound);
    }
    return {};
  }
  if (!outcome.fault) return fmt::format("expected the fault {}, but every thread halted", fault_name(program.fault));
  const auto got = classify_fault_message(*outcome.fault);
  if (got != program.fault) {
    return fmt::format("expected the fault {}, but: {}", fault_name(program.fault), *outcome.fault);
  }
  if (const auto pixel = program.fault_pixel(); pixel && outcome.fault_pixel != pixel) {
    return fmt::format("expected the first faulting pixel to be {}, but: {}", *pixel, *outcome.fault);
  }
  return {};
}

}  // namespace rpu::progen
