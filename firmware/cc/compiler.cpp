#include "cc/compiler.hpp"

#include <cstdlib>
#include <algorithm>
#include <map>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "asm/firmware_file.hpp"
#include "cc/abi.hpp"
#include "cc/emit.hpp"
#include "cc/frontend.hpp"
#include "cc/link.hpp"
#include "cc/listing.hpp"
#include "cc/lower.hpp"
#include "cc/regalloc.hpp"
#include "cc/spirv_module.hpp"
#include "common/error.hpp"
#include "common/input_file.hpp"
#include "common/output_file.hpp"
#include "rpu/version.hpp"

namespace rpu::cc {

namespace fs = std::filesystem;

namespace {

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
  return read_input_file(file, "the shader");
}

// Each trace's payload is what every shader it may run takes: each closest-hit shader
// (unless the trace skips them) and the miss shader it names. The calling convention
// passes a payload's leaves in registers, so a shader that reads others would read
// another member's bits.
void check_payloads(const std::vector<std::pair<TraceForm, PayloadType>>& traced,
                    const std::vector<std::pair<const SpirvShader*, PayloadType>>& incoming,
                    const std::vector<SpirvShader>& shaders) {
  for (const auto& [form, payload] : traced) {
    for (const auto& [shader, taken] : incoming) {
      int miss = 0;
      for (const SpirvShader& s : shaders) {
        if (&s == shader) break;
        miss += s.stage == Stage::kMiss ? 1 : 0;
      }
      const bool runs = shader->stage == Stage::kMiss ? miss == form.miss
                                                      : shader->stage == Stage::kClosestHit && !form.skip_closest;
      if (runs && !(taken == payload)) {
        throw Error(fmt::format("{} is {} ({}), but {} is {} ({}): a trace's payload and the rayPayloadInEXT of each "
                                "shader it may run (every closest-hit shader unless the trace skips them, and the miss "
                                "shader it names) must hold the same members in the same order",
                                payload.where, payload.glsl, payload.leaves, taken.where, taken.glsl, taken.leaves));
      }
    }
  }
}

// A value given for an id no shader declares is an error; a constant given no value
// keeps its default, which the warnings say (a published shader's default may be a
// placeholder, such as a recursion depth of 0, that its host always overrides).
std::vector<std::string> check_spec_constants(const std::vector<SpirvShader>& shaders, const CompileOptions& options) {
  std::map<std::uint32_t, std::vector<std::string>> declared;  // id -> "NAME (type) in file"
  std::vector<std::string> warnings;
  for (const SpirvShader& shader : shaders) {
    for (const SpecConstant& s : shader.spec_constants) {
      declared[s.id].push_back(fmt::format("{} ({}) in {}", s.name, s.type, shader.file.string()));
      if (!s.given) {
        warnings.push_back(fmt::format("{}: specialization constant {} (constant_id {}) keeps its default {}; give "
                                       "--spec-constant {}=VALUE to set it",
                                       shader.file.string(), s.name, s.id, s.value, s.id));
      }
    }
  }
  for (const auto& [id, value] : options.spec_constants) {
    if (declared.contains(id)) continue;
    std::vector<std::string> all;
    for (const auto& [other, names] : declared) {
      for (const std::string& n : names) all.push_back(fmt::format("{} {}", other, n));
    }
    throw Error(fmt::format("--spec-constant {}={}: no shader declares constant_id {} ({})", id, value, id,
                            all.empty() ? std::string("they declare none")
                                        : fmt::format("they declare {}", fmt::join(all, ", "))));
  }
  return warnings;
}

}  // namespace

Compiled compile(const std::vector<ShaderSource>& sources, const CompileOptions& options) {
  if (options.registers < kRegPayload + 2 || options.registers > kMaxRegisters) {
    throw Error(fmt::format("--registers {}: the calling convention needs {} to {}", options.registers,
                            kRegPayload + 2, kMaxRegisters));
  }
  std::vector<SpirvShader> shaders;
  std::vector<std::string> miss_labels;
  std::set<std::string> labels;
  int raygens = 0;
  // Every shader is compiled as far as it goes, so that one compile reports the errors of
  // all of them (each shader's lowering reports all of its own).
  std::vector<std::string> errors;
  const auto attempt = [&](const auto& step) {
    try {
      step();
    } catch (const Error& e) {
      errors.emplace_back(e.what());
    }
  };
  for (const ShaderSource& s : sources) {
    check_stem(s.file);
    SpirvShader named;
    named.file = s.file;
    named.stage = stage_of(s.file);
    const std::string label = shader_label(named);
    if (named.stage == Stage::kRaygen) ++raygens;
    if (!labels.insert(label).second) {
      throw Error(fmt::format("{}: a second {} shader named '{}'", s.file.string(), stage_name(named.stage),
                              s.file.stem().string()));
    }
    if (named.stage == Stage::kMiss) miss_labels.push_back(label);
    attempt([&] { shaders.push_back(compile_glsl(s.file, s.text, options)); });
  }
  if (raygens != 1) {
    throw Error(fmt::format("the firmware needs exactly one ray-generation shader (.rgen); {} given", raygens));
  }
  Compiled out;
  if (errors.empty()) out.warnings = check_spec_constants(shaders, options);
  LowerContext context;
  context.registers = options.registers;
  context.miss_shaders = static_cast<int>(miss_labels.size());
  Program program;
  program.title = fmt::format("Generated by rpu cc from {} shader(s). Calling convention: docs/shaders.md.",
                              shaders.size());
  std::set<TraceForm> traces;
  int raygen_saves = 0, shader_saves = 0;
  bool thin_lens = false;
  std::vector<std::pair<TraceForm, PayloadType>> traced;
  std::vector<std::pair<const SpirvShader*, PayloadType>> incoming;
  for (const SpirvShader& shader : shaders) {
    attempt([&] {
      const Module module = Module::parse(shader.words, shader.file.string());
      Lowered lowered = lower(module, shader, context);
      traced.insert(traced.end(), lowered.traced.begin(), lowered.traced.end());
      if (lowered.incoming) incoming.emplace_back(&shader, *lowered.incoming);
      const Allocation allocation = allocate(lowered.function, options.registers);
      traces.insert(lowered.traces.begin(), lowered.traces.end());
      thin_lens = thin_lens || lowered.reads_aperture;
      (shader.stage == Stage::kRaygen ? raygen_saves : shader_saves) =
          std::max(shader.stage == Stage::kRaygen ? raygen_saves : shader_saves, allocation.max_save_bytes);
      program.sections.push_back({fmt::format("{} shader {} ({} registers)", stage_name(shader.stage),
                                              shader.file.string(), allocation.registers_used),
                                  emit(lowered.function, allocation)});
    });
  }
  if (!errors.empty()) throw Error(fmt::format("{}", fmt::join(errors, "\n")));
  check_payloads(traced, incoming, shaders);
  program.declarations = declarations(raygen_saves, shader_saves, thin_lens);
  Section& routines = program.sections.emplace_back(Section{"traceRayEXT, one routine per form used", {}});
  const auto append = [&](std::vector<MachineItem> code) {
    routines.items.insert(routines.items.end(), std::make_move_iterator(code.begin()),
                          std::make_move_iterator(code.end()));
  };
  for (const TraceForm& form : traces) {
    const MFunction routine = trace_routine(form, miss_labels);
    append(emit(routine, pinned(routine)));
  }
  append(recursion_limit());
  out.firmware = link(program);
  if (options.listing) out.listing = listing(program);
  return out;
}

Compiled compile_files(const std::vector<fs::path>& files, const CompileOptions& options) {
  std::vector<ShaderSource> sources;
  for (const fs::path& f : files) sources.push_back({f, read_text(f)});
  return compile(sources, options);
}

Compiled compile_cached(const std::vector<fs::path>& files, const CompileOptions& options) {
  // The key: every preprocessed source (so included files and defines count) under its
  // path as given (the line table names it), the options, this build.
  std::string keyed = fmt::format("{} {} {}\n", kCommit, options.opt_level, options.registers);
  for (const auto& [id, value] : options.spec_constants) keyed += fmt::format("spec {}={}\n", id, value);
  for (const fs::path& f : files) keyed += f.string() + "\n" + preprocess_glsl(f, read_text(f), options);
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a
  for (const unsigned char c : keyed) h = (h ^ c) * 1099511628211ull;
  const char* env = std::getenv("RPU_CACHE_DIR");
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  const char* home = std::getenv("HOME");
  const fs::path dir = env ? fs::path(env)
                       : xdg ? fs::path(xdg) / "rpu"
                       : home ? fs::path(home) / ".cache" / "rpu"
                              : fs::temp_directory_path() / "rpu-cache";
  // An entry is its whole key, the compile's warnings, then the firmware file's bytes: it
  // is used only when the key it holds is this one, so neither a hash collision nor a
  // file put in its place (a damaged entry, another firmware) is ever run instead of the
  // compile.
  const fs::path cached = dir / fmt::format("cc-{:016x}.entry", h);
  const std::string head = fmt::format("rpu compile cache\n{}\n", keyed.size());
  std::error_code ec;
  if (fs::is_regular_file(cached, ec)) {
    try {
      const std::string entry = read_input_file(cached, "the compile-cache entry");
      if (entry.size() > head.size() + keyed.size() && entry.compare(0, head.size(), head) == 0 &&
          entry.compare(head.size(), keyed.size(), keyed) == 0) {
        std::size_t at = head.size() + keyed.size();
        Compiled c;
        for (std::size_t end; (end = entry.find('\n', at)) != std::string::npos && end > at; at = end + 1) {
          c.warnings.push_back(entry.substr(at, end - at));
        }
        if (at < entry.size() && entry[at] == '\n') {
          const auto* bytes = reinterpret_cast<const std::uint8_t*>(entry.data()) + at + 1;
          c.firmware = isa::firmware_from_bytes({bytes, entry.size() - at - 1}, cached.string());
          return c;
        }
      }
    } catch (const Error&) {
      // a damaged entry is compiled again and replaced
    }
  }
  Compiled c = compile_files(files, options);
  c.listing.clear();
  fs::create_directories(dir, ec);
  if (!ec) {
    try {
      const std::vector<std::uint8_t> bytes = isa::firmware_to_bytes(c.firmware);
      OutputFile out(cached);
      out.stream() << head << keyed;
      for (const std::string& w : c.warnings) out.stream() << w << '\n';  // a warning is one line
      out.stream() << '\n';
      out.stream().write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
      out.commit();
    } catch (const Error&) {
      // an unwritable cache costs only the next compile
    }
  }
  return c;
}

}  // namespace rpu::cc
