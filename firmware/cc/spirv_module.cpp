#define SPV_ENABLE_UTILITY_CODE
#include "cc/spirv_module.hpp"

#include <fmt/format.h>

#include "cc/spirv_names.hpp"
#include "common/error.hpp"

namespace rpu::cc {

namespace {

std::string literal_string(std::span<const std::uint32_t> words, std::size_t& used) {
  std::string s;
  for (std::size_t i = 0; i < words.size(); ++i) {
    for (int b = 0; b < 4; ++b) {
      const char c = static_cast<char>((words[i] >> (8 * b)) & 0xff);
      if (c == '\0') {
        used = i + 1;
        return s;
      }
      s += c;
    }
  }
  used = words.size();
  return s;
}

// A scalar OpSpecConstantOp (operands: the opcode, then constant ids) of the operations
// the Shader capability allows it, evaluated on 32-bit words; nullopt for any other.
std::optional<std::uint32_t> spec_constant_op(const Module& m, const std::vector<std::uint32_t>& o) {
  std::vector<std::uint32_t> v;
  for (std::size_t k = 1; k < o.size(); ++k) {
    const auto c = m.constants.find(o[k]);
    if (c == m.constants.end() || c->second.composite) return std::nullopt;
    v.push_back(c->second.bits);
  }
  const auto s = [&](std::size_t k) { return static_cast<std::int32_t>(v[k]); };
  const auto b = [](bool x) { return x ? 1u : 0u; };
  using spv::Op;
  const auto op = static_cast<Op>(o[0]);
  if (v.size() == 1) {
    switch (op) {
      case Op::OpSNegate: return 0u - v[0];
      case Op::OpNot: return ~v[0];
      case Op::OpLogicalNot: return b(v[0] == 0);
      case Op::OpSConvert:
      case Op::OpUConvert: return v[0];
      default: return std::nullopt;
    }
  }
  if (v.size() == 3 && op == Op::OpSelect) return v[0] ? v[1] : v[2];
  if (v.size() != 2) return std::nullopt;
  switch (op) {
    case Op::OpIAdd: return v[0] + v[1];
    case Op::OpISub: return v[0] - v[1];
    case Op::OpIMul: return v[0] * v[1];
    case Op::OpUDiv: return v[1] ? std::optional(v[0] / v[1]) : std::nullopt;
    case Op::OpUMod: return v[1] ? std::optional(v[0] % v[1]) : std::nullopt;
    case Op::OpSDiv:
    case Op::OpSRem:
    case Op::OpSMod: {
      if (v[1] == 0 || (s(0) == INT32_MIN && s(1) == -1)) return std::nullopt;
      const std::int32_t r = s(0) % s(1);
      if (op == Op::OpSDiv) return static_cast<std::uint32_t>(s(0) / s(1));
      if (op == Op::OpSRem || r == 0 || (r < 0) == (s(1) < 0)) return static_cast<std::uint32_t>(r);
      return static_cast<std::uint32_t>(r + s(1));
    }
    case Op::OpShiftLeftLogical: return v[1] < 32 ? std::optional(v[0] << v[1]) : std::nullopt;
    case Op::OpShiftRightLogical: return v[1] < 32 ? std::optional(v[0] >> v[1]) : std::nullopt;
    case Op::OpShiftRightArithmetic:
      return v[1] < 32 ? std::optional(static_cast<std::uint32_t>(s(0) >> v[1])) : std::nullopt;
    case Op::OpBitwiseOr: return v[0] | v[1];
    case Op::OpBitwiseXor: return v[0] ^ v[1];
    case Op::OpBitwiseAnd: return v[0] & v[1];
    case Op::OpLogicalOr: return b(v[0] || v[1]);
    case Op::OpLogicalAnd: return b(v[0] && v[1]);
    case Op::OpLogicalEqual:
    case Op::OpIEqual: return b(v[0] == v[1]);
    case Op::OpLogicalNotEqual:
    case Op::OpINotEqual: return b(v[0] != v[1]);
    case Op::OpULessThan: return b(v[0] < v[1]);
    case Op::OpSLessThan: return b(s(0) < s(1));
    case Op::OpUGreaterThan: return b(v[0] > v[1]);
    case Op::OpSGreaterThan: return b(s(0) > s(1));
    case Op::OpULessThanEqual: return b(v[0] <= v[1]);
    case Op::OpSLessThanEqual: return b(s(0) <= s(1));
    case Op::OpUGreaterThanEqual: return b(v[0] >= v[1]);
    case Op::OpSGreaterThanEqual: return b(s(0) >= s(1));
    default: return std::nullopt;
  }
}

}  // namespace

Module Module::parse(std::span<const std::uint32_t> words, const std::string& file) {
  if (words.size() < 5 || words[0] != spv::MagicNumber) {
    throw Error(fmt::format("{}: not a SPIR-V module (magic {:#x})", file, words.empty() ? 0u : words[0]));
  }
  Module m;
  Function* function = nullptr;
  Block* block = nullptr;
  SourceLocation where;
  for (std::size_t at = 5; at < words.size();) {
    const std::uint32_t count = words[at] >> 16;
    const auto op = static_cast<spv::Op>(words[at] & 0xffff);
    if (count == 0 || at + count > words.size()) {
      throw Error(fmt::format("{}: SPIR-V word {}: instruction {} of {} words runs past the module's end", file, at,
                              op_name(op), count));
    }
    const std::span<const std::uint32_t> in = words.subspan(at + 1, count - 1);
    at += count;
    bool has_result = false, has_type = false;
    spv::HasResultAndType(op, &has_result, &has_type);
    Instruction inst;
    inst.op = op;
    std::size_t k = 0;
    if (has_type && k < in.size()) inst.type = in[k++];
    if (has_result && k < in.size()) inst.result = in[k++];
    inst.operands.assign(in.begin() + static_cast<std::ptrdiff_t>(k), in.end());
    const auto& o = inst.operands;
    const auto need = [&](std::size_t n) {
      if (o.size() < n) {
        throw Error(fmt::format("{}: SPIR-V {} has {} operands, expected at least {}", file, op_name(op), o.size(), n));
      }
    };
    switch (op) {
      case spv::Op::OpExtInstImport: {
        std::size_t used = 0;
        if (literal_string(o, used) == "GLSL.std.450") m.glsl_std_450 = inst.result;
        break;
      }
      case spv::Op::OpEntryPoint:
        need(2);
        if (m.entry == 0) {
          m.model = static_cast<spv::ExecutionModel>(o[0]);
          m.entry = o[1];
        }
        break;
      case spv::Op::OpString: {
        std::size_t used = 0;
        m.strings[inst.result] = literal_string(o, used);
        break;
      }
      case spv::Op::OpName: {
        need(1);
        std::size_t used = 0;
        m.names[o[0]] = literal_string(std::span(o).subspan(1), used);
        break;
      }
      case spv::Op::OpLine:
        need(2);
        where.file = m.strings.count(o[0]) ? m.strings[o[0]] : file;
        where.line = static_cast<int>(o[1]);
        break;
      case spv::Op::OpNoLine:
        where = {};
        break;
      case spv::Op::OpDecorate:
      case spv::Op::OpMemberDecorate: {
        const bool member = op == spv::Op::OpMemberDecorate;
        need(member ? 3 : 2);
        Decorations& d = member ? m.member_decorations[{o[0], o[1]}] : m.decorations[o[0]];
        const std::size_t i = member ? 2 : 1;
        const auto value = [&]() -> std::uint32_t { need(i + 2); return o[i + 1]; };
        switch (static_cast<spv::Decoration>(o[i])) {
          case spv::Decoration::BuiltIn: d.builtin = static_cast<spv::BuiltIn>(value()); break;
          case spv::Decoration::Binding: d.binding = value(); break;
          case spv::Decoration::DescriptorSet: d.set = value(); break;
          case spv::Decoration::Offset: d.offset = value(); break;
          case spv::Decoration::ArrayStride: d.array_stride = value(); break;
          case spv::Decoration::SpecId: d.spec_id = value(); break;
          default: break;
        }
        break;
      }
      case spv::Op::OpTypeVoid:
      case spv::Op::OpTypeBool:
      case spv::Op::OpTypeInt:
      case spv::Op::OpTypeFloat:
      case spv::Op::OpTypeVector:
      case spv::Op::OpTypeMatrix:
      case spv::Op::OpTypeArray:
      case spv::Op::OpTypeRuntimeArray:
      case spv::Op::OpTypeStruct:
      case spv::Op::OpTypePointer:
      case spv::Op::OpTypeFunction:
      case spv::Op::OpTypeImage:
      case spv::Op::OpTypeSampler:
      case spv::Op::OpTypeSampledImage:
      case spv::Op::OpTypeAccelerationStructureKHR:
      case spv::Op::OpTypeRayQueryKHR: {
        Type t;
        t.op = op;
        if (op == spv::Op::OpTypeInt) {
          need(2);
          t.count = o[0];
          t.is_signed = o[1] != 0;
        } else if (op == spv::Op::OpTypeFloat) {
          need(1);
          t.count = o[0];
        } else if (op == spv::Op::OpTypeVector || op == spv::Op::OpTypeMatrix) {
          need(2);
          t.element = o[0];
          t.count = o[1];
        } else if (op == spv::Op::OpTypeArray) {
          need(2);
          t.element = o[0];
          const auto c = m.constants.find(o[1]);
          t.count = c == m.constants.end() ? 0 : c->second.bits;
        } else if (op == spv::Op::OpTypeRuntimeArray) {
          need(1);
          t.element = o[0];
        } else if (op == spv::Op::OpTypeStruct) {
          t.members = o;
        } else if (op == spv::Op::OpTypePointer) {
          need(2);
          t.storage = static_cast<spv::StorageClass>(o[0]);
          t.element = o[1];
        }
        m.types[inst.result] = t;
        break;
      }
      case spv::Op::OpConstantTrue:
      case spv::Op::OpConstantFalse:
      case spv::Op::OpSpecConstantTrue:
      case spv::Op::OpSpecConstantFalse:
        m.constants[inst.result] = {inst.type, false,
                                    op == spv::Op::OpConstantTrue || op == spv::Op::OpSpecConstantTrue ? 1u : 0u, {},
                                    false, op == spv::Op::OpSpecConstantTrue || op == spv::Op::OpSpecConstantFalse};
        break;
      case spv::Op::OpConstant:
      case spv::Op::OpSpecConstant:
        need(1);
        if (o.size() != 1) throw Error(fmt::format("{}: SPIR-V constant %{} is wider than 32 bits", file, inst.result));
        m.constants[inst.result] = {inst.type, false, o[0], {}, false, op == spv::Op::OpSpecConstant};
        break;
      case spv::Op::OpConstantComposite:
      case spv::Op::OpSpecConstantComposite:
        m.constants[inst.result] = {inst.type, true, 0, o, false};
        break;
      case spv::Op::OpSpecConstantOp:
        // What SPIRV-Tools' folding leaves of frozen specialization constants.
        need(2);
        if (const std::optional<std::uint32_t> bits = spec_constant_op(m, o)) {
          m.constants[inst.result] = {inst.type, false, *bits, {}, false};
        }
        break;
      case spv::Op::OpUndef:
        if (function != nullptr) {
          if (block != nullptr) {
            inst.where = where;
            block->body.push_back(inst);
          }
          break;
        }
        [[fallthrough]];  // a module-level undefined value: any value will do, zero it is
      case spv::Op::OpConstantNull: {
        m.constants[inst.result] = {inst.type, false, 0, {}, true};
        break;
      }
      case spv::Op::OpVariable:
        need(1);
        if (function == nullptr) {
          Variable v{inst.type, static_cast<spv::StorageClass>(o[0]), std::nullopt};
          if (o.size() > 1) v.initializer = o[1];
          m.variables[inst.result] = v;
        } else if (block != nullptr) {
          block->body.push_back(inst);
        }
        break;
      case spv::Op::OpFunction:
        m.functions.push_back({});
        function = &m.functions.back();
        function->id = inst.result;
        function->name = m.names.count(inst.result) ? m.names[inst.result] : "";
        block = nullptr;
        break;
      case spv::Op::OpFunctionEnd:
        function = nullptr;
        block = nullptr;
        break;
      case spv::Op::OpLabel:
        if (function == nullptr) throw Error(fmt::format("{}: SPIR-V OpLabel outside a function", file));
        function->blocks.push_back({inst.result, {}});
        block = &function->blocks.back();
        break;
      default:
        if (block != nullptr) {
          inst.where = where;
          block->body.push_back(inst);
          if (op == spv::Op::OpBranch || op == spv::Op::OpBranchConditional || op == spv::Op::OpSwitch ||
              op == spv::Op::OpReturn || op == spv::Op::OpReturnValue || op == spv::Op::OpKill ||
              op == spv::Op::OpUnreachable || op == spv::Op::OpTerminateRayKHR ||
              op == spv::Op::OpIgnoreIntersectionKHR) {
            where = {};  // OpLine does not outlive its block
          }
        }
        break;
    }
  }
  if (m.entry == 0) throw Error(fmt::format("{}: the SPIR-V module has no entry point", file));
  return m;
}

const Type& Module::type(Id id) const {
  const auto it = types.find(id);
  if (it == types.end()) throw Error(fmt::format("SPIR-V: %{} is not a type", id));
  return it->second;
}

std::string Module::glsl_type(Id id) const {
  const auto it = types.find(id);
  if (it == types.end()) return fmt::format("%{}", id);
  const Type& t = it->second;
  const auto scalar_prefix = [&](Id s) -> std::string {
    const Type& e = type(s);
    if (e.op == spv::Op::OpTypeBool) return "b";
    if (e.op == spv::Op::OpTypeInt) {
      return fmt::format("{}{}", e.is_signed ? "i" : "u", e.count == 32 ? std::string() : std::to_string(e.count));
    }
    return e.count == 64 ? "d" : e.count == 16 ? "f16" : "";
  };
  switch (t.op) {
    case spv::Op::OpTypeVoid: return "void";
    case spv::Op::OpTypeBool: return "bool";
    case spv::Op::OpTypeInt:
      return t.count == 32 ? (t.is_signed ? "int" : "uint") : fmt::format("{}int{}_t", t.is_signed ? "" : "u", t.count);
    case spv::Op::OpTypeFloat: return t.count == 32 ? "float" : t.count == 64 ? "double" : fmt::format("float{}_t", t.count);
    case spv::Op::OpTypeVector: return fmt::format("{}vec{}", scalar_prefix(t.element), t.count);
    case spv::Op::OpTypeMatrix: {
      const Type& column = type(t.element);
      return column.count == t.count ? fmt::format("{}mat{}", scalar_prefix(column.element), t.count)
                                     : fmt::format("{}mat{}x{}", scalar_prefix(column.element), t.count, column.count);
    }
    case spv::Op::OpTypeArray: return fmt::format("{}[{}]", glsl_type(t.element), t.count);
    case spv::Op::OpTypeRuntimeArray: return fmt::format("{}[]", glsl_type(t.element));
    case spv::Op::OpTypePointer: return glsl_type(t.element);
    case spv::Op::OpTypeStruct: {
      if (const auto name = names.find(id); name != names.end() && !name->second.empty()) {
        return "struct " + name->second;
      }
      std::string members;
      for (const Id m : t.members) members += (members.empty() ? "" : ", ") + glsl_type(m);
      return fmt::format("struct {{ {} }}", members);
    }
    case spv::Op::OpTypeImage: return "an image (image2D or texture2D)";
    case spv::Op::OpTypeSampler: return "sampler";
    case spv::Op::OpTypeSampledImage: return "a sampled image (sampler2D)";
    case spv::Op::OpTypeAccelerationStructureKHR: return "accelerationStructureEXT";
    case spv::Op::OpTypeRayQueryKHR: return "rayQueryEXT";
    default: return fmt::format("%{}", id);
  }
}

const Decorations& Module::decoration(Id id) const {
  static const Decorations none;
  const auto it = decorations.find(id);
  return it == decorations.end() ? none : it->second;
}

const Decorations& Module::member_decoration(Id struct_type, std::uint32_t member) const {
  static const Decorations none;
  const auto it = member_decorations.find({struct_type, member});
  return it == member_decorations.end() ? none : it->second;
}

std::uint32_t Module::components(Id type_id) const {
  const Type& t = type(type_id);
  switch (t.op) {
    case spv::Op::OpTypeBool:
    case spv::Op::OpTypeInt:
    case spv::Op::OpTypeFloat: return 1;
    case spv::Op::OpTypeVector: return t.count;
    default: return 0;
  }
}

Id Module::scalar_of(Id type_id) const {
  const Type& t = type(type_id);
  return t.op == spv::Op::OpTypeVector ? t.element : type_id;
}

bool Module::is_float(Id type_id) const { return type(scalar_of(type_id)).op == spv::Op::OpTypeFloat; }
bool Module::is_bool(Id type_id) const { return type(scalar_of(type_id)).op == spv::Op::OpTypeBool; }

}  // namespace rpu::cc
