#include "asm/expression.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace rpu::assembler {

namespace {

// Binary operators by C precedence, loosest first: | ^ & (<< >>) (+ -) (* / %).
struct BinaryOp {
  std::string_view text;
  ExprOp op;
  int precedence;
};
constexpr BinaryOp kBinary[] = {
    {"|", ExprOp::kOr, 0},   {"^", ExprOp::kXor, 1},  {"&", ExprOp::kAnd, 2},  {"<<", ExprOp::kShl, 3},
    {">>", ExprOp::kShr, 3}, {"+", ExprOp::kAdd, 4},  {"-", ExprOp::kSub, 4},  {"*", ExprOp::kMul, 5},
    {"/", ExprOp::kDiv, 5},  {"%", ExprOp::kRem, 5},
};
constexpr int kTightest = 5;

const BinaryOp* binary_op(const Token& t) {
  if (t.kind != TokenKind::kPunct) return nullptr;
  for (const BinaryOp& b : kBinary) {
    if (t.text == b.text) return &b;
  }
  return nullptr;
}

class Parser {
 public:
  Parser(const std::vector<Token>& tokens, std::size_t& pos, std::size_t end, ExprPool& pool, ExprError& error)
      : tokens_(tokens), pos_(pos), end_(end), pool_(pool), error_(error) {}

  std::optional<int> binary(int precedence) {
    if (precedence > kTightest) return unary();
    std::optional<int> lhs = binary(precedence + 1);
    while (lhs) {
      const BinaryOp* op = binary_op(peek());
      if (!op || op->precedence != precedence) break;
      const int column = peek().column;
      ++pos_;
      const std::optional<int> rhs = binary(precedence + 1);
      if (!rhs) return std::nullopt;
      lhs = node(op->op, column, *lhs, *rhs);
    }
    return lhs;
  }

 private:
  // Counts the unary operators and parentheses being parsed, which bounds the
  // recursion before any node exists whose depth could be measured.
  struct Nest {
    explicit Nest(int& n) : n_(++n) {}
    ~Nest() { --n_; }
    Nest(const Nest&) = delete;
    Nest& operator=(const Nest&) = delete;
    int& n_;
  };

  const Token& peek() const { return pos_ < end_ ? tokens_[pos_] : tokens_[end_]; }

  std::optional<int> fail(const Token& at, std::string_view expected) {
    error_ = {at.column, fmt::format("{}, expected {}", describe(at), expected)};
    return std::nullopt;
  }

  std::optional<int> node(ExprOp op, int column, int lhs = -1, int rhs = -1) {
    ExprNode n;
    n.op = op;
    n.column = column;
    n.lhs = lhs;
    n.rhs = rhs;
    n.depth = 1 + std::max(lhs >= 0 ? pool_[lhs].depth : 0, rhs >= 0 ? pool_[rhs].depth : 0);
    if (n.depth > kMaxExprDepth) {
      error_ = {column, fmt::format("expression nested {} deep, expected at most {} levels", n.depth,
                                    kMaxExprDepth)};
      return std::nullopt;
    }
    pool_.push_back(std::move(n));
    return static_cast<int>(pool_.size() - 1);
  }

  std::optional<int> unary() {
    const Nest nest(nesting_);
    const Token& t = peek();
    if (nesting_ > kMaxExprDepth) return fail(t, fmt::format("at most {} nested levels", kMaxExprDepth));
    ExprOp op{};
    if (t.is("-")) {
      op = ExprOp::kNeg;
    } else if (t.is("~")) {
      op = ExprOp::kNot;
    } else if (t.is("+")) {
      op = ExprOp::kPlus;
    } else {
      return primary();
    }
    const int column = t.column;
    ++pos_;
    const std::optional<int> operand = unary();
    if (!operand) return std::nullopt;
    return node(op, column, *operand);
  }

  std::optional<int> primary() {
    const Token& t = peek();
    switch (t.kind) {
      case TokenKind::kNumber: {
        const std::optional<std::int64_t> v = parse_integer(t.text);
        if (!v) {
          if (t.text.find_first_of(".eE") != std::string::npos && t.text.find_first_of("xX") == std::string::npos) {
            return fail(t, "an integer (float literals only go in lif and .float)");
          }
          return fail(t, "an integer that fits 64 bits");
        }
        const int column = t.column;
        ++pos_;
        const std::optional<int> n = node(ExprOp::kNumber, column);
        if (n) pool_[static_cast<std::size_t>(*n)].value = *v;
        return n;
      }
      case TokenKind::kIdent: {
        if (is_register_name(t.text)) return fail(t, "an integer expression, not a register");
        const int column = t.column;
        std::string symbol = t.text;
        ++pos_;
        const std::optional<int> n = node(ExprOp::kSymbol, column);
        if (n) pool_[static_cast<std::size_t>(*n)].symbol = std::move(symbol);
        return n;
      }
      default:
        if (t.is("(")) {
          ++pos_;
          const std::optional<int> inner = binary(0);
          if (!inner) return std::nullopt;
          if (!peek().is(")")) return fail(peek(), "')' or an operator");
          ++pos_;
          return inner;
        }
        return fail(t, "a number, symbol, unary operator or '('");
    }
  }

  int nesting_ = 0;
  const std::vector<Token>& tokens_;
  std::size_t& pos_;
  std::size_t end_;
  ExprPool& pool_;
  ExprError& error_;
};

}  // namespace

std::optional<int> parse_expression(const std::vector<Token>& tokens, std::size_t& pos, std::size_t end,
                                    ExprPool& pool, ExprError& error) {
  return Parser(tokens, pos, end, pool, error).binary(0);
}

std::optional<std::int64_t> parse_integer(std::string_view text) {
  unsigned base = 10;
  if (text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X')) {
    base = 16;
    text.remove_prefix(2);
  } else if (text.size() > 2 && text[0] == '0' && (text[1] == 'b' || text[1] == 'B')) {
    base = 2;
    text.remove_prefix(2);
  }
  if (text.empty()) return std::nullopt;
  std::uint64_t value = 0;
  for (const char c : text) {
    unsigned digit = 0;
    if (c >= '0' && c <= '9') {
      digit = static_cast<unsigned>(c - '0');
    } else if (c >= 'a' && c <= 'f') {
      digit = static_cast<unsigned>(c - 'a' + 10);
    } else if (c >= 'A' && c <= 'F') {
      digit = static_cast<unsigned>(c - 'A' + 10);
    } else {
      return std::nullopt;
    }
    if (digit >= base) return std::nullopt;
    if (value > (UINT64_MAX - digit) / base) return std::nullopt;
    value = value * base + digit;
  }
  return static_cast<std::int64_t>(value);
}

bool is_register_name(std::string_view ident) {
  const std::string_view name = ident.substr(0, ident.find('.'));
  if (name.size() < 2 || name[0] != 'r') return false;
  for (const char c : name.substr(1)) {
    if (c < '0' || c > '9') return false;
  }
  return true;
}

std::optional<std::int64_t> evaluate(const ExprPool& pool, int root, const Location& where, SymbolValues& symbols) {
  const ExprNode& n = pool[static_cast<std::size_t>(root)];
  const Location at{where.file, where.line, n.column};
  if (n.op == ExprOp::kNumber) return n.value;
  if (n.op == ExprOp::kSymbol) return symbols.value(n.symbol, at);
  const std::optional<std::int64_t> l = evaluate(pool, n.lhs, where, symbols);
  if (!l) return std::nullopt;
  // Wrapping arithmetic through uint64: two's complement without signed overflow.
  const auto a = static_cast<std::uint64_t>(*l);
  switch (n.op) {
    case ExprOp::kNeg: return static_cast<std::int64_t>(0 - a);
    case ExprOp::kNot: return static_cast<std::int64_t>(~a);
    case ExprOp::kPlus: return *l;
    default: break;
  }
  const std::optional<std::int64_t> r = evaluate(pool, n.rhs, where, symbols);
  if (!r) return std::nullopt;
  const auto b = static_cast<std::uint64_t>(*r);
  switch (n.op) {
    case ExprOp::kMul: return static_cast<std::int64_t>(a * b);
    case ExprOp::kAdd: return static_cast<std::int64_t>(a + b);
    case ExprOp::kSub: return static_cast<std::int64_t>(a - b);
    case ExprOp::kAnd: return static_cast<std::int64_t>(a & b);
    case ExprOp::kXor: return static_cast<std::int64_t>(a ^ b);
    case ExprOp::kOr: return static_cast<std::int64_t>(a | b);
    case ExprOp::kDiv:
    case ExprOp::kRem:
      if (*r == 0) {
        symbols.error(at, fmt::format("division by zero, expected a nonzero divisor"));
        return std::nullopt;
      }
      // INT64_MIN / -1 overflows in C++; in two's complement it wraps to INT64_MIN, rem 0.
      if (*r == -1) return n.op == ExprOp::kDiv ? static_cast<std::int64_t>(0 - a) : 0;
      return n.op == ExprOp::kDiv ? *l / *r : *l % *r;
    case ExprOp::kShl:
    case ExprOp::kShr:
      if (*r < 0 || *r > 63) {
        symbols.error(at, fmt::format("shift by {}, expected a count from 0 to 63", *r));
        return std::nullopt;
      }
      // >> is arithmetic, as C++20 defines it for signed values.
      return n.op == ExprOp::kShl ? static_cast<std::int64_t>(a << *r) : *l >> *r;
    default: return std::nullopt;
  }
}

}  // namespace rpu::assembler
