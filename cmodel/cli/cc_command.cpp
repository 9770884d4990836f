// rpu cc: GLSL ray-tracing shaders to a firmware file (docs/shaders.md).
#include <filesystem>
#include <memory>
#include <vector>

#include <fmt/format.h>

#include "asm/firmware_file.hpp"
#include "cc/compiler.hpp"
#include "cli/chip_options.hpp"
#include "cli/commands.hpp"
#include "cli/output_paths.hpp"
#include "common/output_file.hpp"

namespace rpu::cli {

Command add_cc_command(CLI::App& app) {
  struct Options {
    std::vector<std::string> inputs;
    std::string output;
    std::string listing;
    int opt_level = 2;
    int registers = 16;
    ShaderOptions shaders;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "cc", "Compile GLSL ray-tracing shaders (.rgen, .rchit, .rmiss) into one firmware file (docs/shaders.md)");
  cmd->add_option("shaders", o->inputs,
                  "One ray-generation shader (.rgen), closest-hit shaders (.rchit: a material's `shader` names the "
                  "file's stem) and miss shaders (.rmiss: miss index i is the i-th given)")
      ->required();
  cmd->add_option("-o,--output", o->output, "Firmware file to write (.rfw)")->required();
  cmd->add_option("--listing", o->listing,
                  "Also write the generated assembly: the pc of every instruction, its source line as a .loc");
  cmd->add_option("-O", o->opt_level,
                  "-O0: SPIRV-Tools' legalisation passes only (inlining, SSA); -O2 (the default): its performance "
                  "passes too")
      ->check(CLI::IsMember({0, 2}));
  cmd->add_option("--registers", o->registers,
                  "Registers the firmware may use (16 runs on every configuration of spec/configs.toml)")
      ->check(CLI::Range(6, 64));
  add_shader_options(*cmd, o->shaders);
  return {cmd, [o] {
            std::vector<std::filesystem::path> files(o->inputs.begin(), o->inputs.end());
            std::vector<PlannedInput> inputs;
            for (const auto& f : files) inputs.push_back({"a shader", f});
            std::vector<PlannedOutput> outputs{{"-o", o->output, {".rfw"}}};
            if (!o->listing.empty()) outputs.push_back({"--listing", o->listing, {}});
            check_outputs(outputs, inputs);
            cc::CompileOptions options = o->shaders.compile_options();
            options.opt_level = o->opt_level;
            options.registers = o->registers;
            options.listing = !o->listing.empty();
            const cc::Compiled compiled = cc::compile_files(files, options);
            for (const std::string& w : compiled.warnings) fmt::print(stderr, "rpu: warning: {}\n", w);
            isa::save_firmware(compiled.firmware, o->output);
            if (!o->listing.empty()) {
              OutputFile listing(o->listing);
              listing.stream() << compiled.listing;
              listing.commit();
            }
            fmt::print(stderr, "rpu: {} shader(s): {} instructions -> {}\n", files.size(),
                       compiled.firmware.code.size(), o->output);
            return 0;
          }};
}

}  // namespace rpu::cli
