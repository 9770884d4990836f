#include "asm/assembler.hpp"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <map>
#include <string_view>
#include <tuple>

#include <fmt/format.h>

#include "asm/expression.hpp"
#include "asm/lexer.hpp"
#include "common/did_you_mean.hpp"
#include "common/error.hpp"
#include "common/input_file.hpp"
#include "isa/instruction.hpp"
#include "rpu/spec.hpp"

namespace rpu::isa {

using assembler::describe;
using assembler::evaluate;
using assembler::ExprError;
using assembler::ExprNode;
using assembler::ExprOp;
using assembler::ExprPool;
using assembler::LexError;
using assembler::Location;
using assembler::printable;
using assembler::Token;
using assembler::TokenKind;

namespace {

namespace si = spec::isa;

constexpr int kMaxErrors = 20;
// Include cycles are found by path; this bounds what a path test cannot see (the same
// file reached through a symlink or an absolute and a relative path).
constexpr std::size_t kMaxIncludeDepth = 32;
// .equ constants that refer to constants: deep chains would recurse without bound.
constexpr std::size_t kMaxConstantChain = 100;
// .data must fit the device's data window, below the stacks.
constexpr std::uint64_t kDataLimit = spec::memory::kDeviceStackBase - spec::memory::kDeviceDataBase;
constexpr int kRegisterCount = 1 << si::kDstField.width;
constexpr std::string_view kLanes = "xyzw";
constexpr std::uint32_t kCanonicalNan = 0x7fc00000;

struct TooManyErrors {};

enum class Section : unsigned char { kText, kData };

std::string_view operand_name(Operand k) {
  switch (k) {
    case Operand::kD: return "d";
    case Operand::kA: return "a";
    case Operand::kB: return "b";
    case Operand::kC: return "c";
    case Operand::kImm: return "imm";
    case Operand::kFimm: return "fimm";
    case Operand::kMem: return "mem";
    case Operand::kTarget: return "target";
    case Operand::kSr: return "sr";
  }
  return "?";
}

// "add d, a, b": how an instruction is written, for operand-count errors.
std::string signature(const InsnSpec& spec) {
  std::string s(spec.mnemonic);
  for (int k = 0; k < spec.operand_count; ++k) {
    s += k == 0 ? " " : ", ";
    s += operand_name(spec.operands[static_cast<std::size_t>(k)]);
  }
  return s;
}

constexpr std::string_view kDirectives[] = {".text",  ".data", ".equ",   ".include", ".word", ".byte",
                                            ".float", ".space", ".align", ".insn",    ".loc"};

const std::map<std::string_view, std::uint32_t>& predefined_symbols() {
  static const auto table = [] {
    std::map<std::string_view, std::uint32_t> t;
    for (const si::AsmSymbol& s : si::kAsmSymbols) t.emplace(s.name, s.value);
    return t;
  }();
  return table;
}

std::string int_text(std::int64_t v) {
  return v >= -65536 && v <= 65536 ? fmt::format("{}", v) : fmt::format("{} ({:#x})", v, static_cast<std::uint64_t>(v));
}

// A parsed instruction operand, values still as expressions.
struct ParsedOperand {
  Operand kind = Operand::kD;
  Location loc;
  std::uint8_t dst = 0;
  std::uint8_t wmask = kAllLanes;
  Source src;
  int expr = -1;           // imm, target, sr given as a number, mem offset (-1: none)
  std::uint32_t bits = 0;  // fimm, or sr given by name
};

enum class StatementKind : unsigned char { kLabel, kInsn, kRawInsn, kWord, kByte, kFloat, kSpace, kAlign };

struct Statement {
  StatementKind kind = StatementKind::kInsn;
  Section section = Section::kText;
  Location loc;
  std::string label;  // kLabel
  const InsnSpec* spec = nullptr;
  std::vector<ParsedOperand> operands;  // kInsn
  std::vector<int> exprs;               // kRawInsn, kWord, kByte, kSpace, kAlign
  std::vector<Location> expr_locs;
  std::vector<std::uint32_t> floats;  // kFloat
  std::uint32_t address = 0;          // after layout: pc, or offset into .data
  std::uint32_t bytes = 0;            // after layout: data bytes
  std::string source_file;            // kInsn, kRawInsn: the line table's line (0: none)
  std::uint32_t source_line = 0;
};

// What a .loc directive set: the source line of the instructions after it in its file.
struct SourceLineSet {
  bool set = false;  // no .loc yet: each instruction's own file:line
  std::string file;
  std::uint32_t line = 0;
};

struct SymbolDef {
  enum class Kind : unsigned char { kCode, kData, kConstant } kind = Kind::kConstant;
  enum class State : unsigned char { kPending, kResolving, kDone, kFailed } state = State::kPending;
  Location loc;
  int expr = -1;         // constants
  bool placed = false;   // labels: layout has given it its address
  std::int64_t value = 0;
};

struct SourceFile {
  std::string name;  // as shown in messages
  std::vector<std::string> lines;
};

// A token range of one line being parsed.
struct Cursor {
  const std::vector<Token>& tokens;
  std::size_t pos;
  std::size_t end;  // tokens[end] is the token after the range (',' or end of line)

  const Token& peek() const { return pos < end ? tokens[pos] : tokens[end]; }
  bool done() const { return pos >= end; }
};

struct RegisterRef {
  std::uint8_t reg = 0;
  bool has_suffix = false;
  std::string suffix;  // after the '.'
  int suffix_column = 0;
};

class Assembler final : public assembler::SymbolValues {
 public:
  explicit Assembler(const SourceLoader& load) : load_(load) {}

  Assembly run(const std::filesystem::path& file) {
    try {
      read_main(file);
      // Statements that failed to parse are left out; the rest still lay out and
      // emit, so that their errors are reported in the same run.
      if (layout()) emit();
    } catch (const TooManyErrors&) {
      errors_.push_back(fmt::format("too many errors, stopped after {}", kMaxErrors));
    }
    if (!errors_.empty()) {
      std::string message;
      for (const std::string& e : errors_) message += (message.empty() ? "" : "\n") + e;
      throw Error(message);
    }
    return std::move(result_);
  }

  std::optional<std::int64_t> value(const std::string& name, const Location& where) override {
    if (const auto p = predefined_symbols().find(name); p != predefined_symbols().end()) return p->second;
    const auto it = symbols_.find(name);
    if (it == symbols_.end()) {
      std::vector<std::string_view> names;
      for (const auto& [n, def] : symbols_) names.push_back(n);
      for (const auto& [n, v] : predefined_symbols()) names.push_back(n);
      error(where, fmt::format("undefined symbol '{}', expected a label, .equ constant or memory-map symbol{}",
                               printable(name), did_you_mean(name, names)));
      return std::nullopt;
    }
    SymbolDef& def = it->second;
    if (def.kind != SymbolDef::Kind::kConstant) {
      if (!def.placed) {
        error(where, fmt::format("label '{}', which is defined later, expected constants or earlier labels "
                                 "(a .space or .align size must be known when layout reaches it)",
                                 printable(name)));
        return std::nullopt;
      }
      return def.value;
    }
    switch (def.state) {
      case SymbolDef::State::kDone: return def.value;
      case SymbolDef::State::kFailed: return std::nullopt;  // already reported
      case SymbolDef::State::kResolving: {
        std::string chain;
        for (const std::string& n : resolving_) chain += (chain.empty() ? "" : " -> ") + n;
        error(where, fmt::format("'{}' defined in terms of itself ({} -> {}), expected a value that does not "
                                 "refer back to it",
                                 printable(name), printable(chain), printable(name)));
        return std::nullopt;
      }
      case SymbolDef::State::kPending: break;
    }
    if (resolving_.size() >= kMaxConstantChain) {
      error(where, fmt::format("constant '{}' at the end of a chain of {} constants, expected at most {}",
                               printable(name), resolving_.size(), kMaxConstantChain));
      return std::nullopt;
    }
    def.state = SymbolDef::State::kResolving;
    resolving_.push_back(name);
    const std::optional<std::int64_t> v = evaluate(pool_, def.expr, def.loc, *this);
    resolving_.pop_back();
    if (v && fit32(*v, def.loc, fmt::format(".equ {}", name))) {
      def.state = SymbolDef::State::kDone;
      def.value = *v;
      return def.value;
    }
    def.state = SymbolDef::State::kFailed;
    return std::nullopt;
  }

  void error(const Location& where, std::string message) override {
    errors_.push_back(fmt::format("{}:{}:{}: error: {}", files_[static_cast<std::size_t>(where.file)].name,
                                  where.line, where.column, message));
    if (errors_.size() >= kMaxErrors) throw TooManyErrors{};
  }

 private:
  // ---- reading: files, lines, statements ---------------------------------------

  void read_main(const std::filesystem::path& file) {
    std::optional<std::string> text = load_(file);
    if (!text) {
      errors_.push_back(fmt::format("{}: error: cannot read the file, expected a readable assembly source",
                                    file.string()));
      return;
    }
    read_text(file, file.string(), *text);
  }

  void read_text(const std::filesystem::path& path, std::string name, const std::string& text) {
    const int index = static_cast<int>(files_.size());
    SourceFile source{std::move(name), {}};
    std::size_t start = 0;
    while (start <= text.size()) {
      std::size_t end = text.find('\n', start);
      if (end == std::string::npos) end = text.size();
      source.lines.emplace_back(text, start, end - start);
      start = end + 1;
    }
    files_.push_back(std::move(source));
    open_.push_back(path.lexically_normal());
    source_lines_.emplace_back();
    const std::size_t lines = files_.back().lines.size();
    for (std::size_t i = 0; i < lines; ++i) read_line(index, static_cast<int>(i) + 1);
    source_lines_.pop_back();
    open_.pop_back();
  }

  Location at(const Location& line, int column) const { return {line.file, line.line, column}; }

  void read_line(int file, int line_number) {
    const Location line{file, line_number, 1};
    // Copy: an .include below appends to files_, which may move the lines.
    const std::string text = files_[static_cast<std::size_t>(file)].lines[static_cast<std::size_t>(line_number - 1)];
    LexError lex_error;
    const std::vector<Token> tokens = assembler::lex_line(text, lex_error);
    if (lex_error.column) {
      error(at(line, lex_error.column), lex_error.message);
      return;
    }
    std::size_t pos = 0;
    while (tokens[pos].kind == TokenKind::kIdent && tokens[pos + 1].is(":")) {
      define_label(tokens[pos], line);
      pos += 2;
    }
    const Token& head = tokens[pos];
    if (head.kind == TokenKind::kEnd) return;
    if (head.kind != TokenKind::kIdent) {
      error(at(line, head.column), fmt::format("{}, expected a label, instruction or directive", describe(head)));
      return;
    }
    Cursor rest{tokens, pos + 1, tokens.size() - 1};
    if (head.text[0] == '.') {
      directive(head, rest, line);
    } else {
      instruction(head, rest, line);
    }
  }

  bool check_new_symbol(const Token& name, const Location& line, std::string_view what) {
    const Location where = at(line, name.column);
    if (assembler::is_register_name(name.text)) {
      error(where, fmt::format("register name '{}' as a {}, expected a name that is not r<number>",
                               printable(name.text), what));
      return false;
    }
    if (predefined_symbols().contains(name.text)) {
      error(where, fmt::format("'{}', a predefined memory-map symbol, as a {}, expected a new name",
                               printable(name.text), what));
      return false;
    }
    if (const auto it = symbols_.find(name.text); it != symbols_.end()) {
      const Location& first = it->second.loc;
      error(where, fmt::format("duplicate symbol '{}' (first defined at {}:{}), expected a new name",
                               printable(name.text), files_[static_cast<std::size_t>(first.file)].name, first.line));
      return false;
    }
    return true;
  }

  void define_label(const Token& name, const Location& line) {
    if (!check_new_symbol(name, line, "label")) return;
    SymbolDef def;
    def.kind = section_ == Section::kText ? SymbolDef::Kind::kCode : SymbolDef::Kind::kData;
    def.loc = at(line, name.column);
    symbols_.emplace(name.text, def);
    Statement s;
    s.kind = StatementKind::kLabel;
    s.section = section_;
    s.loc = def.loc;
    s.label = name.text;
    statements_.push_back(std::move(s));
  }

  // The ranges between top-level commas of [c.pos, c.end); an empty list for no tokens.
  std::vector<Cursor> split_operands(const Cursor& c) {
    std::vector<Cursor> parts;
    if (c.done()) return parts;
    int depth = 0;
    std::size_t start = c.pos;
    for (std::size_t i = c.pos; i < c.end; ++i) {
      const Token& t = c.tokens[i];
      if (t.is("[") || t.is("(")) ++depth;
      if ((t.is("]") || t.is(")")) && depth > 0) --depth;
      if (t.is(",") && depth == 0) {
        parts.push_back({c.tokens, start, i});
        start = i + 1;
      }
    }
    parts.push_back({c.tokens, start, c.end});
    return parts;
  }

  // Operand lists of directives and instructions: a missing operand between commas is
  // an error here so that every part below holds at least one token.
  std::optional<std::vector<Cursor>> operand_list(const Cursor& c, const Location& line) {
    std::vector<Cursor> parts = split_operands(c);
    for (const Cursor& p : parts) {
      if (p.done()) {
        error(at(line, p.peek().column), fmt::format("{}, expected an operand", describe(p.peek())));
        return std::nullopt;
      }
    }
    return parts;
  }

  bool expect_done(const Cursor& c, const Location& line, std::string_view after) {
    if (c.done()) return true;
    error(at(line, c.peek().column), fmt::format("{} after {}, expected ',' or end of line", describe(c.peek()), after));
    return false;
  }

  std::optional<int> expression(Cursor& c, const Location& line) {
    ExprError e;
    const std::optional<int> root = assembler::parse_expression(c.tokens, c.pos, c.end, pool_, e);
    if (!root) {
      error(at(line, e.column), e.message);
      return std::nullopt;
    }
    if (!c.done()) {
      error(at(line, c.peek().column), fmt::format("{}, expected an operator or the end of the expression",
                                                   describe(c.peek())));
      return std::nullopt;
    }
    return root;
  }

  bool require_section(Section wanted, const Token& head, const Location& line) {
    if (section_ == wanted) return true;
    error(at(line, head.column),
          wanted == Section::kData
              ? fmt::format("'{}' in .text, expected it in .data (data directives need a .data section)", head.text)
              : fmt::format("'{}' in .data, expected it in .text (instructions need a .text section)", head.text));
    return false;
  }

  void directive(const Token& head, Cursor rest, const Location& line) {
    const std::string& name = head.text;
    if (name == ".text" || name == ".data") {
      if (!expect_done(rest, line, name)) return;
      section_ = name == ".text" ? Section::kText : Section::kData;
    } else if (name == ".equ") {
      equ(rest, line);
    } else if (name == ".include") {
      include(rest, line);
    } else if (name == ".loc") {
      source_line(rest, line);
    } else if (name == ".word" || name == ".byte" || name == ".space" || name == ".align" || name == ".insn") {
      const bool insn = name == ".insn";
      if (!require_section(insn ? Section::kText : Section::kData, head, line)) return;
      const std::optional<std::vector<Cursor>> parts = operand_list(rest, line);
      if (!parts) return;
      const bool list = name == ".word" || name == ".byte";
      if (parts->empty() || (!list && parts->size() != 1)) {
        error(at(line, parts->size() > 1 ? (*parts)[1].peek().column : rest.peek().column),
              fmt::format("{} operands, expected {}", parts->size(), list ? "at least one" : "one"));
        return;
      }
      Statement s;
      s.kind = name == ".word"    ? StatementKind::kWord
               : name == ".byte"  ? StatementKind::kByte
               : name == ".space" ? StatementKind::kSpace
               : name == ".align" ? StatementKind::kAlign
                                  : StatementKind::kRawInsn;
      s.section = section_;
      s.loc = at(line, head.column);
      if (insn) place_source(s, line);
      for (Cursor part : *parts) {
        const int column = part.peek().column;
        const std::optional<int> e = expression(part, line);
        if (!e) return;
        s.exprs.push_back(*e);
        s.expr_locs.push_back(at(line, column));
      }
      statements_.push_back(std::move(s));
    } else if (name == ".float") {
      if (!require_section(Section::kData, head, line)) return;
      const std::optional<std::vector<Cursor>> parts = operand_list(rest, line);
      if (!parts) return;
      if (parts->empty()) {
        error(at(line, rest.peek().column), fmt::format("{}, expected at least one float", describe(rest.peek())));
        return;
      }
      Statement s;
      s.kind = StatementKind::kFloat;
      s.section = section_;
      s.loc = at(line, head.column);
      for (Cursor part : *parts) {
        const std::optional<std::uint32_t> bits = float_literal(part, line);
        if (!bits || !expect_done(part, line, "the float")) return;
        s.floats.push_back(*bits);
      }
      statements_.push_back(std::move(s));
    } else {
      std::vector<std::string_view> names(std::begin(kDirectives), std::end(kDirectives));
      error(at(line, head.column),
            fmt::format("unknown directive '{}', expected one of .text .data .equ .include .word .byte .float "
                        ".space .align .insn .loc{}",
                        printable(name), did_you_mean(name, names)));
    }
  }

  void equ(Cursor rest, const Location& line) {
    const Token& name = rest.peek();
    if (name.kind != TokenKind::kIdent) {
      error(at(line, name.column), fmt::format("{}, expected a constant name after .equ", describe(name)));
      return;
    }
    if (!check_new_symbol(name, line, "constant")) return;
    SymbolDef def;
    def.kind = SymbolDef::Kind::kConstant;
    def.loc = at(line, name.column);
    // Defined even if the value below is malformed, so that uses do not add
    // "undefined symbol" errors to the one that matters.
    def.state = SymbolDef::State::kFailed;
    SymbolDef& stored = symbols_.emplace(name.text, def).first->second;
    ++rest.pos;
    if (!rest.peek().is(",")) {
      error(at(line, rest.peek().column), fmt::format("{}, expected ',' and the value of {}", describe(rest.peek()),
                                                      printable(name.text)));
      return;
    }
    ++rest.pos;
    const int column = rest.peek().column;
    const std::optional<int> e = expression(rest, line);
    if (!e) return;
    stored.expr = *e;
    stored.loc = at(line, column);
    stored.state = SymbolDef::State::kPending;
  }

  // .loc "file", line: the instructions after it in this file came from that line (a
  // compiler's listing says which GLSL line); .loc alone: from no line.
  void source_line(Cursor rest, const Location& line) {
    SourceLineSet& current = source_lines_.back();
    if (rest.done()) {
      current = {true, {}, 0};
      return;
    }
    const Token& file = rest.peek();
    if (file.kind != TokenKind::kString || file.text.empty() || file.text.size() > LineTable::kMaxFileName ||
        std::any_of(file.text.begin(), file.text.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20; })) {
      error(at(line, file.column), fmt::format("{}, expected a quoted file name of 1 to {} bytes without control "
                                               "characters: .loc \"file.rchit\", 12",
                                               describe(file), LineTable::kMaxFileName));
      return;
    }
    ++rest.pos;
    if (!rest.peek().is(",")) {
      error(at(line, rest.peek().column), fmt::format("{}, expected ',' and a line number", describe(rest.peek())));
      return;
    }
    ++rest.pos;
    const Token& number = rest.peek();
    const std::optional<std::int64_t> n =
        number.kind == TokenKind::kNumber ? assembler::parse_integer(number.text) : std::nullopt;
    if (!n || *n < 1 || *n > INT32_MAX) {
      error(at(line, number.column), fmt::format("{}, expected a line number from 1 to {}", describe(number), INT32_MAX));
      return;
    }
    ++rest.pos;
    if (!expect_done(rest, line, "the line number")) return;
    current = {true, file.text, static_cast<std::uint32_t>(*n)};
  }

  // The line-table line of an instruction statement at `line`.
  void place_source(Statement& s, const Location& line) const {
    const SourceLineSet& current = source_lines_.back();
    s.source_file = current.set ? current.file : files_[static_cast<std::size_t>(line.file)].name;
    s.source_line = current.set ? current.line : static_cast<std::uint32_t>(line.line);
  }

  std::string include_chain(const std::string& last) const {
    std::string chain;
    for (const Location& site : include_sites_) {
      chain += fmt::format("{}:{} -> ", files_[static_cast<std::size_t>(site.file)].name, site.line);
    }
    return chain + last;
  }

  void include(Cursor rest, const Location& line) {
    const Token& path_token = rest.peek();
    if (path_token.kind != TokenKind::kString) {
      error(at(line, path_token.column), fmt::format("{}, expected a quoted path: .include \"file.s\"",
                                                     describe(path_token)));
      return;
    }
    ++rest.pos;
    if (!expect_done(rest, line, "the .include path")) return;
    const Location where = at(line, path_token.column);
    const std::filesystem::path relative(path_token.text);
    const std::filesystem::path path =
        relative.is_absolute() ? relative.lexically_normal()
                               : (open_.back().parent_path() / relative).lexically_normal();
    include_sites_.push_back(at(line, 0));
    const std::string shown = path.string();
    if (std::find(open_.begin(), open_.end(), path) != open_.end()) {
      error(where, fmt::format("include cycle {}, expected a file that is not already being included",
                               printable(include_chain(shown))));
    } else if (open_.size() >= kMaxIncludeDepth) {
      error(where, fmt::format("includes nested {} deep ({}), expected at most {}", open_.size(),
                               printable(include_chain(shown)), kMaxIncludeDepth));
    } else if (std::optional<std::string> text = path_token.text.empty() ? std::nullopt : load_(path); !text) {
      error(where, fmt::format("cannot read '{}' (include chain {}), expected an existing file",
                               printable(path_token.text), printable(include_chain(shown))));
    } else {
      read_text(path, shown, *text);
    }
    include_sites_.pop_back();
  }

  // ---- instructions --------------------------------------------------------------

  void instruction(const Token& head, Cursor rest, const Location& line) {
    const InsnSpec* spec = find_insn(head.text);
    if (!spec) {
      std::vector<std::string_view> names;
      for (const InsnSpec& s : si::kInsns) names.push_back(s.mnemonic);
      error(at(line, head.column), fmt::format("unknown mnemonic '{}', expected an instruction of docs/isa.md{}",
                                               printable(head.text), did_you_mean(head.text, names)));
      return;
    }
    if (!require_section(Section::kText, head, line)) return;
    const std::optional<std::vector<Cursor>> parts = operand_list(rest, line);
    if (!parts) return;
    const auto want = static_cast<std::size_t>(spec->operand_count);
    if (parts->size() != want) {
      const int column = parts->size() > want ? (*parts)[want].peek().column : rest.tokens[rest.end].column;
      error(at(line, column), fmt::format("{} operand{}, expected {} ({})", parts->size(),
                                          parts->size() == 1 ? "" : "s", want, signature(*spec)));
      return;
    }
    Statement s;
    s.kind = StatementKind::kInsn;
    s.section = section_;
    s.loc = at(line, head.column);
    s.spec = spec;
    place_source(s, line);
    for (std::size_t k = 0; k < want; ++k) {
      Cursor part = (*parts)[k];
      ParsedOperand op;
      op.kind = spec->operands[k];
      op.loc = at(line, part.peek().column);
      if (!operand(*spec, part, line, op) || !expect_done(part, line, "the operand")) return;
      s.operands.push_back(op);
    }
    statements_.push_back(std::move(s));
  }

  bool operand(const InsnSpec& spec, Cursor& c, const Location& line, ParsedOperand& op) {
    // neg/abs exist only in format R, and only for instructions that take float modifiers.
    const bool mods = spec.float_modifiers && spec.format == si::Format::kR;
    switch (op.kind) {
      case Operand::kD: return destination(c, line, op);
      case Operand::kA: return source(c, line, op.src, spec, "a", mods, mods);
      case Operand::kB: return source(c, line, op.src, spec, "b", mods, mods);
      case Operand::kC: return source(c, line, op.src, spec, "c", mods, false);
      case Operand::kFimm: {
        const std::optional<std::uint32_t> bits = float_literal(c, line);
        op.bits = bits.value_or(0);
        return bits.has_value();
      }
      case Operand::kSr:
        if (c.peek().kind == TokenKind::kIdent && c.pos + 1 == c.end) {
          if (const si::SpecialSpec* sr = find_special(c.peek().text)) {
            op.bits = static_cast<std::uint32_t>(sr->index);
            ++c.pos;
            return true;
          }
        }
        [[fallthrough]];
      case Operand::kImm:
      case Operand::kTarget: {
        const std::optional<int> e = expression(c, line);
        op.expr = e.value_or(-1);
        return e.has_value();
      }
      case Operand::kMem: return memory(c, line, op, spec);
    }
    return false;
  }

  std::optional<RegisterRef> register_ref(Cursor& c, const Location& line, std::string_view what) {
    const Token& t = c.peek();
    if (t.kind != TokenKind::kIdent || !assembler::is_register_name(t.text)) {
      error(at(line, t.column), fmt::format("{}, expected {} r0..r{}", describe(t), what, kRegisterCount - 1));
      return std::nullopt;
    }
    const std::size_t dot = t.text.find('.');
    const std::string digits = t.text.substr(1, dot == std::string::npos ? std::string::npos : dot - 1);
    // r0..r63 in canonical form: no leading zeros, so each register has one spelling.
    if (digits.size() > 2 || (digits.size() > 1 && digits[0] == '0') || std::stoi(digits) >= kRegisterCount) {
      error(at(line, t.column), fmt::format("bad register 'r{}', expected r0..r{}", printable(digits),
                                            kRegisterCount - 1));
      return std::nullopt;
    }
    RegisterRef r;
    r.reg = static_cast<std::uint8_t>(std::stoi(digits));
    ++c.pos;
    if (dot != std::string::npos) {
      r.has_suffix = true;
      r.suffix = t.text.substr(dot + 1);
      r.suffix_column = t.column + static_cast<int>(dot);
    }
    return r;
  }

  // A suffix written apart from its register: "r1 .x" reads as "r1.x".
  void detached_suffix(Cursor& c, RegisterRef& r) {
    const Token& t = c.peek();
    if (!r.has_suffix && !c.done() && t.kind == TokenKind::kIdent && t.text[0] == '.') {
      r.has_suffix = true;
      r.suffix = t.text.substr(1);
      r.suffix_column = t.column;
      ++c.pos;
    }
  }

  bool destination(Cursor& c, const Location& line, ParsedOperand& op) {
    const Token& t = c.peek();
    if (t.is("-") || t.is("|")) {
      error(at(line, t.column), fmt::format("modifier '{}' on the destination, expected a register like r3 or r3.xz",
                                            t.text));
      return false;
    }
    std::optional<RegisterRef> r = register_ref(c, line, "a destination register");
    if (!r) return false;
    detached_suffix(c, *r);
    op.dst = r->reg;
    op.wmask = kAllLanes;
    if (!r->has_suffix) return true;
    const Location where = at(line, r->suffix_column);
    if (r->suffix == "none") {
      op.wmask = 0;
      return true;
    }
    std::uint8_t mask = 0;
    int previous = -1;
    bool ordered = true;
    for (const char lane : r->suffix) {
      const std::size_t i = kLanes.find(lane);
      if (i == std::string_view::npos || r->suffix.size() > 4) {
        error(where, fmt::format("bad write mask '.{}', expected distinct lanes from xyzw in order (r3.xz) or .none",
                                 printable(r->suffix)));
        return false;
      }
      ordered = ordered && static_cast<int>(i) > previous;
      previous = static_cast<int>(i);
      mask = static_cast<std::uint8_t>(mask | 1u << i);
    }
    if (r->suffix.empty() || !ordered) {
      error(where, fmt::format("swizzle '.{}' on the destination, expected a write mask: distinct lanes from xyzw "
                               "in order (r3.xz) or .none",
                               printable(r->suffix)));
      return false;
    }
    op.wmask = mask;
    return true;
  }

  bool source(Cursor& c, const Location& line, Source& src, const InsnSpec& spec, std::string_view role,
              bool allow_neg, bool allow_abs) {
    src = Source{};
    src.swizzle = kIdentitySwizzle;
    int neg_column = 0;
    int abs_column = 0;
    if (c.peek().is("-")) {
      neg_column = c.peek().column;
      ++c.pos;
    }
    std::optional<RegisterRef> r;
    if (c.peek().is("|")) {
      abs_column = c.peek().column;
      ++c.pos;
      r = register_ref(c, line, "a source register");
      if (!r) return false;
      if (r->has_suffix) {
        error(at(line, r->suffix_column), fmt::format("swizzle '.{}' inside |...|, expected it after the bars: |r{}|.{}",
                                                      printable(r->suffix), r->reg, printable(r->suffix)));
        return false;
      }
      if (!c.peek().is("|")) {
        error(at(line, c.peek().column), fmt::format("{}, expected '|' closing |r{}|", describe(c.peek()), r->reg));
        return false;
      }
      ++c.pos;
    } else {
      r = register_ref(c, line, role == "mem" ? "an address register" : "a source register");
      if (!r) return false;
    }
    detached_suffix(c, *r);
    src.reg = r->reg;
    src.neg = neg_column != 0;
    src.abs = abs_column != 0;
    for (const auto& [column, name, allowed] : {std::tuple{neg_column, "neg '-'", allow_neg},
                                                std::tuple{abs_column, "abs '|...|'", allow_abs}}) {
      if (column == 0 || allowed) continue;
      const std::string subject = role == "mem" ? "the address register" : fmt::format("source {}", role);
      std::string why;
      if (role == "mem") {
        why = "a plain register";
      } else if (spec.float_modifiers && spec.format == si::Format::kR) {
        why = "no abs on source c (the encoding has no c_abs bit)";
      } else {
        why = fmt::format("a plain register ('{}' takes no neg/abs; only instructions with mods = \"float\" do)",
                          spec.mnemonic);
      }
      error(at(line, column), fmt::format("{} on {} of '{}', expected {}", name, subject, spec.mnemonic, why));
      return false;
    }
    if (!r->has_suffix) return true;
    const Location where = at(line, r->suffix_column);
    if (r->suffix == "none") {
      error(where, "write mask '.none' on a source, expected a swizzle: 1 to 4 lanes from xyzw");
      return false;
    }
    if (r->suffix.empty() || r->suffix.size() > 4 || r->suffix.find_first_not_of(kLanes) != std::string::npos) {
      error(where, fmt::format("bad swizzle '.{}', expected 1 to 4 lanes from xyzw (r1.zyx; the last repeats)",
                               printable(r->suffix)));
      return false;
    }
    // Fewer than four lanes repeat the last one: .x = xxxx, .xy = xyyy.
    std::uint8_t swizzle = 0;
    for (std::size_t i = 0; i < 4; ++i) {
      const std::size_t lane = kLanes.find(r->suffix[std::min(i, r->suffix.size() - 1)]);
      swizzle = static_cast<std::uint8_t>(swizzle | lane << (2 * i));
    }
    src.swizzle = swizzle;
    return true;
  }

  bool memory(Cursor& c, const Location& line, ParsedOperand& op, const InsnSpec& spec) {
    if (!c.peek().is("[")) {
      error(at(line, c.peek().column), fmt::format("{}, expected '[' starting a memory operand [r1 + offset]",
                                                   describe(c.peek())));
      return false;
    }
    ++c.pos;
    if (!source(c, line, op.src, spec, "mem", false, false)) return false;
    if (c.peek().is("+") || c.peek().is("-")) {
      // The sign belongs to the offset expression: [r1 - 4 + 2] has offset -2, as in C.
      op.loc.column = c.peek().column;
      ExprError e;
      Cursor inner{c.tokens, c.pos, c.end};
      const std::optional<int> root = assembler::parse_expression(c.tokens, inner.pos, c.end, pool_, e);
      if (!root) {
        error(at(line, e.column), e.message);
        return false;
      }
      op.expr = *root;
      c.pos = inner.pos;
    }
    if (!c.peek().is("]")) {
      error(at(line, c.peek().column), fmt::format("{}, expected '+', '-' or ']' in the memory operand",
                                                   describe(c.peek())));
      return false;
    }
    ++c.pos;
    return true;
  }

  // fimm and .float: a decimal (rounded to fp32 to nearest), inf, nan, or 0x raw bits.
  std::optional<std::uint32_t> float_literal(Cursor& c, const Location& line) {
    std::string sign;
    const int column = c.peek().column;
    if (c.peek().is("-") || c.peek().is("+")) {
      sign = c.peek().text;
      ++c.pos;
    }
    const Token& t = c.peek();
    const Location where = at(line, column);
    const bool hex = t.kind == TokenKind::kNumber && t.text.size() > 1 && (t.text[1] == 'x' || t.text[1] == 'X');
    const bool binary = t.kind == TokenKind::kNumber && t.text.size() > 1 && (t.text[1] == 'b' || t.text[1] == 'B');
    if (hex) {
      const std::optional<std::int64_t> v = assembler::parse_integer(t.text);
      if (!sign.empty() || !v || *v < 0 || *v > 0xffffffff) {
        error(where, fmt::format("raw float bits '{}{}', expected an unsigned 32-bit 0x value without sign", sign,
                                 printable(t.text)));
        return std::nullopt;
      }
      ++c.pos;
      return static_cast<std::uint32_t>(*v);
    }
    if (t.kind == TokenKind::kIdent && (t.text == "inf" || t.text == "nan")) {
      ++c.pos;
      if (t.text == "inf") return std::bit_cast<std::uint32_t>(sign == "-" ? -INFINITY : INFINITY);
      if (sign.empty()) return kCanonicalNan;
      error(where, fmt::format("'{}nan', expected nan (the canonical 0x7fc00000) or raw 0x bits", sign));
      return std::nullopt;
    }
    if (t.kind != TokenKind::kNumber || binary) {
      error(at(line, t.column), fmt::format("{}, expected a float literal (1.5, -2e-3, inf, nan) or 0x raw bits",
                                            describe(t)));
      return std::nullopt;
    }
    const std::string text = (sign == "-" ? "-" : "") + t.text;
    errno = 0;
    const float f = std::strtof(text.c_str(), nullptr);
    // ERANGE also flags results that underflow to a subnormal or zero; those are the
    // correctly rounded value and kept. Only overflow is refused.
    if (errno == ERANGE && std::isinf(f)) {
      error(where, fmt::format("float literal {} overflows fp32, expected a magnitude up to 3.4028235e38, or inf",
                               text));
      return std::nullopt;
    }
    ++c.pos;
    return std::bit_cast<std::uint32_t>(f);
  }

  // ---- layout and emission ---------------------------------------------------------

  std::optional<std::uint32_t> fit32(std::int64_t v, const Location& where, std::string_view what) {
    if (v >= INT32_MIN && v <= static_cast<std::int64_t>(UINT32_MAX)) return static_cast<std::uint32_t>(v);
    error(where, fmt::format("value {} out of range for {}, expected a 32-bit signed or unsigned integer",
                             int_text(v), what));
    return std::nullopt;
  }

  // Addresses of every statement and label; false if they cannot be trusted.
  bool layout() {
    std::uint64_t pc = 0;
    std::uint64_t offset = 0;
    for (Statement& s : statements_) {
      s.address = static_cast<std::uint32_t>(s.section == Section::kText ? pc : offset);
      switch (s.kind) {
        case StatementKind::kLabel: {
          SymbolDef& def = symbols_.at(s.label);
          def.value = s.section == Section::kText ? static_cast<std::int64_t>(pc)
                                                  : spec::memory::kDeviceDataBase + static_cast<std::int64_t>(offset);
          def.placed = true;
          break;
        }
        case StatementKind::kInsn:
        case StatementKind::kRawInsn: ++pc; break;
        case StatementKind::kWord: s.bytes = static_cast<std::uint32_t>(4 * s.exprs.size()); break;
        case StatementKind::kByte: s.bytes = static_cast<std::uint32_t>(s.exprs.size()); break;
        case StatementKind::kFloat: s.bytes = static_cast<std::uint32_t>(4 * s.floats.size()); break;
        case StatementKind::kSpace: {
          const std::optional<std::int64_t> n = evaluate(pool_, s.exprs[0], s.expr_locs[0], *this);
          if (n && (*n < 0 || static_cast<std::uint64_t>(*n) > kDataLimit)) {
            error(s.expr_locs[0], fmt::format(".space {}, expected 0 to {} bytes", int_text(*n), kDataLimit));
          } else if (n) {
            s.bytes = static_cast<std::uint32_t>(*n);
          }
          break;
        }
        case StatementKind::kAlign: {
          const std::optional<std::int64_t> n = evaluate(pool_, s.exprs[0], s.expr_locs[0], *this);
          if (n && (*n <= 0 || !std::has_single_bit(static_cast<std::uint64_t>(*n)) ||
                    static_cast<std::uint64_t>(*n) > kDataLimit)) {
            error(s.expr_locs[0], fmt::format(".align {}, expected a power of two from 1 to {} bytes", int_text(*n),
                                              kDataLimit));
          } else if (n) {
            s.bytes = static_cast<std::uint32_t>((0 - offset) & static_cast<std::uint64_t>(*n - 1));
          }
          break;
        }
      }
      if (s.section == Section::kData && offset + s.bytes > kDataLimit) {
        error(s.loc, fmt::format("data section of {} bytes, expected at most {} (the device's data window "
                                 "DEVICE_DATA_BASE..DEVICE_STACK_BASE)",
                                 offset + s.bytes, kDataLimit));
        return false;
      }
      offset += s.bytes;
    }
    if (pc > UINT32_MAX) {
      errors_.push_back(fmt::format("{}: error: {} instructions, expected at most {}", files_[0].name, pc, UINT32_MAX));
      return false;
    }
    result_.firmware.code.assign(pc, 0);
    result_.firmware.data.assign(offset, 0);
    return true;
  }

  std::optional<std::uint32_t> operand_value(const ParsedOperand& op, std::string_view what) {
    const std::optional<std::int64_t> v = evaluate(pool_, op.expr, op.loc, *this);
    return v ? fit32(*v, op.loc, what) : std::nullopt;
  }

  void emit_instruction(const Statement& s) {
    Instruction insn;
    insn.spec = s.spec;
    bool ok = true;
    for (const ParsedOperand& op : s.operands) {
      switch (op.kind) {
        case Operand::kD:
          insn.dst = op.dst;
          insn.wmask = op.wmask;
          break;
        case Operand::kA:
        case Operand::kMem: insn.src[0] = op.src; break;
        case Operand::kB: insn.src[1] = op.src; break;
        case Operand::kC: insn.src[2] = op.src; break;
        case Operand::kFimm: insn.imm = op.bits; break;
        case Operand::kSr:
        case Operand::kImm:
        case Operand::kTarget: break;
      }
      if (op.kind == Operand::kSr && op.expr < 0) {
        insn.imm = op.bits;
      } else if (op.kind == Operand::kTarget && is_data_label(op.expr)) {
        error(op.loc, fmt::format("data label '{}' as a branch target, expected a code label or instruction index",
                                  printable(pool_[static_cast<std::size_t>(op.expr)].symbol)));
        ok = false;
      } else if (op.expr >= 0) {
        const std::string what =
            op.kind == Operand::kMem ? "a memory offset" : fmt::format("the {} operand", operand_name(op.kind));
        const std::optional<std::uint32_t> v = operand_value(op, what);
        ok = ok && v.has_value();
        insn.imm = v.value_or(0);
      }
    }
    if (ok) result_.firmware.code[s.address] = encode(insn);
  }

  bool is_data_label(int expr) const {
    if (expr < 0) return false;
    const ExprNode& n = pool_[static_cast<std::size_t>(expr)];
    if (n.op != ExprOp::kSymbol) return false;
    const auto it = symbols_.find(n.symbol);
    return it != symbols_.end() && it->second.kind == SymbolDef::Kind::kData;
  }

  void emit() {
    Firmware& fw = result_.firmware;
    for (const Statement& s : statements_) {
      std::uint32_t at_byte = s.address;
      switch (s.kind) {
        case StatementKind::kLabel:
        case StatementKind::kSpace:
        case StatementKind::kAlign: break;
        case StatementKind::kInsn: emit_instruction(s); break;
        case StatementKind::kRawInsn: {
          // Any 64-bit pattern: .insn carries words the decoder rejects.
          const std::optional<std::int64_t> v = evaluate(pool_, s.exprs[0], s.expr_locs[0], *this);
          if (v) fw.code[s.address] = static_cast<std::uint64_t>(*v);
          break;
        }
        case StatementKind::kWord:
        case StatementKind::kByte:
          for (std::size_t i = 0; i < s.exprs.size(); ++i) {
            const std::optional<std::int64_t> v = evaluate(pool_, s.exprs[i], s.expr_locs[i], *this);
            if (!v) continue;
            if (s.kind == StatementKind::kByte) {
              if (*v < -128 || *v > 255) {
                error(s.expr_locs[i], fmt::format("value {} out of range for .byte, expected -128 to 255",
                                                  int_text(*v)));
              } else {
                fw.data[at_byte + i] = static_cast<std::uint8_t>(*v);
              }
            } else if (const std::optional<std::uint32_t> w = fit32(*v, s.expr_locs[i], ".word")) {
              put_u32(at_byte + 4 * i, *w);
            }
          }
          break;
        case StatementKind::kFloat:
          for (std::size_t i = 0; i < s.floats.size(); ++i) put_u32(at_byte + 4 * i, s.floats[i]);
          break;
      }
      if (s.kind != StatementKind::kLabel) listing(s);
      if (s.kind == StatementKind::kInsn || s.kind == StatementKind::kRawInsn) {
        fw.lines.add(s.address, s.source_file, s.source_line);
      }
    }
    for (const auto& [name, def] : symbols_) {
      const Symbol::Kind kind = def.kind == SymbolDef::Kind::kCode   ? Symbol::Kind::kCode
                                : def.kind == SymbolDef::Kind::kData ? Symbol::Kind::kData
                                                                     : Symbol::Kind::kConstant;
      if (kind == Symbol::Kind::kConstant) {
        // Constants nothing used are evaluated here, so their errors are reported too.
        const std::optional<std::int64_t> v = value(name, def.loc);
        if (!v) continue;
      }
      fw.symbols[name] = Symbol{kind, static_cast<std::uint32_t>(def.value)};
    }
  }

  void put_u32(std::size_t at_byte, std::uint32_t v) {
    for (std::size_t i = 0; i < 4; ++i) result_.firmware.data[at_byte + i] = static_cast<std::uint8_t>(v >> (8 * i));
  }

  void listing(const Statement& s) {
    const SourceFile& file = files_[static_cast<std::size_t>(s.loc.file)];
    std::string text = file.lines[static_cast<std::size_t>(s.loc.line - 1)];
    text.erase(text.find_last_not_of(" \t\r") + 1);
    const bool code = s.section == Section::kText;
    result_.listing.push_back({code, code ? s.address : spec::memory::kDeviceDataBase + s.address, s.bytes, file.name,
                               s.loc.line, std::move(text)});
  }

  const SourceLoader& load_;
  std::vector<SourceFile> files_;
  std::vector<std::filesystem::path> open_;  // files being read, outermost first
  std::vector<Location> include_sites_;      // the .include lines leading to open_.back()
  std::vector<SourceLineSet> source_lines_;  // per file of open_: what its last .loc set
  std::vector<Statement> statements_;
  std::map<std::string, SymbolDef, std::less<>> symbols_;
  std::vector<std::string> resolving_;  // constants being evaluated, for cycle messages
  ExprPool pool_;
  Section section_ = Section::kText;
  std::vector<std::string> errors_;
  Assembly result_;
};

}  // namespace

std::optional<std::string> read_source_file(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::exists(std::filesystem::symlink_status(file, ec))) return std::nullopt;
  return read_input_file(file, "the assembly source");
}

Assembly assemble_with_listing(const std::filesystem::path& file, const SourceLoader& load) {
  return Assembler(load).run(file);
}

Firmware assemble(const std::filesystem::path& file, const SourceLoader& load) {
  return assemble_with_listing(file, load).firmware;
}

Firmware assemble(const std::filesystem::path& file) { return assemble(file, read_source_file); }

std::string format_listing(const Assembly& assembly) {
  std::string out;
  for (const ListingLine& l : assembly.listing) {
    if (l.code) {
      out += fmt::format("{:>8}  {:016x}  {:<16}  {}\n", l.address, assembly.firmware.code[l.address],
                         fmt::format("{}:{}", l.file, l.line), l.text);
    } else {
      out += fmt::format("{:08x}  {:>16}  {:<16}  {}\n", l.address,
                         fmt::format("({} byte{})", l.bytes, l.bytes == 1 ? "" : "s"),
                         fmt::format("{}:{}", l.file, l.line), l.text);
    }
  }
  return out;
}

bool is_symbol_name(std::string_view name) {
  if (name.empty() || !assembler::is_ident_start(name[0]) || assembler::is_register_name(name)) return false;
  return std::all_of(name.begin(), name.end(), assembler::is_ident_char);
}

}  // namespace rpu::isa
