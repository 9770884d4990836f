#include "cc/frontend.hpp"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <clocale>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <unordered_map>
#include <vector>

#include <fmt/format.h>
#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>
#include <spirv-tools/libspirv.hpp>
#include <spirv-tools/optimizer.hpp>

#include "cc/abi.hpp"
#include "cc/glsl_library.hpp"
#include "cc/spirv_module.hpp"
#include "common/error.hpp"

namespace rpu::cc {

namespace fs = std::filesystem;

Stage stage_of(const fs::path& file) {
  const std::string ext = file.extension().string();
  if (ext == ".rgen") return Stage::kRaygen;
  if (ext == ".rchit") return Stage::kClosestHit;
  if (ext == ".rmiss") return Stage::kMiss;
  if (ext == ".rahit") return Stage::kAnyHit;
  throw Error(fmt::format("{}: unknown shader stage '{}', expected .rgen (ray generation), .rchit (closest hit), "
                          ".rmiss (miss) or .rahit (any hit)",
                          file.string(), ext));
}

const char* stage_name(Stage stage) {
  switch (stage) {
    case Stage::kRaygen: return "ray generation";
    case Stage::kClosestHit: return "closest hit";
    case Stage::kMiss: return "miss";
    case Stage::kAnyHit: return "any hit";
  }
  return "?";
}

const std::string* library_header(const std::string& name) {
  static const std::map<std::string, std::string> headers = [] {
    std::map<std::string, std::string> h;
    for (const auto& [n, text] : kGlslLibrary) h.emplace(std::string(n), std::string(text));
    return h;
  }();
  const auto it = headers.find(name);
  return it == headers.end() ? nullptr : &it->second;
}

namespace {

// #include "x": beside the including file on disk, then in the include directories,
// then the built-in library.
class Includer : public glslang::TShader::Includer {
 public:
  explicit Includer(const std::vector<fs::path>& dirs) : dirs_(dirs) {}

  IncludeResult* includeLocal(const char* requested, const char* requesting, size_t) override {
    auto text = std::make_unique<std::string>();
    std::string name;
    std::error_code ec;
    fs::path found = fs::path(requesting).parent_path() / requested;
    for (auto dir = dirs_.begin(); !fs::is_regular_file(found, ec) && dir != dirs_.end(); ++dir) {
      found = *dir / requested;
    }
    if (fs::is_regular_file(found, ec)) {
      std::ifstream in(found, std::ios::binary);
      std::ostringstream s;
      s << in.rdbuf();
      name = found.lexically_normal().string();
      *text = s.str();
    } else if (const std::string* lib = library_header(fs::path(requested).filename().string());
               lib != nullptr && fs::path(requested).filename() == fs::path(requested)) {
      name = requested;
      *text = *lib;
    } else {
      return nullptr;  // glslang reports "cannot find or open include file"
    }
    std::string* kept = text.release();
    return new IncludeResult(name, kept->data(), kept->size(), kept);
  }
  IncludeResult* includeSystem(const char* requested, const char* requesting, size_t depth) override {
    return includeLocal(requested, requesting, depth);
  }
  void releaseInclude(IncludeResult* r) override {
    if (r == nullptr) return;
    delete static_cast<std::string*>(r->userData);
    delete r;
  }

 private:
  const std::vector<fs::path>& dirs_;
};

bool is_identifier(std::string_view name) {
  const auto word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  return !name.empty() && !std::isdigit(static_cast<unsigned char>(name[0])) && std::all_of(name.begin(), name.end(), word);
}

// The preamble of every shader: the extensions rpu cc turns on, then the -D defines.
std::string preamble(const FrontEndOptions& options) {
  std::string text =
      "#extension GL_GOOGLE_include_directive : require\n#extension GL_GOOGLE_cpp_style_line_directive : require\n";
  for (const std::string& d : options.defines) {
    const auto eq = d.find('=');
    text += fmt::format("#define {} {}\n", d.substr(0, eq), eq == std::string::npos ? "1" : d.substr(eq + 1));
  }
  return text;
}

EShLanguage language_of(Stage stage) {
  switch (stage) {
    case Stage::kRaygen: return EShLangRayGen;
    case Stage::kClosestHit: return EShLangClosestHit;
    case Stage::kMiss: return EShLangMiss;
    case Stage::kAnyHit: return EShLangAnyHit;
  }
  return EShLangRayGen;
}

constexpr auto kMessages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules);

// glslang's process-wide tables, set up once and kept (the library is not reentrant
// before InitializeProcess).
void initialise() {
  static std::once_flag once;
  std::call_once(once, [] { glslang::InitializeProcess(); });
}

// One TShader set up for a file: Vulkan 1.2, SPIR-V 1.5, includes on.
struct Shader {
  Shader(const fs::path& file, const std::string& source, Stage stage, const FrontEndOptions& options)
      : name(file.string()), text(source), head(preamble(options)), shader(language_of(stage)) {
    initialise();
    // TShader keeps these pointers until it parses: members, not locals.
    text_ptr = text.c_str();
    name_ptr = name.c_str();
    text_length = static_cast<int>(text.size());
    shader.setStringsWithLengthsAndNames(&text_ptr, &text_length, &name_ptr, 1);
    shader.setPreamble(head.c_str());
    shader.setEnvInput(glslang::EShSourceGlsl, language_of(stage), glslang::EShClientVulkan, 100);
    shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_2);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_5);
    shader.setEntryPoint("main");
  }
  // glslang's log, without its trailing blank lines; each message names file:line.
  std::string log() {
    std::string message = shader.getInfoLog();
    while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
    return message.empty() ? fmt::format("{}: glslang failed without a message", name) : message;
  }
  std::string name, text, head;  // head: the preamble
  const char* text_ptr = nullptr;
  const char* name_ptr = nullptr;
  int text_length = 0;
  glslang::TShader shader;
};

// The blocks a block's terminator may go to (a condition that is a constant, as this
// compile sees it, goes one way).
std::vector<Id> successors(const Module& m, const Block& b) {
  const Instruction& t = b.body.back();
  switch (t.op) {
    case spv::Op::OpBranch: return {t.operands[0]};
    case spv::Op::OpBranchConditional: {
      const auto c = m.constants.find(t.operands[0]);
      if (c != m.constants.end() && !c->second.composite) return {c->second.bits ? t.operands[1] : t.operands[2]};
      return {t.operands[1], t.operands[2]};
    }
    case spv::Op::OpSwitch: {
      std::vector<Id> out = {t.operands[1]};
      for (std::size_t k = 3; k < t.operands.size(); k += 2) out.push_back(t.operands[k]);
      return out;
    }
    default: return {};
  }
}

// The scalar components of a value of type `t` (saturating: a type may be enormous).
std::uint64_t components(const Module& m, Id t) {
  constexpr std::uint64_t kMany = std::uint64_t{1} << 40;
  const Type& type = m.type(t);
  switch (type.op) {
    case spv::Op::OpTypeVector: return type.count;
    case spv::Op::OpTypeMatrix:
    case spv::Op::OpTypeArray: return std::min(kMany, type.count * components(m, type.element));
    case spv::Op::OpTypeStruct: {
      std::uint64_t sum = 0;
      for (const Id member : type.members) sum = std::min(kMany, sum + components(m, member));
      return sum;
    }
    default: return 1;
  }
}

// The back end keeps every local variable in registers (kMaxRegisters of kLanes at most,
// spilled whole); a larger local array cannot be kept, and SPIRV-Tools takes minutes and
// gigabytes on one before that shows (a loop over 4096 elements, unrolled). Refused at
// its line, before the optimiser runs.
void refuse_huge_locals(const Module& m, const fs::path& file) {
  constexpr std::uint64_t kMaxComponents = std::uint64_t{kMaxRegisters} * kLanes;
  for (const Function& f : m.functions) {
    for (const Block& b : f.blocks) {
      for (const Instruction& i : b.body) {
        if (i.op != spv::Op::OpVariable || i.operands.empty() ||
            static_cast<spv::StorageClass>(i.operands[0]) != spv::StorageClass::Function) {
          continue;
        }
        const std::uint64_t n = components(m, m.type(i.type).element);
        if (n <= kMaxComponents) continue;
        // Declarations carry no line: name the first line that uses the variable.
        SourceLocation where = i.where;
        for (const Block& c : f.blocks) {
          for (const Instruction& use : c.body) {
            const bool uses = std::find(use.operands.begin(), use.operands.end(), i.result) != use.operands.end();
            if (where.line == 0 && uses && use.where.line > 0) where = use.where;
          }
        }
        const auto name = m.names.find(i.result);
        throw Error(fmt::format("{}:{}: the local variable '{}' has {} components, more than the {} of the largest "
                                "register file ({} registers of {} lanes) that the RPU back end keeps locals in",
                                where.file.empty() ? file.string() : where.file, where.line,
                                name == m.names.end() ? "?" : name->second, n, kMaxComponents, kMaxRegisters, kLanes));
      }
    }
  }
}

// A loop that no path leaves (no break past its merge, no return, terminate or kill
// inside it) runs until the watchdog stops its thread. SPIRV-Tools' dead-code
// elimination removes one without side effects, and the shader would end instead of
// running away: refused at its line, before the optimiser runs.
void refuse_endless_loops(const Module& m, const fs::path& file) {
  for (const Function& f : m.functions) {
    std::unordered_map<Id, const Block*> blocks;
    for (const Block& b : f.blocks) blocks[b.label] = &b;
    for (const Block& header : f.blocks) {
      const Instruction* merge = nullptr;
      for (const Instruction& i : header.body) {
        if (i.op == spv::Op::OpLoopMerge) merge = &i;
      }
      if (merge == nullptr) continue;
      // Every block reached from the header without passing its merge; any path out
      // of the function or into the merge leaves the loop.
      std::set<Id> seen = {header.label};
      std::vector<const Block*> work = {&header};
      bool leaves = false;
      while (!work.empty() && !leaves) {
        const Block* b = work.back();
        work.pop_back();
        const spv::Op last = b->body.empty() ? spv::Op::OpNop : b->body.back().op;
        leaves = last == spv::Op::OpReturn || last == spv::Op::OpReturnValue || last == spv::Op::OpKill ||
                 last == spv::Op::OpTerminateRayKHR || last == spv::Op::OpIgnoreIntersectionKHR;
        for (const Id next : b->body.empty() ? std::vector<Id>{} : successors(m, *b)) {
          if (next == merge->operands[0]) leaves = true;
          if (seen.insert(next).second && blocks.count(next)) work.push_back(blocks.at(next));
        }
      }
      if (!leaves) {
        throw Error(fmt::format("{}:{}: this loop never ends: no break, return or terminate leaves it, so its thread "
                                "would run until the watchdog stops it (a runaway shader)",
                                merge->where.file.empty() ? file.string() : merge->where.file, merge->where.line));
      }
    }
  }
}

// The type of a scalar specialization constant, as GLSL names it.
std::string spec_type(const Module& m, Id type) {
  const Type& t = m.type(type);
  if (t.op == spv::Op::OpTypeBool) return "bool";
  if (t.op == spv::Op::OpTypeFloat && t.count == 32) return "float";
  if (t.op == spv::Op::OpTypeInt && t.count == 32) return t.is_signed ? "int" : "uint";
  return "";
}

std::string spec_text(const std::string& type, std::uint32_t bits) {
  if (type == "bool") return bits ? "true" : "false";
  if (type == "int") return fmt::format("{}", static_cast<std::int32_t>(bits));
  if (type == "uint") return fmt::format("{}u", bits);
  return fmt::format("{}", std::bit_cast<float>(bits));
}

// The bits of `text` as a constant of `type`, or nullopt if it is not one.
std::optional<std::uint32_t> spec_bits(const std::string& type, std::string text) {
  if (type == "bool") {
    if (text == "true" || text == "false") return text == "true" ? 1u : 0u;
    return std::nullopt;
  }
  if (type == "float") {
    if (!text.empty() && (text.back() == 'f' || text.back() == 'F')) text.pop_back();
    if (text.empty() || std::isspace(static_cast<unsigned char>(text[0]))) return std::nullopt;
    // strtof reads the C locale's decimal point, which is the one rpu runs in.
    char* end = nullptr;
    errno = 0;
    const float f = std::strtof(text.c_str(), &end);
    if (end != text.c_str() + text.size() || (errno == ERANGE && std::isinf(f))) return std::nullopt;
    return std::bit_cast<std::uint32_t>(f);
  }
  if (type == "uint" && !text.empty() && (text.back() == 'u' || text.back() == 'U')) text.pop_back();
  const bool negative = type == "int" && !text.empty() && text[0] == '-';
  std::string_view digits(text);
  if (negative) digits.remove_prefix(1);
  int base = 10;
  if (digits.size() > 2 && digits[0] == '0' && (digits[1] == 'x' || digits[1] == 'X')) {
    digits.remove_prefix(2);
    base = 16;
  }
  std::uint64_t v = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), v, base);
  if (digits.empty() || error != std::errc() || end != digits.data() + digits.size()) return std::nullopt;
  if (type == "uint") return v <= UINT32_MAX ? std::optional(static_cast<std::uint32_t>(v)) : std::nullopt;
  if (v > (negative ? 0x80000000ull : 0x7fffffffull)) return std::nullopt;
  return static_cast<std::uint32_t>(negative ? 0 - v : v);
}

const char* spec_range(const std::string& type) {
  if (type == "bool") return "true or false";
  if (type == "int") return "an integer from -2147483648 to 2147483647";
  if (type == "uint") return "an integer from 0 to 4294967295";
  return "a float such as 0.5 or 1e-3";
}

// The shader's specialization constants, given the values `options` holds for their
// ids; sets them in `words` (SPIRV-Tools' set-spec-constant-default-value pass), then
// freezes every one into a plain constant and folds what is made of them, so that the
// checks and the optimiser below see the values the firmware runs with.
std::vector<SpecConstant> specialise(std::vector<std::uint32_t>& words, const fs::path& file,
                                     const FrontEndOptions& options) {
  const Module m = Module::parse(words, file.string());
  std::vector<SpecConstant> out;
  std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> given;
  for (const auto& [id, d] : m.decorations) {
    const auto c = m.constants.find(id);
    if (!d.spec_id || c == m.constants.end() || !c->second.spec) continue;
    SpecConstant s;
    s.id = *d.spec_id;
    const auto name = m.names.find(id);
    s.name = name == m.names.end() ? fmt::format("constant_id {}", s.id) : name->second;
    s.type = spec_type(m, c->second.type);
    std::uint32_t bits = c->second.bits;
    if (const auto v = options.spec_constants.find(s.id); v != options.spec_constants.end()) {
      const std::optional<std::uint32_t> parsed = s.type.empty() ? std::nullopt : spec_bits(s.type, v->second);
      if (!parsed) {
        throw Error(fmt::format("{}: --spec-constant {}={}: {} (constant_id {}) is {}; expected {}", file.string(),
                                s.id, v->second, s.name, s.id, s.type.empty() ? "not a 32-bit scalar" : "a " + s.type,
                                s.type.empty() ? "a bool, int, uint or float constant" : spec_range(s.type)));
      }
      bits = *parsed;
      given[s.id] = {bits};
      s.given = true;
    }
    s.value = spec_text(s.type, bits);
    out.push_back(std::move(s));
  }
  std::sort(out.begin(), out.end(), [](const SpecConstant& a, const SpecConstant& b) { return a.id < b.id; });
  spvtools::Optimizer optimizer(SPV_ENV_VULKAN_1_2);
  if (!given.empty()) optimizer.RegisterPass(spvtools::CreateSetSpecConstantDefaultValuePass(given));
  optimizer.RegisterPass(spvtools::CreateFreezeSpecConstantValuePass());
  // What glslang made of the constants (OpSpecConstantOp: a conversion, a comparison)
  // becomes a plain constant too.
  optimizer.RegisterPass(spvtools::CreateFoldSpecConstantOpAndCompositePass());
  std::vector<std::uint32_t> frozen;
  if (!optimizer.Run(words.data(), words.size(), &frozen)) {
    throw Error(fmt::format("{}: SPIRV-Tools could not set the specialization constants", file.string()));
  }
  words = std::move(frozen);
  return out;
}

}  // namespace

void check_define(const std::string& define) {
  const std::string name = define.substr(0, define.find('='));
  if (!is_identifier(name)) {
    throw Error(fmt::format("-D {}: '{}' is not a macro name, expected -D NAME or -D NAME=VALUE", define, name));
  }
  if (define.find_first_of("\n\r") != std::string::npos) {
    throw Error(fmt::format("-D {}: the value holds a line break, expected one line", name));
  }
}

std::pair<std::uint32_t, std::string> parse_spec_constant(const std::string& assignment) {
  const auto eq = assignment.find('=');
  std::uint32_t id = 0;
  const char* first = assignment.data();
  const char* last = assignment.data() + (eq == std::string::npos ? 0 : eq);
  const auto [end, error] = std::from_chars(first, last, id);
  if (eq == std::string::npos || eq == 0 || error != std::errc() || end != last || eq + 1 == assignment.size()) {
    throw Error(fmt::format("--spec-constant {}: expected ID=VALUE, the constant_id a number (0 to 4294967295) and "
                            "a value",
                            assignment));
  }
  return {id, assignment.substr(eq + 1)};
}

std::string preprocess_glsl(const fs::path& file, const std::string& source, const FrontEndOptions& options) {
  Shader s(file, source, stage_of(file), options);
  Includer includer(options.include_dirs);
  std::string out;
  if (!s.shader.preprocess(GetDefaultResources(), 460, ENoProfile, false, false, kMessages, &out, includer)) {
    throw Error(s.log());
  }
  return out;
}

SpirvShader compile_glsl(const fs::path& file, const std::string& source, const FrontEndOptions& options) {
  SpirvShader out;
  out.file = file;
  out.stage = stage_of(file);
  Shader s(file, source, out.stage, options);
  Includer includer(options.include_dirs);
  if (!s.shader.parse(GetDefaultResources(), 460, false, kMessages, includer)) throw Error(s.log());
  glslang::TProgram program;
  program.addShader(&s.shader);
  if (!program.link(kMessages)) {
    std::string message = program.getInfoLog();
    while (!message.empty() && message.back() == '\n') message.pop_back();
    throw Error(fmt::format("{}: {}", file.string(), message));
  }
  glslang::SpvOptions spv_options;
  spv_options.generateDebugInfo = true;  // OpLine: the back end's messages name the source line
  spv_options.disableOptimizer = true;   // SPIRV-Tools runs below, with our choice of passes
  spv::SpvBuildLogger logger;
  std::vector<std::uint32_t> words;
  glslang::GlslangToSpv(*program.getIntermediate(language_of(out.stage)), words, &logger, &spv_options);
  out.spec_constants = specialise(words, file, options);
  {
    const Module unoptimised = Module::parse(words, file.string());
    refuse_huge_locals(unoptimised, file);
    refuse_endless_loops(unoptimised, file);
  }


  std::string messages;
  const auto consumer = [&](spv_message_level_t level, const char*, const spv_position_t& at, const char* text) {
    if (level <= SPV_MSG_ERROR) messages += fmt::format("{}: SPIR-V word {}: {}\n", file.string(), at.index, text);
  };
  spvtools::Optimizer optimizer(SPV_ENV_VULKAN_1_2);
  optimizer.SetMessageConsumer(consumer);
  optimizer.RegisterLegalizationPasses();
  if (options.opt_level >= 2) optimizer.RegisterPerformancePasses();
  std::vector<std::uint32_t> optimised;
  if (!optimizer.Run(words.data(), words.size(), &optimised)) {
    throw Error(fmt::format("{}: SPIRV-Tools' optimiser failed:\n{}", file.string(), messages));
  }
  spvtools::SpirvTools tools(SPV_ENV_VULKAN_1_2);
  tools.SetMessageConsumer(consumer);
  if (!tools.Validate(optimised)) {
    throw Error(fmt::format("{}: the optimised SPIR-V does not validate:\n{}", file.string(), messages));
  }
  out.words = std::move(optimised);
  return out;
}

}  // namespace rpu::cc
