#include "cc/compiler.hpp"

#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "asm/assembler.hpp"
#include "asm/firmware_file.hpp"
#include "cc/emit.hpp"
#include "cc/frontend.hpp"
#include "cc/lower.hpp"
#include "cc/regalloc.hpp"
#include "cc/spirv_module.hpp"
#include "common/error.hpp"
#include "rpu/version.hpp"

namespace rpu::cc {

namespace fs = std::filesystem;

namespace {

// The routine behind one traceRayEXT form. Entered with r0 = (origin, t_min),
// r1 = (direction, t_max), r3.y = the new ray's nesting level and the payload in r4..;
// r2 and r3 are scratch. A hit calls the material's closest-hit shader through the
// shader table with r2 = (t, u, v, primitive) and r3.x = the material index; a miss
// jumps to the miss shader, which returns to the tracing shader itself.
std::string trace_routine(const TraceForm& form, const std::vector<std::string>& miss_labels) {
  std::string s = fmt::format("{}:\n", form.label());
  s += "        li      r3.z, DEVICE_LAUNCH_BASE\n"
       "        ld1     r3.w, [r3.z + LAUNCH_MAX_DEPTH_AT]\n"
       "        iaddi   r3.w, r3.w, 1\n"
       "        ilt     r3.w, r3.w, r3.y            ; nested deeper than max depth + 1?\n"
       "        bnz     r3.w, rpu_trace_recursion_limit\n";
  s += fmt::format("        {:<7} r2, r0, r1\n", form.any_hit ? "tracea" : "trace");
  s += "        iaddi   r3.w, r2.w, 1\n";
  const std::string miss = form.miss < 0 ? std::string() : miss_labels.at(static_cast<std::size_t>(form.miss));
  s += fmt::format("        bz      r3.w, {}\n", miss.empty() ? form.label() + "_done" : miss);
  if (!form.skip_closest) {
    s += "        ld1     r3.w, [r3.z + LAUNCH_TRIANGLES_AT]\n"
         "        imuli   r3.x, r2.w, TRIANGLE_BYTES\n"
         "        iadd    r3.w, r3.w, r3.x\n"
         "        ld1     r3.x, [r3.w + TRIANGLE_MATERIAL_AT]\n"
         "        ld1     r3.w, [r3.z + LAUNCH_MATERIALS_AT]\n"
         "        imuli   r3.z, r3.x, MATERIAL_BYTES\n"
         "        iadd    r3.w, r3.w, r3.z\n"
         "        ld1     r3.w, [r3.w + MATERIAL_SHADER_AT]\n"
         "        mfra    r3.z                        ; kept on the memory stack: the return stack\n"
         "        push    r3                          ; stays one entry deep at any nesting\n"
         "        calli   r3.w\n"
         "        pop     r3\n"
         "        mtra    r3.z\n";
  }
  if (miss.empty()) s += form.label() + "_done:\n";
  s += "        ret\n";
  return s;
}

// A stem names a code label: it must be an assembler identifier.
void check_stem(const fs::path& file) {
  const std::string stem = file.stem().string();
  bool ok = !stem.empty();
  for (const char c : stem) ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_');
  if (!ok) {
    throw Error(fmt::format("{}: the file name '{}' must be letters, digits and '_' only: it names the shader "
                            "(a material's `shader` in the scene file)",
                            file.string(), stem));
  }
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(fmt::format("{}: cannot read the shader", file.string()));
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

Compiled compile(const std::vector<ShaderSource>& sources, const CompileOptions& options) {
  if (options.registers < kRegPayload + 2 || options.registers > 64) {
    throw Error(fmt::format("--registers {}: the calling convention needs {} to 64", options.registers,
                            kRegPayload + 2));
  }
  std::vector<SpirvShader> shaders;
  std::vector<std::string> miss_labels;
  std::set<std::string> labels;
  int raygens = 0;
  for (const ShaderSource& s : sources) {
    check_stem(s.file);
    shaders.push_back(compile_glsl(s.file, s.text, options.opt_level));
    const std::string label = shader_label(shaders.back());
    if (shaders.back().stage == Stage::kRaygen) ++raygens;
    if (!labels.insert(label).second) {
      throw Error(fmt::format("{}: a second {} shader named '{}'", s.file.string(), stage_name(shaders.back().stage),
                              s.file.stem().string()));
    }
    if (shaders.back().stage == Stage::kMiss) miss_labels.push_back(label);
  }
  if (raygens != 1) {
    throw Error(fmt::format("the firmware needs exactly one ray-generation shader (.rgen); {} given", raygens));
  }
  LowerContext context;
  context.registers = options.registers;
  context.miss_shaders = static_cast<int>(miss_labels.size());
  std::string body;
  std::set<TraceForm> traces;
  int raygen_saves = 0, shader_saves = 0;
  bool thin_lens = false;
  for (const SpirvShader& shader : shaders) {
    const Module module = Module::parse(shader.words, shader.file.string());
    Lowered lowered = lower(module, shader, context);
    const Allocation allocation = allocate(lowered.function, options.registers);
    traces.insert(lowered.traces.begin(), lowered.traces.end());
    thin_lens = thin_lens || lowered.reads_aperture;
    (shader.stage == Stage::kRaygen ? raygen_saves : shader_saves) =
        std::max(shader.stage == Stage::kRaygen ? raygen_saves : shader_saves, allocation.max_save_bytes);
    body += fmt::format("\n; {} shader {} ({} registers)\n", stage_name(shader.stage), shader.file.string(),
                        allocation.registers_used);
    body += emit(lowered.function, allocation);
  }
  // Stack per thread: what ray generation keeps across its traces, then per nesting level
  // a trace routine's frame (16 bytes) and what a hit or miss shader keeps across its own
  // traces; levels run to max depth + 1 (docs/shaders.md "Recursion").
  const int per_level = 16 + shader_saves;
  std::string text = fmt::format(
      "; Generated by rpu cc from {} shader(s). Calling convention: docs/shaders.md.\n"
      ".equ FIRMWARE_RETURN_STACK_ENTRIES, 1\n"
      ".equ FIRMWARE_STACK_BYTES, {}\n"
      ".equ FIRMWARE_STACK_BYTES_PER_DEPTH, {}\n"
      "{}"
      ".text\n",
      shaders.size(), raygen_saves + 2 * per_level, per_level,
      thin_lens ? "; a shader reads the camera's aperture: the firmware models the thin lens\n"
                  ".equ FIRMWARE_THIN_LENS, 1\n"
                : "");
  // Ray generation first: pc 0 is where a listing starts reading.
  text += body;
  text += "\n; traceRayEXT, one routine per form used\n";
  for (const TraceForm& form : traces) text += trace_routine(form, miss_labels);
  text += "; a trace nested deeper than max depth + 1: stop the thread with an illegal-instruction fault\n"
          "rpu_trace_recursion_limit:\n"
          "        .insn 0\n";
  Compiled out;
  out.assembly = text;
  const fs::path name = "<rpu cc>.s";
  try {
    out.firmware = isa::assemble(name, [&](const fs::path& p) -> std::optional<std::string> {
      if (p == name) return text;
      return std::nullopt;
    });
  } catch (const Error& e) {
    throw Error(fmt::format("internal error: the compiled assembly does not assemble: {}\n{}", e.what(), text));
  }
  return out;
}

Compiled compile_files(const std::vector<fs::path>& files, const CompileOptions& options) {
  std::vector<ShaderSource> sources;
  for (const fs::path& f : files) sources.push_back({f, read_text(f)});
  return compile(sources, options);
}

isa::Firmware compile_cached(const std::vector<fs::path>& files, const CompileOptions& options) {
  // The key: every preprocessed source (so included files count), the options, this build.
  std::string keyed = fmt::format("{} {} {}\n", kCommit, options.opt_level, options.registers);
  for (const fs::path& f : files) keyed += f.filename().string() + "\n" + preprocess_glsl(f, read_text(f));
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a
  for (const unsigned char c : keyed) h = (h ^ c) * 1099511628211ull;
  const char* env = std::getenv("RPU_CACHE_DIR");
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  const char* home = std::getenv("HOME");
  const fs::path dir = env ? fs::path(env)
                       : xdg ? fs::path(xdg) / "rpu"
                       : home ? fs::path(home) / ".cache" / "rpu"
                              : fs::temp_directory_path() / "rpu-cache";
  const fs::path cached = dir / fmt::format("cc-{:016x}.rfw", h);
  std::error_code ec;
  if (fs::is_regular_file(cached, ec)) {
    try {
      return isa::load_firmware(cached);
    } catch (const Error&) {
      // a damaged cache entry is compiled again and replaced
    }
  }
  Compiled c = compile_files(files, options);
  fs::create_directories(dir, ec);
  if (!ec) {
    try {
      isa::save_firmware(c.firmware, cached);
    } catch (const Error&) {
      // an unwritable cache costs only the next compile
    }
  }
  return std::move(c.firmware);
}

}  // namespace rpu::cc
