#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "asm/lexer.hpp"

// Integer expressions of the assembler: C operators and precedence, evaluated in 64-bit
// two's complement (wrapping), symbols resolved late so that labels and .equ constants
// may be used before they are defined.
namespace rpu::assembler {

// Where in the sources: file is an index into the assembler's file names.
struct Location {
  int file = 0;
  int line = 0;
  int column = 0;
};

enum class ExprOp : unsigned char {
  kNumber, kSymbol, kNeg, kNot, kPlus,
  kMul, kDiv, kRem, kAdd, kSub, kShl, kShr, kAnd, kXor, kOr,
};

struct ExprNode {
  ExprOp op = ExprOp::kNumber;
  int column = 0;
  int depth = 1;  // of the tree below and including this node
  int lhs = -1;
  int rhs = -1;
  std::int64_t value = 0;  // kNumber
  std::string symbol;      // kSymbol
};

// Deeper trees are refused so that parsing and evaluation (both recursive) stay far
// from the stack limit on any input; real expressions are a few levels deep.
inline constexpr int kMaxExprDepth = 200;

using ExprPool = std::vector<ExprNode>;

struct ExprError {
  int column = 0;
  std::string message;
};

// Parses tokens[pos, end) as far as an expression goes, appending nodes to pool;
// returns the root node, or nullopt with `error` set. pos is left after the expression.
std::optional<int> parse_expression(const std::vector<Token>& tokens, std::size_t& pos, std::size_t end,
                                    ExprPool& pool, ExprError& error);

// Integer literal (decimal, 0x, 0b) as 64-bit two's complement bits, or nullopt if it
// does not fit 64 bits or is not an integer.
std::optional<std::int64_t> parse_integer(std::string_view text);

// "r0".."r99..." with an optional ".suffix": names the assembler keeps for registers
// (never symbols, so that `li r1, r2` is an error rather than an undefined symbol).
bool is_register_name(std::string_view ident);

class SymbolValues {
 public:
  virtual ~SymbolValues() = default;
  // The value of `name` used at `where`, or nullopt after reporting why not.
  virtual std::optional<std::int64_t> value(const std::string& name, const Location& where) = 0;
  virtual void error(const Location& where, std::string message) = 0;
};

// Evaluates node `root` of pool; `where` gives file and line (columns come from the
// nodes). nullopt after an error was reported through `symbols`.
std::optional<std::int64_t> evaluate(const ExprPool& pool, int root, const Location& where, SymbolValues& symbols);

}  // namespace rpu::assembler
