// rpu asm / rpu disasm: shader assembly to a firmware file (.rfw) and back to text.
#include <fstream>
#include <memory>

#include <fmt/format.h>

#include "asm/assembler.hpp"
#include "asm/firmware_file.hpp"
#include "asm/firmware_text.hpp"
#include "cli/commands.hpp"
#include "common/error.hpp"

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
            const isa::Assembly assembly = isa::assemble_with_listing(o->input, isa::read_source_file);
            isa::save_firmware(assembly.firmware, o->output);
            if (!o->listing.empty()) {
              std::ofstream out(o->listing, std::ios::binary | std::ios::trunc);
              out << isa::format_listing(assembly);
              out.close();
              if (!out) throw Error(fmt::format("{}: cannot write the listing", o->listing));
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
  cmd->add_option("file", *input, "Firmware file (.rfw); any other name is assembled as a source first")->required();
  return {cmd, [input] {
            const std::filesystem::path path(*input);
            const isa::Firmware fw = path.extension() == ".rfw" ? isa::load_firmware(path) : isa::assemble(path);
            fmt::print("{}", isa::firmware_to_text(fw));
            return 0;
          }};
}

}  // namespace rpu::cli
