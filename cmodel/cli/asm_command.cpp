// rpu asm / rpu disasm: shader assembly to a firmware file (.rfw) and back to text.
#include <filesystem>
#include <memory>
#include <vector>

#include <fmt/format.h>

#include "asm/assembler.hpp"
#include "asm/firmware_file.hpp"
#include "asm/firmware_text.hpp"
#include "cli/commands.hpp"
#include "cli/output_paths.hpp"
#include "common/output_file.hpp"

namespace rpu::cli {

Command add_asm_command(CLI::App& app) {
  struct Options {
    std::string input;
    std::string output;
    std::string listing;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("asm", "Assemble a shader source (docs/assembler.md) into a firmware file");
  cmd->add_option("source", o->input, "Assembly source file (.s)")->required();
  cmd->add_option("-o,--output", o->output, "Firmware file to write (.rfw)")->required();
  cmd->add_option("--listing", o->listing, "Also write a listing: pc, instruction word, source line");
  return {cmd, [o] {
            // Every file the assembler reads (the source and its .includes): none may be
            // an output.
            std::vector<PlannedInput> inputs;
            const auto record = [&inputs](const std::filesystem::path& file) {
              inputs.push_back({inputs.empty() ? "the assembly source" : "the included file", file});
              return isa::read_source_file(file);
            };
            const isa::Assembly assembly = isa::assemble_with_listing(o->input, record);
            std::vector<PlannedOutput> outputs{{"-o", o->output, {".rfw"}}};
            if (!o->listing.empty()) outputs.push_back({"--listing", o->listing, {}});
            check_outputs(outputs, inputs);
            isa::save_firmware(assembly.firmware, o->output);
            if (!o->listing.empty()) {
              OutputFile listing(o->listing);
              listing.stream() << isa::format_listing(assembly);
              listing.commit();
            }
            fmt::print(stderr, "rpu: {}: {} instructions, {} data bytes, {} symbols -> {}\n", o->input,
                       assembly.firmware.code.size(), assembly.firmware.data.size(), assembly.firmware.symbols.size(),
                       o->output);
            return 0;
          }};
}

Command add_disasm_command(CLI::App& app) {
  auto input = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand(
      "disasm", "Print a firmware file (.rfw), or an assembly source after assembling it, as assembly text");
  cmd->add_option("file", *input, "Firmware file (starts with the magic \"RFW1\"); any other file is assembled as a "
                                  "source first")
      ->required();
  return {cmd, [input] {
            const isa::Firmware fw = isa::load_firmware_or_assemble(*input);
            fmt::print("{}", isa::firmware_to_text(fw));
            return 0;
          }};
}

}  // namespace rpu::cli
