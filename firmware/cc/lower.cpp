#include "cc/lower.hpp"

#include <algorithm>
#include <bit>
#include <functional>
#include <map>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "cc/abi.hpp"
#include "cc/builder.hpp"
#include "cc/select.hpp"
#include "cc/spirv_names.hpp"
#include "common/error.hpp"
#include "isa/instruction.hpp"
#include "rpu/spec.hpp"

namespace rpu::cc {

namespace mm = spec::memory;

namespace {

// Where a pointer points: device memory (a buffer), a variable kept in registers, a
// built-in, or an opaque object (the framebuffer image, the acceleration structure).
struct Pointer {
  enum class Where { kMemory, kRegisters, kBuiltin, kHitAttribute, kOpaque } where = Where::kMemory;
  int address = -1;           // memory: vreg with the base address (lane of `address_lane`), or -1
  std::uint32_t offset = 0;   // memory: constant part of the address
  std::uint32_t binding = ~0u;  // memory: the buffer's binding
  Id variable = 0;            // registers, builtin, hit attribute: the variable
  std::vector<std::uint32_t> path;  // registers/builtin: member or component indices
  Id type = 0;                // pointee type
};

// What GLSL wrote for a SPIR-V instruction the back end refuses, where one spelling says
// it (a refusal names the source line, which then tells the instruction apart), then the
// opcode's own name.
constexpr std::pair<spv::Op, std::string_view> kGlslSpellings[] = {
    {spv::Op::OpImageSampleImplicitLod, "texture()/textureLod() on a sampler"},
    {spv::Op::OpImageSampleExplicitLod, "texture()/textureLod() on a sampler"},
    {spv::Op::OpImageFetch, "texelFetch()"},
    {spv::Op::OpImage, "a texture: texture() or texelFetch() on a sampler2D"},
    {spv::Op::OpSampledImage, "a texture: texture() or texelFetch() on a sampler2D"},
    {spv::Op::OpImageQuerySize, "textureSize()/imageSize()"},
    {spv::Op::OpImageQuerySizeLod, "textureSize()/imageSize()"},
    {spv::Op::OpExecuteCallableKHR, "executeCallableEXT()"},
    {spv::Op::OpTerminateRayKHR, "terminateRayEXT"},
    {spv::Op::OpIgnoreIntersectionKHR, "ignoreIntersectionEXT"},
    {spv::Op::OpReportIntersectionKHR, "reportIntersectionEXT()"},
    {spv::Op::OpKill, "discard"},
    {spv::Op::OpFMod, "mod() of floats"},
    {spv::Op::OpFRem, "a float remainder"},
    {spv::Op::OpConvertUToPtr, "a buffer_reference address (uint64_t)"},
    {spv::Op::OpConvertPtrToU, "a buffer_reference address (uint64_t)"},
    {spv::Op::OpBitCount, "bitCount()"},
    {spv::Op::OpBitReverse, "bitfieldReverse()"},
    {spv::Op::OpBitFieldInsert, "bitfieldInsert()"},
    {spv::Op::OpBitFieldSExtract, "bitfieldExtract()"},
    {spv::Op::OpBitFieldUExtract, "bitfieldExtract()"},
    {spv::Op::OpTranspose, "transpose()"},
    {spv::Op::OpOuterProduct, "outerProduct()"},
    {spv::Op::OpDPdx, "dFdx()/dFdy()/fwidth() (no derivatives in ray tracing)"},
    {spv::Op::OpDPdy, "dFdx()/dFdy()/fwidth() (no derivatives in ray tracing)"},
    {spv::Op::OpFwidth, "dFdx()/dFdy()/fwidth() (no derivatives in ray tracing)"},
};

std::string glsl_spelling(spv::Op op) {
  for (const auto& [o, glsl] : kGlslSpellings) {
    if (o == op) return fmt::format("{} ({})", glsl, op_name(op));
  }
  return op_name(op);
}

// Thrown where an instruction reads, through a phi or a pointer, the result of one that
// failed: it is skipped without an error of its own.
struct UsesAFailure {};

// A value of the shader: a scalar or vector (one source operand), or an aggregate.
// An aggregate loaded from a buffer stays `lazy` (where it is and its type) until a
// member is used: buffers are read-only, so a late load reads the same, and the members
// a shader never uses cost neither a load nor a register. The late load keeps the source
// line of the OpLoad, which a fault in it names.
struct Value {
  bool aggregate = false;
  Src leaf;
  std::vector<Value> members;
  bool lazy = false;
  Pointer at;
  Id type = 0;
  SourceLocation where;  // lazy: the OpLoad's line
};

class Lowerer {
 public:
  Lowerer(const Module& m, const SpirvShader& shader, const LowerContext& ctx) : m_(m), shader_(shader), ctx_(ctx) {
    fn_.label = shader_label(shader);
    fn_.name = shader.file.string();
  }

  Lowered run() {
    const Function* f = nullptr;
    for (const Function& fun : m_.functions) {
      if (fun.id == m_.entry) f = &fun;
    }
    if (f == nullptr) throw Error(fmt::format("{}: the entry point's function is missing", shader_.file.string()));
    if (m_.functions.size() > 1) {
      for (const Function& fun : m_.functions) {
        if (fun.id != m_.entry) {
          b_.fail(fun.blocks.empty() || fun.blocks[0].body.empty() ? SourceLocation{} : fun.blocks[0].body[0].where,
                  fmt::format("function '{}' was not inlined (recursion is not supported)", fun.name));
        }
      }
    }
    for (const Block& b : f->blocks) {
      for (const Instruction& i : b.body) {
        if (i.op == spv::Op::OpTraceRayKHR) has_calls_ = true;
        if (i.result != 0) defined_by_[i.result] = i.op;
        if (const auto at = launch_word(i)) launch_words_read_.insert(*at);
      }
    }
    entry();
    for (std::size_t bi = 0; bi < f->blocks.size(); ++bi) {
      const Block& b = f->blocks[bi];
      blocks_[b.label] = &b;
    }
    for (std::size_t bi = 0; bi < f->blocks.size(); ++bi) {
      const Block& b = f->blocks[bi];
      next_block_ = bi + 1 < f->blocks.size() ? f->blocks[bi + 1].label : 0;
      current_block_ = b.label;
      b_.label(block_label(b.label));
      block_constants_.clear();
      block_addresses_.clear();
      block_loads_.clear();
      for (const Instruction& i : b.body) {
        b_.where = i.where;
        // An instruction that reads a result that failed is skipped, and fails too, without
        // a message of its own: the errors reported are each a cause.
        const bool reads_failed = std::any_of(i.operands.begin(), i.operands.end(),
                                              [&](std::uint32_t word) { return failed_.contains(word); });
        if (reads_failed) {
          if (i.result != 0) failed_.insert(i.result);
          continue;
        }
        try {
          instruction(i);
        } catch (const UsesAFailure&) {
          if (i.result != 0) failed_.insert(i.result);
        } catch (const Error& e) {
          if (std::find(errors_.begin(), errors_.end(), e.what()) == errors_.end()) errors_.emplace_back(e.what());
          if (i.result != 0) failed_.insert(i.result);
          if (errors_.size() >= kMaxErrors) break;
        }
      }
      if (errors_.size() >= kMaxErrors) break;
    }
    if (!errors_.empty()) throw Error(fmt::format("{}", fmt::join(errors_, "\n")));
    return {std::move(fn_), traces_, reads_aperture_, incoming_type_, traced_};
  }

 private:
  // ---- values ---------------------------------------------------------------------------
  int width_of(Id type) const {
    const std::uint32_t n = m_.components(type);
    if (n == 0 || n > 4) return 0;
    return static_cast<int>(n);
  }

  Value constant(Id id) {
    const Constant& c = m_.constants.at(id);
    const Type& t = m_.type(c.type);
    if (t.op == spv::Op::OpTypeVector || t.op == spv::Op::OpTypeBool || t.op == spv::Op::OpTypeInt ||
        t.op == spv::Op::OpTypeFloat) {
      if (const auto it = block_constants_.find(id); it != block_constants_.end()) return it->second;
      const int n = width_of(c.type);
      std::array<std::uint32_t, 4> bits{};
      for (int j = 0; j < n; ++j) {
        std::uint32_t b = 0;
        if (c.null) {
          b = 0;
        } else if (c.composite) {
          const Constant& e = m_.constants.at(c.constituents.at(static_cast<std::size_t>(j)));
          b = e.null ? 0 : e.bits;
        } else {
          b = c.bits;
        }
        bits[static_cast<std::size_t>(j)] = b;
      }
      const bool is_bool = m_.is_bool(c.type), is_float = m_.is_float(c.type);
      if (is_bool) {
        for (auto& b : bits) b = b ? 0xffffffffu : 0u;
      }
      const int d = b_.vreg(n);
      // One instruction per distinct value, with the lanes that hold it.
      std::uint8_t done = 0;
      for (int j = 0; j < n; ++j) {
        if (done & (1u << j)) continue;
        std::uint8_t mask = 0;
        for (int k = j; k < n; ++k) {
          if (bits[static_cast<std::size_t>(k)] == bits[static_cast<std::size_t>(j)]) {
            mask |= static_cast<std::uint8_t>(1u << k);
          }
        }
        b_.op_into(d, mask == (1u << n) - 1 ? 0 : mask, is_float ? Opcode::kLif : Opcode::kLi, {},
                   Imm::lane(bits[static_cast<std::size_t>(j)], is_float),
                done == 0);
        done |= mask;
      }
      Value v;
      v.leaf = whole(d, n);
      block_constants_[id] = v;
      return v;
    }
    Value v;
    v.aggregate = true;
    const std::size_t members = t.op == spv::Op::OpTypeStruct ? t.members.size() : t.count;
    for (std::size_t k = 0; k < members; ++k) {
      if (c.null) {
        v.members.push_back(zero(t.op == spv::Op::OpTypeStruct ? t.members[k] : t.element));
      } else {
        v.members.push_back(value(c.constituents.at(k)));
      }
    }
    return v;
  }
  Value zero(Id type) {
    const Type& t = m_.type(type);
    Value v;
    if (const int n = width_of(type); n > 0) {
      v.leaf = b_.op(Opcode::kLi, n, {}, Imm::integer(0));
      return v;
    }
    v.aggregate = true;
    if (t.op == spv::Op::OpTypeStruct) {
      for (Id member : t.members) v.members.push_back(zero(member));
    } else {
      for (std::uint32_t k = 0; k < t.count; ++k) v.members.push_back(zero(t.element));
    }
    return v;
  }
  Value value(Id id) {
    if (const auto it = values_.find(id); it != values_.end()) return it->second;
    if (m_.constants.count(id)) return constant(id);
    if (const auto it = phis_.find(id); it != phis_.end()) return it->second;
    if (failed_.contains(id)) throw UsesAFailure{};
    const auto def = defined_by_.find(id);
    b_.unsupported(def == defined_by_.end()
                       ? fmt::format("the value %{} (an operand the back end has no value for)", id)
                       : fmt::format("using the result of {} as a value", op_name(def->second)));
  }
  Src scalar_or_vector(Id id) {
    const Value v = concrete(value(id));
    if (v.aggregate) b_.unsupported("an aggregate where a scalar or vector belongs");
    return v.leaf;
  }
  std::optional<std::uint32_t> constant_scalar(Id id) const {
    const auto it = m_.constants.find(id);
    if (it == m_.constants.end()) return std::nullopt;
    const Constant& c = it->second;
    if (c.null) return 0u;
    if (!c.composite) return c.bits;
    // A splat vector counts as its scalar.
    std::optional<std::uint32_t> first;
    for (Id e : c.constituents) {
      const auto b = constant_scalar(e);
      if (!b || (first && *first != *b)) return std::nullopt;
      first = b;
    }
    return first;
  }
  // A value shaped like `type` in fresh vregs (phis, register-resident variables).
  Value fresh(Id type) {
    Value v;
    if (const int n = width_of(type); n > 0) {
      v.leaf = whole(b_.vreg(n), n);
      return v;
    }
    const Type& t = m_.type(type);
    v.aggregate = true;
    if (t.op == spv::Op::OpTypeStruct) {
      for (Id member : t.members) v.members.push_back(fresh(member));
    } else if (t.op == spv::Op::OpTypeArray || t.op == spv::Op::OpTypeMatrix) {
      for (std::uint32_t k = 0; k < t.count; ++k) v.members.push_back(fresh(t.element));
    } else {
      b_.unsupported(fmt::format("a value of type {}", m_.glsl_type(type)));
    }
    return v;
  }
  // A lazy value loaded now, at the line of its OpLoad.
  Value materialise(const Value& lazy) {
    const SourceLocation here = b_.where;
    b_.where = lazy.where;
    Value v = load_memory(lazy.at, lazy.type, true);
    b_.where = here;
    return v;
  }
  Value concrete(const Value& v) { return v.lazy ? materialise(v) : v; }
  // A lazy aggregate as its members, each still lazy; a lazy scalar or vector loaded.
  Value expand(const Value& v) {
    if (!v.lazy) return v;
    if (width_of(v.type) > 0) return materialise(v);
    const Type& t = m_.type(v.type);
    Value r;
    r.aggregate = true;
    const std::size_t count = t.op == spv::Op::OpTypeStruct ? t.members.size() : t.count;
    for (std::size_t k = 0; k < count; ++k) {
      Value m;
      m.lazy = true;
      m.at = v.at;
      m.where = v.where;
      if (t.op == spv::Op::OpTypeStruct) {
        m.at.offset += m_.member_decoration(v.type, static_cast<std::uint32_t>(k)).offset.value_or(0);
        m.type = t.members[k];
      } else {
        m.at.offset += static_cast<std::uint32_t>(k) * m_.decoration(v.type).array_stride.value_or(0);
        m.type = t.element;
      }
      r.members.push_back(m);
    }
    return r;
  }
  void leaves(const Value& lazy_or_not, std::vector<Src>& out) {
    const Value v = concrete(lazy_or_not);
    if (!v.aggregate) {
      out.push_back(v.leaf);
      return;
    }
    for (const Value& m : v.members) leaves(m, out);
  }
  void assign(const Value& to, const Value& from) {
    std::vector<Src> a, b;
    leaves(to, a);
    leaves(from, b);
    for (std::size_t k = 0; k < a.size() && k < b.size(); ++k) b_.copy_into(a[k].v, b[k]);
  }
  Value copy_of(const Value& lazy_or_not) {
    if (lazy_or_not.lazy) return materialise(lazy_or_not);  // a fresh load is a copy
    const Value& from = lazy_or_not;
    if (!from.aggregate) {
      Value v;
      v.leaf = b_.op(Opcode::kMov, from.leaf.n, {from.leaf});
      return v;
    }
    Value v;
    v.aggregate = true;
    for (const Value& m : from.members) v.members.push_back(copy_of(m));
    return v;
  }

  // ---- entry and exit -------------------------------------------------------------------
  void entry() {
    b_.label(fn_.label);
    if (shader_.stage == Stage::kAnyHit) b_.unsupported("an any-hit shader (the traversal unit decides hits itself)");
    if (shader_.stage == Stage::kRaygen) return;
    for (const auto& [id, var] : m_.variables) {
      if (var.storage != spv::StorageClass::IncomingRayPayloadKHR) continue;
      if (incoming_payload_) b_.unsupported("more than one rayPayloadInEXT variable");
      incoming_payload_ = id;
    }
    const Id payload_type = incoming_payload_ ? m_.type(m_.variables.at(incoming_payload_).type).element : 0;
    if (incoming_payload_) {
      payload_widths_ = payload_widths(payload_type);
      const auto name = m_.names.find(incoming_payload_);
      incoming_type_ = payload_of(payload_type, fmt::format("{}'s rayPayloadInEXT {}", shader_.file.string(),
                                                             name == m_.names.end() ? "" : name->second));
    }
    entry_ = enter(b_, shader_.stage, payload_widths_, ctx_.registers);
    if (incoming_payload_) {
      Value home = fresh(payload_type);
      std::vector<Src> dst;
      leaves(home, dst);
      for (std::size_t k = 0; k < dst.size(); ++k) b_.copy_into(dst[k].v, b_.whole(entry_.payload[k]));
      homes_[incoming_payload_] = home;
    }
    if (has_calls_) return_address_ = save_return_address(b_);
  }
  PayloadType payload_of(Id type, std::string where) {
    PayloadType p;
    std::function<void(Id)> walk = [&](Id t) {
      const Type& ty = m_.type(t);
      if (width_of(t) > 0) {
        if (!p.leaves.empty()) p.leaves += ' ';
        p.leaves += m_.glsl_type(t);
      } else if (ty.op == spv::Op::OpTypeStruct) {
        for (Id member : ty.members) walk(member);
      } else {
        for (std::uint32_t k = 0; k < ty.count; ++k) walk(ty.element);
      }
    };
    walk(type);
    p.glsl = m_.glsl_type(type);
    p.where = std::move(where);
    return p;
  }
  // The widths of a payload's scalar and vector leaves (one register each), in declaration order.
  std::vector<int> payload_widths(Id type) {
    std::vector<int> widths;
    std::function<void(Id)> walk = [&](Id t) {
      if (const int n = width_of(t); n > 0) {
        widths.push_back(n);
        return;
      }
      const Type& ty = m_.type(t);
      if (ty.op == spv::Op::OpTypeStruct) {
        for (Id member : ty.members) walk(member);
      } else if (ty.op == spv::Op::OpTypeArray || ty.op == spv::Op::OpTypeMatrix) {
        for (std::uint32_t k = 0; k < ty.count; ++k) walk(ty.element);
      } else {
        b_.unsupported(fmt::format("a ray payload member of type {}", m_.glsl_type(t)));
      }
    };
    walk(type);
    return widths;
  }
  void function_return() {
    std::vector<Src> payload;
    if (incoming_payload_) leaves(homes_.at(incoming_payload_), payload);
    leave(b_, shader_.stage, payload_widths_, payload, return_address_, ctx_.registers);
  }

  // ---- control flow ---------------------------------------------------------------------
  std::string block_label(Id id) const { return fmt::format(".{}_b{}", fn_.label, id); }

  // The copies an edge from the current block to `to` needs for `to`'s phis.
  std::vector<std::pair<Value, Id>> edge_copies(Id from, Id to) {
    std::vector<std::pair<Value, Id>> copies;
    const Block& b = *blocks_.at(to);
    for (const Instruction& i : b.body) {
      if (i.op != spv::Op::OpPhi) break;
      for (std::size_t k = 0; k + 1 < i.operands.size(); k += 2) {
        if (i.operands[k + 1] == from) copies.push_back({phi(i), i.operands[k]});
      }
    }
    return copies;
  }
  Value phi(const Instruction& i) {
    if (const auto it = phis_.find(i.result); it != phis_.end()) return it->second;
    return phis_[i.result] = fresh(i.type);
  }
  bool is_phi_of(Id value, Id block) const {
    const Block& b = *blocks_.at(block);
    for (const Instruction& i : b.body) {
      if (i.op != spv::Op::OpPhi) break;
      if (i.result == value) return true;
    }
    return false;
  }
  // Phi copies are parallel: a source that is itself a phi of the target goes through a
  // temporary first, so no copy reads a phi another copy already wrote.
  void emit_edge_copies(Id from, Id to) {
    const auto copies = edge_copies(from, to);
    std::vector<std::pair<Value, Value>> staged;
    for (const auto& [dst, src] : copies) {
      if (is_phi_of(src, to) && phis_.count(src)) {
        // self-copy x = phi(.., x) needs nothing
        std::vector<Src> a, b;
        leaves(dst, a);
        leaves(phis_.at(src), b);
        if (!a.empty() && a[0].v == b[0].v) continue;
        staged.push_back({dst, copy_of(phis_.at(src))});
      } else {
        staged.push_back({dst, value(src)});
      }
    }
    for (const auto& [dst, src] : staged) assign(dst, src);
  }
  void jump_to(Id from, Id to) {
    emit_edge_copies(from, to);
    b_.branch(block_label(to));
  }
  void conditional(Id from, const Src& cond, Id on_true, Id on_false) {
    const bool copies_true = !edge_copies(from, on_true).empty();
    if (on_true == next_block_ && edge_copies(from, on_false).empty()) {
      // falls through into the true block: one branch around it
      b_.cond_branch(false, cond, block_label(on_false));
      jump_to(from, on_true);
      return;
    }
    const std::string tramp = fmt::format(".{}_e{}_{}", fn_.label, from, on_true);
    b_.cond_branch(true, cond, copies_true ? tramp : block_label(on_true));
    jump_to(from, on_false);
    if (copies_true) {
      b_.label(tramp);
      block_constants_.clear();
      block_addresses_.clear();
      block_loads_.clear();
      jump_to(from, on_true);
    }
  }

  // ---- memory -----------------------------------------------------------------------------
  static std::uint32_t camera_binding() {
    for (const spec::ShaderBuffer& b : spec::kShaderBuffers) {
      if (b.name == "camera") return b.binding;
    }
    return ~0u;
  }
  Src launch_base() { return b_.op(Opcode::kLi, 1, {}, Imm::bits(mm::kDeviceLaunchBase)); }
  // A scene without vertex normals or uvs has their buffer at address 0 (launch
  // normals_at, uvs_at of spec/memory_map.toml), where the memory image's header is: a
  // shader that reads one there stops at its line with an illegal-instruction fault at
  // the code label .<shader>_no_<buffer><n>, instead of reading the header as normals.
  // The byte offset in the launch block of a scalar an access chain names, if it is one.
  std::optional<std::uint32_t> launch_word(const Instruction& i) const {
    if (i.op != spv::Op::OpAccessChain && i.op != spv::Op::OpInBoundsAccessChain) return std::nullopt;
    const auto var = m_.variables.find(i.operands[0]);
    if (var == m_.variables.end() || m_.decoration(i.operands[0]).binding.value_or(~0u) != 0 ||
        var->second.storage != spv::StorageClass::StorageBuffer) {
      return std::nullopt;
    }
    Id type = m_.type(var->second.type).element;
    std::uint32_t offset = 0;
    for (std::size_t k = 1; k < i.operands.size(); ++k) {
      const auto c = m_.constants.find(i.operands[k]);
      const Type& t = m_.type(type);
      if (c == m_.constants.end() || c->second.composite || t.op != spv::Op::OpTypeStruct ||
          c->second.bits >= t.members.size()) {
        return std::nullopt;
      }
      offset += m_.member_decoration(type, c->second.bits).offset.value_or(0);
      type = t.members[c->second.bits];
    }
    return offset;
  }
  void stop_if_absent(const Src& base, std::string_view buffer) {
    const std::string present = b_.fresh_label(fmt::format("has_{}", buffer));
    b_.cond_branch(true, base, present);
    b_.label(b_.fresh_label(fmt::format("no_{}", buffer)));
    MInst trap;
    trap.kind = Kind::kTrap;
    b_.push(std::move(trap));
    b_.label(present);
  }
  Pointer buffer_pointer(Id var_id, const Variable& var) {
    const Decorations& d = m_.decoration(var_id);
    const Id block_type = m_.type(var.type).element;
    const std::uint32_t binding = d.binding.value_or(~0u);
    if (d.set.value_or(0) != 0) b_.unsupported(fmt::format("descriptor set {} (the chip has set 0)", *d.set));
    for (const spec::ShaderBuffer& b : spec::kShaderBuffers) {
      if (b.binding != binding) continue;
      // A block of the shader's own at a binding the chip uses would read the chip's
      // buffer (lights[] for binding 2) as if it were its own.
      const auto block = m_.names.find(block_type);
      if (block == m_.names.end() || block->second != b.block) {
        b_.fail(b_.where, fmt::format("storage buffer block '{}' at binding {}: that binding is the chip's {} "
                                      "buffer, block {} of rpu.glsl; the chip reads no other buffers "
                                      "(spec/shaders.toml, docs/shaders.md)",
                                      block == m_.names.end() ? "" : block->second, binding, b.name, b.block));
      }
      Pointer p;
      p.type = block_type;
      p.binding = binding;
      if (const auto it = block_addresses_.find(binding); it != block_addresses_.end()) {
        p.address = it->second;
        return p;
      }
      Src base = launch_base();
      if (b.in_launch_block) {
        MInst l;
        l.op = Opcode::kLd1;
        l.dst = b_.vreg(1);
        l.srcs = {base};
        l.imm = Imm::integer(b.launch_word_at);
        const int d2 = l.dst;
        b_.push(std::move(l));
        base = whole(d2, 1);
        // A shader that reads launch_record.normals (uvs) tests for the buffer itself.
        if ((b.name == "normals" || b.name == "uvs") && !launch_words_read_.contains(b.launch_word_at)) {
          stop_if_absent(base, b.name);
        }
      }
      block_addresses_[binding] = base.v;
      p.address = base.v;
      return p;
    }
    b_.fail(b_.where, fmt::format("storage buffer '{}' at binding {}: the chip's buffers are at bindings 0-{} "
                                  "(spec/shaders.toml, docs/shaders.md)",
                                  m_.names.count(var_id) ? m_.names.at(var_id) : "", binding,
                                  spec::kShaderBuffers.size() - 1));
  }
  Pointer pointer(Id id) {
    if (const auto it = pointers_.find(id); it != pointers_.end()) return it->second;
    if (failed_.contains(id)) throw UsesAFailure{};
    const auto v = m_.variables.find(id);
    if (v == m_.variables.end()) b_.unsupported(fmt::format("the pointer %{}", id));
    const Variable& var = v->second;
    const Id pointee = m_.type(var.type).element;
    Pointer p;
    p.variable = id;
    p.type = pointee;
    switch (var.storage) {
      case spv::StorageClass::StorageBuffer:
      case spv::StorageClass::Uniform:
        return buffer_pointer(id, var);
      case spv::StorageClass::Input:
        if (!m_.decoration(id).builtin) b_.unsupported("an input variable that is not a built-in");
        p.where = Pointer::Where::kBuiltin;
        return p;
      case spv::StorageClass::HitAttributeKHR:
        p.where = Pointer::Where::kHitAttribute;
        return p;
      case spv::StorageClass::UniformConstant:
        p.where = Pointer::Where::kOpaque;
        return p;
      case spv::StorageClass::Private:
      case spv::StorageClass::Function:
        if (m_.type(pointee).op == spv::Op::OpTypeRayQueryKHR) {
          p.where = Pointer::Where::kOpaque;
          return p;
        }
        [[fallthrough]];
      case spv::StorageClass::RayPayloadKHR:
      case spv::StorageClass::IncomingRayPayloadKHR:
        p.where = Pointer::Where::kRegisters;
        if (!homes_.count(id)) {
          homes_[id] = fresh(pointee);
          if (var.initializer) assign(homes_[id], value(*var.initializer));
        }
        return p;
      default:
        b_.unsupported(fmt::format("a variable in storage class {}",
                                   storage_class_name(static_cast<std::uint32_t>(var.storage))));
    }
  }
  void access_chain(const Instruction& i) {
    Pointer p = pointer(i.operands[0]);
    for (std::size_t k = 1; k < i.operands.size(); ++k) {
      const Id index = i.operands[k];
      const Type& t = m_.type(p.type);
      const auto c = constant_scalar(index);
      if (p.where != Pointer::Where::kMemory) {
        if (!c) {
          b_.unsupported("a dynamic index into a variable kept in registers (a local array indexed by a variable)");
        }
        p.path.push_back(*c);
        p.type = t.op == spv::Op::OpTypeStruct ? t.members.at(*c) : t.element;
        continue;
      }
      if (t.op == spv::Op::OpTypeStruct) {
        p.offset += m_.member_decoration(p.type, *c).offset.value_or(0);
        p.type = t.members.at(*c);
        continue;
      }
      std::uint32_t stride = 4;
      if (t.op == spv::Op::OpTypeArray || t.op == spv::Op::OpTypeRuntimeArray) {
        stride = m_.decoration(p.type).array_stride.value_or(0);
        if (stride == 0) b_.unsupported("an array without an ArrayStride in a buffer");
      } else if (t.op != spv::Op::OpTypeVector) {
        b_.unsupported(fmt::format("indexing a {} in a buffer", m_.glsl_type(p.type)));
      }
      p.type = t.element;
      if (c) {
        p.offset += *c * stride;
        continue;
      }
      const Src idx = scalar_or_vector(index);
      const Src scaled = std::has_single_bit(stride)
                             ? b_.op(Opcode::kShli, 1, {idx}, Imm::integer(std::countr_zero(stride)))
                             : b_.op(Opcode::kImuli, 1, {idx}, Imm::integer(stride));
      p.address = b_.op(Opcode::kIadd, 1, {whole(p.address, 1), scaled}).v;
    }
    pointers_[i.result] = p;
  }
  Value load_memory(const Pointer& p, Id type, bool eager = false) {
    const Type& t = m_.type(type);
    {
      if (!eager) {
        Value v;
        v.lazy = true;
        v.at = p;
        v.type = type;
        v.where = b_.where;
        return v;
      }
    }
    if (const int n = width_of(type); n > 0) {
      const auto key = std::make_tuple(p.address, p.offset, type);
      if (const auto it = block_loads_.find(key); it != block_loads_.end()) {
        Value v;
        v.leaf = it->second;
        return v;
      }
      const bool f = m_.is_float(type);
      if (m_.is_bool(type)) b_.unsupported("a bool in a buffer");
      if (p.binding == camera_binding() && p.offset <= mm::kCameraApertureAt &&
          mm::kCameraApertureAt < p.offset + 4u * static_cast<std::uint32_t>(n)) {
        reads_aperture_ = true;
      }
      MInst l;
      l.op = n == 1 ? (f ? Opcode::kLd1f : Opcode::kLd1) : (f ? Opcode::kLdf : Opcode::kLd);
      l.dst = b_.vreg(n);
      l.srcs = {whole(p.address, 1)};
      l.imm = Imm::integer(static_cast<std::int32_t>(p.offset));
      Value v;
      v.leaf = whole(l.dst, n);
      b_.push(std::move(l));
      block_loads_[key] = v.leaf;
      return v;
    }
    Value v;
    v.aggregate = true;
    if (t.op == spv::Op::OpTypeStruct) {
      for (std::size_t k = 0; k < t.members.size(); ++k) {
        Pointer q = p;
        q.offset += m_.member_decoration(type, static_cast<std::uint32_t>(k)).offset.value_or(0);
        v.members.push_back(load_memory(q, t.members[k], eager));
      }
    } else if (t.op == spv::Op::OpTypeArray) {
      const std::uint32_t stride = m_.decoration(type).array_stride.value_or(0);
      for (std::uint32_t k = 0; k < t.count; ++k) {
        Pointer q = p;
        q.offset += k * stride;
        v.members.push_back(load_memory(q, t.element, eager));
      }
    } else {
      b_.unsupported(fmt::format("loading a {} from a buffer", m_.glsl_type(type)));
    }
    return v;
  }
  // The part of a register-resident variable a path names: a sub-value, or one component.
  struct Place {
    Value* value = nullptr;
    int component = -1;
  };
  Place place(const Pointer& p) {
    Place pl{&homes_.at(p.variable), -1};
    for (const std::uint32_t k : p.path) {
      if (pl.value->aggregate) {
        pl.value = &pl.value->members.at(k);
      } else {
        pl.component = static_cast<int>(k);
      }
    }
    return pl;
  }
  Value builtin(const Pointer& p, Id type) {
    const spv::BuiltIn b = *m_.decoration(p.variable).builtin;
    Src s;
    switch (b) {
      case spv::BuiltIn::LaunchIdKHR:
      case spv::BuiltIn::LaunchSizeKHR: {
        MInst r;
        r.op = Opcode::kRdsr;
        r.dst = b_.vreg(3);
        r.dst_comps = 0b011;
        r.fresh = true;
        r.imm = Imm::special(b == spv::BuiltIn::LaunchIdKHR ? spec::isa::kSpecialPixel : spec::isa::kSpecialLaunch);
        const int d = r.dst;
        b_.push(std::move(r));
        b_.op_into(d, 0b100, Opcode::kLi, {}, Imm::integer(b == spv::BuiltIn::LaunchIdKHR ? 0 : 1));
        small_.insert(d);  // pixel coordinates and sizes are far below 2^31
        s = whole(d, 3);
        break;
      }
      case spv::BuiltIn::WorldRayOriginKHR:
      case spv::BuiltIn::ObjectRayOriginKHR: s = whole(need(entry_.origin), 3); break;
      case spv::BuiltIn::WorldRayDirectionKHR:
      case spv::BuiltIn::ObjectRayDirectionKHR: s = whole(need(entry_.direction), 3); break;
      case spv::BuiltIn::RayTminKHR: s = whole(need(entry_.tmin), 1); break;
      case spv::BuiltIn::RayTmaxKHR:
      case spv::BuiltIn::HitTNV:
        s = entry_.hit_t >= 0 ? whole(entry_.hit_t, 1) : whole(need(entry_.tmax), 1);
        break;
      case spv::BuiltIn::PrimitiveId: s = whole(need(entry_.primitive), 1); break;
      case spv::BuiltIn::InstanceCustomIndexKHR: s = whole(need(entry_.material), 1); break;
      case spv::BuiltIn::InstanceId:
      case spv::BuiltIn::RayGeometryIndexKHR: s = b_.op(Opcode::kLi, 1, {}, Imm::integer(0)); break;
      case spv::BuiltIn::ObjectToWorldKHR:
      case spv::BuiltIn::WorldToObjectKHR: {
        // The chip's scene is one object in world space (no instances): both are the
        // identity, 4 columns of 3 (mat4x3).
        Value m;
        m.aggregate = true;
        for (int c = 0; c < 4; ++c) {
          const int d = b_.vreg(3);
          b_.op_into(d, 0, Opcode::kLif, {}, Imm::fp32_bits(0), true);
          if (c < 3) b_.op_into(d, static_cast<std::uint8_t>(1u << c), Opcode::kLif, {}, Imm::fp32_bits(0x3f800000u));
          Value column;
          column.leaf = whole(d, 3);
          m.members.push_back(column);
        }
        for (const std::uint32_t k : p.path) {
          if (m.aggregate) {
            Value member = m.members.at(k);
            m = std::move(member);
          } else {
            m.leaf = component(m.leaf, static_cast<int>(k));
          }
        }
        return m;
      }
      default:
        b_.unsupported(fmt::format("the built-in {} (the chip provides launch id and size, world and object ray "
                                   "origin and direction, t min and max, hit t, primitive id, instance id and custom "
                                   "index, and the identity object-to-world and world-to-object matrices)",
                                   builtin_name(static_cast<std::uint32_t>(b))));
    }
    for (const std::uint32_t k : p.path) s = component(s, static_cast<int>(k));
    Value v;
    v.leaf = s;
    (void)type;
    return v;
  }
  int need(int v) const {
    if (v < 0) b_.unsupported("this built-in in this stage");
    return v;
  }
  void load(const Instruction& i) {
    const Pointer p = pointer(i.operands[0]);
    switch (p.where) {
      case Pointer::Where::kMemory: values_[i.result] = load_memory(p, i.type); return;
      case Pointer::Where::kBuiltin: values_[i.result] = builtin(p, i.type); return;
      case Pointer::Where::kHitAttribute: {
        if (shader_.stage != Stage::kClosestHit) b_.unsupported("hit attributes outside a closest-hit shader");
        const Id var_type = m_.type(m_.variables.at(p.variable).type).element;
        if (width_of(var_type) != 2 || !m_.is_float(var_type)) {
          b_.unsupported("a hit attribute that is not a vec2 (the chip's hit attributes are the barycentrics)");
        }
        Src s = whole(entry_.barycentrics, 2);
        for (const std::uint32_t k : p.path) s = component(s, static_cast<int>(k));
        Value v;
        v.leaf = s;
        values_[i.result] = v;
        return;
      }
      case Pointer::Where::kOpaque: opaque_[i.result] = p.variable; return;
      case Pointer::Where::kRegisters: {
        const Place pl = place(p);
        if (pl.component >= 0) {
          Value v;
          v.leaf = b_.op(Opcode::kMov, 1, {component(pl.value->leaf, pl.component)});
          values_[i.result] = v;
        } else {
          values_[i.result] = copy_of(*pl.value);
        }
        return;
      }
    }
  }
  void store(const Instruction& i) {
    const Pointer p = pointer(i.operands[0]);
    if (p.where != Pointer::Where::kRegisters) {
      b_.unsupported("a store to a buffer (the scene's buffers are read-only; write the framebuffer with imageStore)");
    }
    const Value from = value(i.operands[1]);
    const Place pl = place(p);
    if (pl.component >= 0) {
      const auto lane = pl.value->leaf.comp[static_cast<std::size_t>(pl.component)];
      b_.op_into(pl.value->leaf.v, static_cast<std::uint8_t>(1u << lane), Opcode::kMov, {from.leaf});
      return;
    }
    assign(*pl.value, from);
  }

  // ---- instructions -------------------------------------------------------------------------
  // An instruction's operands from `first` on, as selection reads them.
  class Args final : public Operands {
   public:
    Args(Lowerer& l, const Instruction& i, std::size_t first) : l_(l), i_(i), first_(first) {}
    Src value(std::size_t k) override { return l_.scalar_or_vector(id(k)); }
    std::optional<std::uint32_t> constant(std::size_t k) const override { return l_.constant_scalar(id(k)); }
    std::vector<Src> columns(std::size_t k) override {
      std::vector<Src> out;
      for (const Value& c : l_.concrete(l_.value(id(k))).members) out.push_back(c.leaf);
      return out;
    }
    bool below_2_31(const Src& s) const override { return l_.small_.count(s.v) != 0; }

   private:
    Id id(std::size_t k) const { return i_.operands.at(first_ + k); }
    Lowerer& l_;
    const Instruction& i_;
    std::size_t first_;
  };
  void set(const Instruction& i, const Src& s) {
    Value v;
    v.leaf = s;
    values_[i.result] = v;
  }
  void instruction(const Instruction& i);
  void ext_inst(const Instruction& i);
  void variable(const Instruction& i);
  void trace(const Instruction& i);
  void image_store(const Instruction& i);
  void image_load(const Instruction& i);
  Src framebuffer_address(Id image, Id coordinate, std::string_view what);
  void ray_query_initialize(const Instruction& i);
  void ray_query_proceed(const Instruction& i);
  void ray_query_type(const Instruction& i);
  bool ray_query_type_test(const Instruction& i);
  Src ray_query_value(const Instruction& i);
  void switch_cases(const Instruction& i);
  void composite_extract(const Instruction& i);
  void composite_insert(const Instruction& i);
  void composite_construct(const Instruction& i);
  void vector_shuffle(const Instruction& i);
  void vector_extract_dynamic(const Instruction& i);
  void matrix_times_scalar(const Instruction& i);
  Src matrix_times(const Value& matrix, const Src& vector);
  void matrix_products(const Instruction& i);
  void same_bits(const Instruction& i);
  const Module& m_;
  const SpirvShader& shader_;
  const LowerContext& ctx_;
  MFunction fn_;
  Builder b_{fn_};
  std::set<TraceForm> traces_;
  bool reads_aperture_ = false;
  std::optional<PayloadType> incoming_type_;
  std::vector<std::pair<TraceForm, PayloadType>> traced_;
  // Every error of the shader is reported, up to kMaxErrors.
  static constexpr std::size_t kMaxErrors = 20;
  std::vector<std::string> errors_;
  std::unordered_set<Id> failed_;  // results of instructions that failed or were skipped
  std::set<std::uint32_t> launch_words_read_;  // byte offsets of launch-block words the shader reads
  std::unordered_map<Id, Value> values_, phis_, homes_;
  std::unordered_map<Id, Pointer> pointers_;
  std::unordered_map<Id, spv::Op> defined_by_;  // for messages
  std::set<int> small_;  // vregs known to hold integers in [0, 2^31)
  // A ray query: its ray (a = origin, t_min; b = direction, t_max) and, once
  // rayQueryProceedEXT traced it, the hit record.
  struct Query {
    bool any_hit = false;
    int a = -1, b = -1, hit = -1;
  };
  std::unordered_map<Id, Query> queries_;
  std::unordered_map<Id, Src> query_types_;
  Query& query(Id pointer_id) {
    const auto it = queries_.find(pointer(pointer_id).variable);
    if (it == queries_.end()) b_.unsupported("a ray query used before rayQueryInitializeEXT in the code's order");
    return it->second;
  }
  const Query& traced(Id pointer_id) {
    const Query& q = query(pointer_id);
    if (q.hit < 0) b_.unsupported("a ray query's intersection read before rayQueryProceedEXT in the code's order");
    return q;
  }
  std::unordered_map<Id, Id> opaque_;
  std::unordered_map<Id, const Block*> blocks_;
  std::unordered_map<Id, Value> block_constants_;
  std::map<std::tuple<int, std::uint32_t, Id>, Src> block_loads_;  // (address, offset, type) loaded in this block
  std::unordered_map<std::uint32_t, int> block_addresses_;
  Id next_block_ = 0;
  Id current_block_ = 0;
  Id incoming_payload_ = 0;
  bool has_calls_ = false;
  // Hit and miss shaders' built-ins, the incoming payload's leaves and the return address.
  Entry entry_;
  std::vector<int> payload_widths_;
  int return_address_ = -1;
};

void Lowerer::trace(const Instruction& i) {
  // OpTraceRayKHR accel flags cullmask sbt_offset sbt_stride miss origin tmin direction tmax payload
  const auto flags = constant_scalar(i.operands[1]);
  const auto sbt_offset = constant_scalar(i.operands[3]);
  const auto miss = constant_scalar(i.operands[5]);
  if (!flags) b_.unsupported("traceRayEXT with ray flags that are not a constant");
  if (!miss) b_.unsupported("traceRayEXT with a miss index that is not a constant");
  TraceForm form;
  form.any_hit = (*flags & static_cast<std::uint32_t>(spv::RayFlagsMask::TerminateOnFirstHitKHR)) != 0;
  form.skip_closest = (*flags & static_cast<std::uint32_t>(spv::RayFlagsMask::SkipClosestHitShaderKHR)) != 0;
  const std::uint32_t unsupported_flags =
      static_cast<std::uint32_t>(spv::RayFlagsMask::CullBackFacingTrianglesKHR) |
      static_cast<std::uint32_t>(spv::RayFlagsMask::CullFrontFacingTrianglesKHR) |
      static_cast<std::uint32_t>(spv::RayFlagsMask::CullOpaqueKHR) |
      static_cast<std::uint32_t>(spv::RayFlagsMask::CullNoOpaqueKHR);
  if (*flags & unsupported_flags) b_.unsupported("traceRayEXT with a face or opacity culling flag");
  if (!form.skip_closest && (!sbt_offset || *sbt_offset != 0)) {
    b_.unsupported("traceRayEXT with an sbtRecordOffset other than 0 (the hit shader is the material's)");
  }
  if (static_cast<int>(*miss) >= ctx_.miss_shaders) {
    if (ctx_.miss_shaders > 0 || *miss != 0) {
      b_.fail(b_.where, fmt::format("traceRayEXT names miss shader {}, but the firmware has {} (the .rmiss files "
                                    "in the order given)",
                                    *miss, ctx_.miss_shaders));
    }
    form.miss = -1;
  } else {
    form.miss = static_cast<int>(*miss);
  }
  traces_.insert(form);

  const Src origin = scalar_or_vector(i.operands[6]), tmin = scalar_or_vector(i.operands[7]);
  const Src direction = scalar_or_vector(i.operands[8]), tmax = scalar_or_vector(i.operands[9]);
  const std::vector<int> ray = set_ray(b_, origin, tmin, direction, tmax, entry_.level);
  // The payload: copied into its registers, and back after the call.
  const Id payload_var = i.operands[10];
  const Pointer p = pointer(payload_var);
  if (p.where != Pointer::Where::kRegisters) b_.unsupported("a payload that is not a rayPayloadEXT variable");
  std::vector<Src> home;
  leaves(homes_.at(payload_var), home);
  const std::vector<int> widths = payload_widths(p.type);
  traced_.emplace_back(form, payload_of(p.type, fmt::format("{}:{}: traceRayEXT's payload", b_.where.file.empty()
                                                                                              ? shader_.file.string()
                                                                                              : b_.where.file,
                                                                b_.where.line)));
  call_trace_routine(b_, form, ray, widths, home, ctx_.registers);
}

// The framebuffer's address of the pixel at `coordinate` of `image`, which must be the
// framebuffer: framebuffer + (y * width + x) * 16. The device faults on another pixel
// than the thread's own, for loads and stores alike.
Src Lowerer::framebuffer_address(Id image, Id coordinate, std::string_view what) {
  const auto img = opaque_.find(image);
  const Id var = img == opaque_.end() ? 0 : img->second;
  if (m_.decoration(var).binding.value_or(~0u) != spec::kShaderFramebufferBinding) {
    b_.fail(b_.where, fmt::format("{} of an image that is not the framebuffer (binding {})", what,
                                  spec::kShaderFramebufferBinding));
  }
  const Src coord = scalar_or_vector(coordinate);
  const Src base = launch_base();
  MInst l;
  l.op = Opcode::kLd1;
  l.dst = b_.vreg(2);
  l.dst_comps = 0b01;
  l.fresh = true;
  l.srcs = {base};
  l.imm = Imm::integer(mm::kLaunchFramebufferAt);
  const int fbw = l.dst;
  b_.push(std::move(l));
  b_.op_into(fbw, 0b10, Opcode::kLd1, {base}, Imm::integer(mm::kLaunchWidthAt));  // lane x is written above
  Src index = b_.op(Opcode::kImul, 1, {component(coord, 1), component(whole(fbw, 2), 1)});
  index = b_.op(Opcode::kIadd, 1, {index, component(coord, 0)});
  index = b_.op(Opcode::kShli, 1, {index}, Imm::integer(std::countr_zero(mm::kFramebufferBytesPerPixel)));
  return b_.op(Opcode::kIadd, 1, {index, component(whole(fbw, 2), 0)});
}

// OpImageRead image coordinate: the thread's own framebuffer pixel as it is now (zero
// before the frame's first imageStore to it).
void Lowerer::image_load(const Instruction& i) {
  if (width_of(i.type) != 4) b_.unsupported("an imageLoad of other than 4 components");
  const Src address = framebuffer_address(i.operands[0], i.operands[1], "imageLoad");
  Value v;
  v.leaf = b_.op(Opcode::kLdf, 4, {address}, Imm::integer(0));
  values_[i.result] = v;
}

void Lowerer::image_store(const Instruction& i) {
  // OpImageWrite image coordinate texel.
  Src texel = scalar_or_vector(i.operands[2]);
  if (texel.n != 4) b_.unsupported("an imageStore of other than 4 components");
  const Src address = framebuffer_address(i.operands[0], i.operands[1], "imageStore");
  // st stores lanes in place: the texel must sit in lanes x..w in order.
  if (texel.comp != std::array<std::uint8_t, 4>{0, 1, 2, 3} || texel.neg || texel.abs) {
    texel = b_.op(Opcode::kMov, 4, {texel});
  }
  MInst s;
  s.op = Opcode::kSt;
  s.srcs = {address, texel};
  s.imm = Imm::integer(0);
  b_.push(std::move(s));
}

void Lowerer::instruction(const Instruction& i) {
  using spv::Op;
  const Id from = current_block_;
  switch (i.op) {
    case Op::OpLine:
    case Op::OpNoLine:
    case Op::OpSelectionMerge:  // the block order keeps the structure
    case Op::OpLoopMerge: return;
    case Op::OpPhi: values_[i.result] = phi(i); return;
    case Op::OpExtInst: ext_inst(i); return;
    // ---- memory and pointers
    case Op::OpVariable: variable(i); return;
    case Op::OpLoad: load(i); return;
    case Op::OpStore: store(i); return;
    case Op::OpAccessChain:
    case Op::OpInBoundsAccessChain: access_chain(i); return;
    case Op::OpImageWrite: image_store(i); return;
    case Op::OpImageRead: image_load(i); return;
    // ---- rays
    case Op::OpTraceRayKHR: trace(i); return;
    case Op::OpRayQueryInitializeKHR: ray_query_initialize(i); return;
    case Op::OpRayQueryProceedKHR: ray_query_proceed(i); return;
    case Op::OpRayQueryGetIntersectionTypeKHR: ray_query_type(i); return;
    case Op::OpRayQueryGetIntersectionTKHR:
    case Op::OpRayQueryGetIntersectionPrimitiveIndexKHR:
    case Op::OpRayQueryGetIntersectionBarycentricsKHR:
    case Op::OpRayQueryGetWorldRayOriginKHR:
    case Op::OpRayQueryGetWorldRayDirectionKHR:
    case Op::OpRayQueryGetRayTMinKHR: set(i, ray_query_value(i)); return;
    case Op::OpRayQueryTerminateKHR: return;
    // ---- control flow
    case Op::OpBranch: jump_to(from, i.operands[0]); return;
    case Op::OpBranchConditional:
      conditional(from, scalar_or_vector(i.operands[0]), i.operands[1], i.operands[2]);
      return;
    case Op::OpSwitch: switch_cases(i); return;
    case Op::OpReturn:
    case Op::OpUnreachable: function_return(); return;
    case Op::OpReturnValue: b_.unsupported("a function returning a value outside the entry point");
    case Op::OpKill:
    case Op::OpTerminateRayKHR:
    case Op::OpIgnoreIntersectionKHR: b_.unsupported(glsl_spelling(i.op));
    // ---- composites
    case Op::OpCompositeExtract: composite_extract(i); return;
    case Op::OpCompositeInsert: composite_insert(i); return;
    case Op::OpCompositeConstruct: composite_construct(i); return;
    case Op::OpVectorShuffle: vector_shuffle(i); return;
    case Op::OpVectorExtractDynamic: vector_extract_dynamic(i); return;
    case Op::OpMatrixTimesScalar: matrix_times_scalar(i); return;
    case Op::OpMatrixTimesVector:
    case Op::OpVectorTimesMatrix:
    case Op::OpMatrixTimesMatrix: matrix_products(i); return;
    case Op::OpCopyObject:
    case Op::OpCopyLogical:  // a buffer's struct as a plain one: the same values
    case Op::OpBitcast:
    case Op::OpSConvert:
    case Op::OpUConvert:
    case Op::OpFConvert: same_bits(i); return;
    case Op::OpUndef: values_[i.result] = zero(i.type); return;
    case Op::OpIEqual:
    case Op::OpINotEqual:
      if (ray_query_type_test(i)) return;
      break;  // selected below
    default: break;
  }
  Args args(*this, i, 0);
  if (const std::optional<Src> s = select(b_, i.op, i.type ? width_of(i.type) : 0, args)) {
    set(i, *s);
    return;
  }
  b_.unsupported(glsl_spelling(i.op));
}

// A function variable SPIRV-Tools did not turn into SSA values: kept in registers.
void Lowerer::variable(const Instruction& i) {
  if (m_.type(m_.type(i.type).element).op == spv::Op::OpTypeRayQueryKHR) {
    Pointer q;
    q.where = Pointer::Where::kOpaque;
    q.variable = i.result;
    pointers_[i.result] = q;
    return;
  }
  Pointer p;
  p.where = Pointer::Where::kRegisters;
  p.variable = i.result;
  p.type = m_.type(i.type).element;
  homes_[i.result] = fresh(p.type);
  if (i.operands.size() > 1) assign(homes_[i.result], value(i.operands[1]));
  pointers_[i.result] = p;
}

// query accel flags cullmask origin tmin direction tmax: the ray, traced at Proceed.
void Lowerer::ray_query_initialize(const Instruction& i) {
  const auto& o = i.operands;
  Query& q = queries_[pointer(o[0]).variable];
  const auto flags = constant_scalar(o[2]);
  if (!flags) b_.unsupported("rayQueryInitializeEXT with ray flags that are not a constant");
  q.any_hit = (*flags & static_cast<std::uint32_t>(spv::RayFlagsMask::TerminateOnFirstHitKHR)) != 0;
  q.a = b_.vreg(4);
  q.b = b_.vreg(4);
  b_.op_into(q.a, 0b0111, Opcode::kMov, {scalar_or_vector(o[4])}, {}, true);
  b_.op_into(q.a, 0b1000, Opcode::kMov, {scalar_or_vector(o[5])});
  b_.op_into(q.b, 0b0111, Opcode::kMov, {scalar_or_vector(o[6])}, {}, true);
  b_.op_into(q.b, 0b1000, Opcode::kMov, {scalar_or_vector(o[7])});
  q.hit = -1;
}

// The traversal unit commits the closest (or first) opaque triangle: nothing is left to
// proceed with afterwards.
void Lowerer::ray_query_proceed(const Instruction& i) {
  Query& q = query(i.operands[0]);
  if (q.hit < 0) q.hit = b_.vreg(4);
  MInst t;
  t.op = q.any_hit ? Opcode::kTracea : Opcode::kTrace;
  t.dst = q.hit;
  t.srcs = {whole(q.a, 4), whole(q.b, 4)};
  b_.push(std::move(t));
  set(i, b_.op(Opcode::kLi, 1, {}, Imm::integer(0)));
}

// Committed: 0 none, 1 triangle. A miss's primitive is 0xffffffff, a hit's below 2^31.
void Lowerer::ray_query_type(const Instruction& i) {
  const Query& q = traced(i.operands[0]);
  if (constant_scalar(i.operands[1]).value_or(0) != 1) b_.unsupported("a ray query's candidate intersection");
  const Src w = component(whole(q.hit, 4), 3);
  set(i, b_.op(Opcode::kXori, 1, {b_.op(Opcode::kShri, 1, {w}, Imm::integer(31))}, Imm::integer(1)));
  query_types_[i.result] = w;
}

// A ray query's committed type against 0 (none) or 1: the miss mask straight from the
// primitive's top bit. False if `i` compares something else.
bool Lowerer::ray_query_type_test(const Instruction& i) {
  const auto& o = i.operands;
  for (int k = 0; k < 2; ++k) {
    const auto t = query_types_.find(o[static_cast<std::size_t>(k)]);
    const auto c = constant_scalar(o[static_cast<std::size_t>(1 - k)]);
    if (t == query_types_.end() || !c || *c > 1) continue;
    const bool miss_mask = (i.op == spv::Op::OpIEqual) == (*c == 0);
    const Src m = b_.op(Opcode::kSrai, 1, {t->second}, Imm::integer(31));
    set(i, miss_mask ? m : b_.not_of(m));
    return true;
  }
  return false;
}

// The ray (origin, t_min; direction, t_max) and the hit record (t, u, v, primitive).
Src Lowerer::ray_query_value(const Instruction& i) {
  const Id q = i.operands[0];
  switch (i.op) {
    case spv::Op::OpRayQueryGetIntersectionTKHR: return component(whole(traced(q).hit, 4), 0);
    case spv::Op::OpRayQueryGetIntersectionPrimitiveIndexKHR: return component(whole(traced(q).hit, 4), 3);
    case spv::Op::OpRayQueryGetIntersectionBarycentricsKHR: {
      Src s = whole(traced(q).hit, 4);
      s.comp = {1, 2, 0, 0};
      s.n = 2;
      return s;
    }
    case spv::Op::OpRayQueryGetWorldRayOriginKHR: return whole(query(q).a, 3);
    case spv::Op::OpRayQueryGetWorldRayDirectionKHR: return whole(query(q).b, 3);
    default: return component(whole(query(q).a, 4), 3);  // t_min
  }
}

// One test per case, in order: not this case, on to the next test; this case, through
// its own phi copies.
void Lowerer::switch_cases(const Instruction& i) {
  const auto& o = i.operands;
  const Id from = current_block_;
  const Src sel = scalar_or_vector(o[0]);
  for (std::size_t k = 2; k + 1 < o.size(); k += 2) {
    const Src c = b_.op(Opcode::kLi, 1, {}, Imm::bits(o[k]));
    const Src eq = b_.op(Opcode::kIeq, 1, {sel, c});
    const std::string tramp = fmt::format(".{}_s{}_{}", fn_.label, from, k);
    b_.cond_branch(false, eq, tramp);
    jump_to(from, o[k + 1]);
    b_.label(tramp);
    block_constants_.clear();
    block_addresses_.clear();
    block_loads_.clear();
  }
  jump_to(from, o[1]);
}

// Into a buffer's record the member stays lazy: loaded where it is used.
void Lowerer::composite_extract(const Instruction& i) {
  const auto& o = i.operands;
  Value v = value(o[0]);
  for (std::size_t k = 1; k < o.size(); ++k) {
    if (v.lazy) v = expand(v);
    if (v.aggregate) {
      Value member = v.members.at(o[k]);  // a copy first: v's members die in the assignment
      v = std::move(member);
    } else {
      v.leaf = component(v.leaf, static_cast<int>(o[k]));
    }
  }
  values_[i.result] = v;
}

// object composite indexes...: values are SSA, so the members an insert leaves alone
// are shared; only the changed leaf is new.
void Lowerer::composite_insert(const Instruction& i) {
  const auto& o = i.operands;
  Value v = expand(value(o[1]));
  Value* at = &v;
  std::size_t k = 2;
  for (; k < o.size(); ++k) {
    *at = expand(*at);
    if (!at->aggregate) break;
    at = &at->members.at(o[k]);
  }
  const Value obj = value(o[0]);
  if (k < o.size()) {
    *at = expand(*at);
    const Src old = at->leaf;
    const int d = b_.vreg(old.n);
    b_.op_into(d, 0, Opcode::kMov, {old});
    b_.op_into(d, static_cast<std::uint8_t>(1u << o[k]), Opcode::kMov, {concrete(obj).leaf});
    at->leaf = whole(d, old.n);
  } else {
    *at = obj;
  }
  values_[i.result] = v;
}

void Lowerer::composite_construct(const Instruction& i) {
  const auto& o = i.operands;
  const int n = width_of(i.type);
  if (n == 0) {
    Value v;
    v.aggregate = true;
    for (const Id part : o) v.members.push_back(value(part));
    values_[i.result] = v;
    return;
  }
  // Components of one vreg (a splat, a reordering) are a view of it: no instruction.
  {
    Src view;
    bool ok = true;
    int at = 0;
    for (const Id part : o) {
      if (constant_scalar(part) && m_.constants.count(part)) {
        ok = false;
        break;
      }
      const Src t = scalar_or_vector(part);
      if (at == 0) view = t;
      if (t.v != view.v || t.neg != view.neg || t.abs != view.abs || at + t.n > 4) {
        ok = false;
        break;
      }
      for (int j = 0; j < t.n; ++j) view.comp[static_cast<std::size_t>(at + j)] = t.comp[static_cast<std::size_t>(j)];
      at += t.n;
    }
    if (ok && at == n) {
      view.n = n;
      set(i, view);
      return;
    }
  }
  const int d = b_.vreg(n);
  int at = 0;
  bool first = true;
  for (std::size_t k = 0; k < o.size();) {
    const std::uint8_t full = static_cast<std::uint8_t>((1u << n) - 1);
    if (const auto c = constant_scalar(o[k]); c && width_of(m_.constants.at(o[k]).type) == 1) {
      // a constant goes straight into its lane
      std::uint32_t bits = *c;
      if (m_.is_bool(m_.constants.at(o[k]).type)) bits = bits ? 0xffffffffu : 0u;
      const std::uint8_t mask = static_cast<std::uint8_t>(1u << at);
      const bool is_float = m_.is_float(m_.constants.at(o[k]).type);
      b_.op_into(d, mask == full ? 0 : mask, is_float ? Opcode::kLif : Opcode::kLi, {}, Imm::lane(bits, is_float),
                 first);
      first = false;
      ++at;
      ++k;
      continue;
    }
    Src s = scalar_or_vector(o[k]);
    ++k;
    // consecutive scalars from one vreg move together
    while (k < o.size() && s.n < 4 && !constant_scalar(o[k])) {
      const Src t = scalar_or_vector(o[k]);
      if (t.n != 1 || t.v != s.v || t.neg != s.neg || t.abs != s.abs) break;
      s.comp[static_cast<std::size_t>(s.n)] = t.comp[0];
      ++s.n;
      ++k;
    }
    const std::uint8_t mask = static_cast<std::uint8_t>(((1u << s.n) - 1) << at);
    b_.op_into(d, mask == full ? 0 : mask, Opcode::kMov, {s}, {}, first);
    first = false;
    at += s.n;
  }
  set(i, whole(d, n));
}

void Lowerer::vector_shuffle(const Instruction& i) {
  const auto& o = i.operands;
  const int n = width_of(i.type);
  const Src a = scalar_or_vector(o[0]), b = scalar_or_vector(o[1]);
  bool only_a = true;
  for (std::size_t k = 2; k < o.size(); ++k) {
    if (o[k] != 0xffffffffu && static_cast<int>(o[k]) >= a.n) only_a = false;
  }
  if (only_a) {
    Src s = a;
    for (std::size_t k = 2; k < o.size(); ++k) s.comp[k - 2] = a.comp[o[k] == 0xffffffffu ? 0 : o[k]];
    s.n = n;
    set(i, s);
    return;
  }
  const int d = b_.vreg(n);
  for (std::size_t k = 2; k < o.size(); ++k) {
    const std::uint32_t c = o[k] == 0xffffffffu ? 0 : o[k];
    const Src from =
        static_cast<int>(c) < a.n ? component(a, static_cast<int>(c)) : component(b, static_cast<int>(c) - a.n);
    b_.op_into(d, static_cast<std::uint8_t>(1u << (k - 2)), Opcode::kMov, {from}, {}, k == 2);
  }
  set(i, whole(d, n));
}

void Lowerer::vector_extract_dynamic(const Instruction& i) {
  const Src v = scalar_or_vector(i.operands[0]);
  const Src idx = scalar_or_vector(i.operands[1]);
  Src r = component(v, 0);
  for (int k = 1; k < v.n; ++k) {
    const Src is_k = b_.op(Opcode::kIeq, 1, {idx, b_.op(Opcode::kLi, 1, {}, Imm::integer(k))});
    r = b_.select(is_k, component(v, k), r, 1);
  }
  set(i, r);
}

void Lowerer::matrix_times_scalar(const Instruction& i) {
  Value m = concrete(value(i.operands[0]));
  const Src s = scalar_or_vector(i.operands[1]);
  Value r;
  r.aggregate = true;
  for (const Value& col : m.members) {
    Value c;
    c.leaf = b_.op(Opcode::kMul, col.leaf.n, {col.leaf, broadcast(s, col.leaf.n)});
    r.members.push_back(c);
  }
  values_[i.result] = r;
}

// M v: the columns of M, each times its component of v, summed (mul, then mad in column
// order: the rounding of GLSL's sum from the first column on).
Src Lowerer::matrix_times(const Value& matrix, const Src& vector) {
  Src sum;
  for (std::size_t j = 0; j < matrix.members.size(); ++j) {
    const Src column = concrete(matrix.members[j]).leaf;
    const Src v = broadcast(component(vector, static_cast<int>(j)), column.n);
    sum = j == 0 ? b_.op(Opcode::kMul, column.n, {column, v}) : b_.op(Opcode::kMad, column.n, {column, v, sum});
  }
  return sum;
}

// matrix * vector, vector * matrix (each result component a dot product of v with a
// column) and matrix * matrix (M times each column of the right one).
void Lowerer::matrix_products(const Instruction& i) {
  const auto& o = i.operands;
  Value r;
  if (i.op == spv::Op::OpMatrixTimesVector) {
    r.leaf = matrix_times(concrete(value(o[0])), scalar_or_vector(o[1]));
  } else if (i.op == spv::Op::OpMatrixTimesMatrix) {
    const Value left = concrete(value(o[0])), right = concrete(value(o[1]));
    r.aggregate = true;
    for (const Value& column : right.members) {
      Value c;
      c.leaf = matrix_times(left, concrete(column).leaf);
      r.members.push_back(c);
    }
  } else {
    const Src v = scalar_or_vector(o[0]);
    const Value m = concrete(value(o[1]));
    const int n = static_cast<int>(m.members.size());
    const int d = b_.vreg(n);
    for (int j = 0; j < n; ++j) {
      const Src column = concrete(m.members[static_cast<std::size_t>(j)]).leaf;
      Src dot = b_.op(Opcode::kMul, 1, {component(v, 0), component(column, 0)});
      for (int k = 1; k < column.n; ++k) {
        dot = b_.op(Opcode::kMad, 1, {component(v, k), component(column, k), dot});
      }
      b_.op_into(d, n == 1 ? 0 : static_cast<std::uint8_t>(1u << j), Opcode::kMov, {dot}, {}, j == 0);
    }
    r.leaf = whole(d, n);
  }
  values_[i.result] = r;
}

// Copies, a bitcast between types of one shape, and conversions between 32-bit types
// (the only width there is): the operand's value.
void Lowerer::same_bits(const Instruction& i) {
  if (i.op == spv::Op::OpBitcast && width_of(i.type) != scalar_or_vector(i.operands[0]).n) {
    b_.unsupported("a bitcast between types of different component counts");
  }
  const bool conversion =
      i.op == spv::Op::OpSConvert || i.op == spv::Op::OpUConvert || i.op == spv::Op::OpFConvert;
  if (conversion && m_.type(m_.scalar_of(i.type)).count != 32) b_.unsupported("a conversion to other than 32 bits");
  values_[i.result] = value(i.operands[0]);
}

void Lowerer::ext_inst(const Instruction& i) {
  const auto& o = i.operands;
  if (o.size() < 2 || o[0] != m_.glsl_std_450) b_.unsupported("an extended instruction set other than GLSL.std.450");
  Args args(*this, i, 2);
  set(i, select_glsl_std_450(b_, o[1], width_of(i.type), args));
}

}  // namespace

Lowered lower(const Module& module, const SpirvShader& shader, const LowerContext& context) {
  return Lowerer(module, shader, context).run();
}

}  // namespace rpu::cc
