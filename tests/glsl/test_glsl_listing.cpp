// The listing of `rpu cc --listing` assembles (rpu asm) to the firmware the compiler
// encoded, line table and all: the listing prints, and link() encodes, the same machine
// instructions
// (docs/shaders.md "The pipeline"). Every program of tests/glsl/programs that compiles,
// and the shader library, with and without spills.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "asm/assembler.hpp"
#include "cc/compiler.hpp"
#include "common/error.hpp"

namespace rpu {
namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// False if the sources do not compile for these options (a refusal the programs test).
bool listing_assembles_to_the_firmware(const std::vector<cc::ShaderSource>& sources, int opt_level, int registers) {
  cc::CompileOptions options;
  options.opt_level = opt_level;
  options.registers = registers;
  options.listing = true;
  cc::Compiled compiled;
  try {
    compiled = cc::compile(sources, options);
  } catch (const Error&) {
    return false;
  }
  SCOPED_TRACE(compiled.listing);
  const fs::path name = "listing.s";
  const isa::Firmware again =
      isa::assemble(name, [&](const fs::path& p) { return p == name ? std::optional(compiled.listing) : std::nullopt; });
  EXPECT_EQ(again.code, compiled.firmware.code);
  EXPECT_EQ(again.data, compiled.firmware.data);
  EXPECT_TRUE(again.symbols == compiled.firmware.symbols) << "the symbols differ";
  EXPECT_TRUE(again.lines == compiled.firmware.lines) << "the line tables differ";
  // Most instructions come from a line of the shaders (a check that the lines survive
  // the optimiser and the back end; the trace routines and the ABI's moves have none).
  std::size_t with_line = 0;
  for (std::uint32_t pc = 0; pc < compiled.firmware.code.size(); ++pc) with_line += compiled.firmware.lines.where(pc) ? 1 : 0;
  EXPECT_GT(with_line, 0u);
  return true;
}

TEST(GlslListing, AssemblesToTheFirmwareOfEveryProgram) {
  const std::string empty_hit = "#version 460\n#extension GL_EXT_ray_tracing : require\nvoid main() {}\n";
  int compiled = 0;
  for (const auto& dir : fs::directory_iterator(RPU_GLSL_PROGRAM_DIR)) {
    std::vector<cc::ShaderSource> sources;
    for (const auto& entry : fs::directory_iterator(dir.path())) {
      const std::string ext = entry.path().extension().string();
      if (ext == ".rgen" || ext == ".rchit" || ext == ".rmiss") sources.push_back({entry.path(), read(entry.path())});
    }
    std::sort(sources.begin(), sources.end(), [](const auto& a, const auto& b) { return a.file < b.file; });
    if (!fs::exists(dir.path() / "whitted.rchit")) sources.push_back({dir.path() / "whitted.rchit", empty_hit});
    for (const int level : {0, 2}) {
      for (const int registers : {16, 6}) {
        SCOPED_TRACE(testing::Message() << dir.path() << " -O" << level << " --registers " << registers);
        compiled += listing_assembles_to_the_firmware(sources, level, registers);
      }
    }
  }
  EXPECT_GT(compiled, 20) << "too few programs compiled: the test tests little";
}

TEST(GlslListing, AssemblesToTheFirmwareOfTheLibrary) {
  const fs::path dir = RPU_GLSL_LIBRARY_DIR;
  for (const char* raygen : {"whitted.rgen", "thin_lens.rgen"}) {
    std::vector<cc::ShaderSource> sources{{dir / raygen, read(dir / raygen)}};
    for (const char* hit : {"whitted", "phong", "mirror", "glossy", "checker", "glass"}) {
      const fs::path file = dir / (std::string(hit) + ".rchit");
      sources.push_back({file, read(file)});
    }
    sources.push_back({dir / "background.rmiss", read(dir / "background.rmiss")});
    for (const int registers : {16, 12}) {
      SCOPED_TRACE(testing::Message() << raygen << " --registers " << registers);
      EXPECT_TRUE(listing_assembles_to_the_firmware(sources, 2, registers)) << "the library does not compile";
    }
  }
}

}  // namespace
}  // namespace rpu
