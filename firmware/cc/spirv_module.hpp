// A SPIR-V module as the back end reads it: types, constants, global variables with
// their decorations, and the entry point's functions as blocks of instructions, each
// instruction with the source file and line of the OpLine before it.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include <spirv/unified1/spirv.hpp11>

namespace rpu::cc {

using Id = std::uint32_t;

struct SourceLocation {
  std::string file;
  int line = 0;  // 0: unknown
};

struct Instruction {
  spv::Op op = spv::Op::OpNop;
  Id type = 0;                     // result type, 0 if none
  Id result = 0;                   // result id, 0 if none
  std::vector<std::uint32_t> operands;  // the words after type and result
  SourceLocation where;
};

struct Block {
  Id label = 0;
  std::vector<Instruction> body;  // OpPhi first, then the rest; the terminator last
};

struct Function {
  Id id = 0;
  std::string name;
  std::vector<Block> blocks;  // in the module's order: every block after its dominator
};

struct Type {
  spv::Op op = spv::Op::OpTypeVoid;
  Id element = 0;        // vector, matrix, array, runtime array, pointer: the element or pointee
  std::uint32_t count = 0;  // vector and matrix: components or columns; array: length; int/float: width
  bool is_signed = false;
  std::vector<Id> members;  // struct
  spv::StorageClass storage = spv::StorageClass::Generic;  // pointer
};

struct Constant {
  Id type = 0;
  bool composite = false;
  std::uint32_t bits = 0;          // scalar: the 32 bits (bool: 0 or 1)
  std::vector<Id> constituents;    // composite
  bool null = false;               // OpConstantNull
  bool spec = false;               // OpSpecConstant, OpSpecConstantTrue/False: its default
};

struct Variable {
  Id type = 0;  // the pointer type
  spv::StorageClass storage = spv::StorageClass::Generic;
  std::optional<Id> initializer;
};

struct Decorations {
  std::optional<spv::BuiltIn> builtin;
  std::optional<std::uint32_t> binding, set, offset, array_stride, spec_id;
};

class Module {
 public:
  // Reads a SPIR-V binary; throws rpu::Error naming the word offset of a malformed instruction.
  static Module parse(std::span<const std::uint32_t> words, const std::string& file);

  spv::ExecutionModel model = spv::ExecutionModel::Max;
  Id entry = 0;
  Id glsl_std_450 = 0;  // the OpExtInstImport id of GLSL.std.450, 0 if none
  std::unordered_map<Id, Type> types;
  std::unordered_map<Id, Constant> constants;
  std::unordered_map<Id, Variable> variables;
  std::unordered_map<Id, Decorations> decorations;
  std::map<std::pair<Id, std::uint32_t>, Decorations> member_decorations;
  std::unordered_map<Id, std::string> names, strings;
  std::vector<Function> functions;

  const Type& type(Id id) const;
  const Decorations& decoration(Id id) const;
  const Decorations& member_decoration(Id struct_type, std::uint32_t member) const;
  // Vector components (1 for a scalar), 0 for anything else.
  std::uint32_t components(Id type_id) const;
  // The scalar type of a scalar or vector type.
  Id scalar_of(Id type_id) const;
  bool is_float(Id type_id) const;  // a float scalar or vector
  bool is_bool(Id type_id) const;
  // A type as GLSL spells it, for messages: float, uvec3, mat4, vec2[3], a struct by its
  // name (struct Payload) or its members, an opaque type by what it holds (sampler2D).
  std::string glsl_type(Id type_id) const;
};

}  // namespace rpu::cc
