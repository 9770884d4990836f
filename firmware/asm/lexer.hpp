#pragma once

#include <string>
#include <string_view>
#include <vector>

// The assembler's tokens: one source line at a time (a statement never spans lines).
namespace rpu::assembler {

enum class TokenKind : unsigned char {
  kIdent,   // [A-Za-z_.][A-Za-z0-9_.]*: mnemonics, directives, labels, registers with suffix
  kNumber,  // 12, 0x1f, 0b101, 1.5, 2e-3: whether an integer or a float is wanted is the parser's call
  kString,  // "..." with \" and \\ escapes; text holds the unescaped contents
  kPunct,   // , : [ ] ( ) + - * / % ~ & | ^ << >>
  kEnd,     // end of line (or the start of a ; comment)
};

struct Token {
  TokenKind kind = TokenKind::kEnd;
  std::string text;
  int column = 1;  // 1-based byte column of the first character

  bool is(std::string_view punct) const { return kind == TokenKind::kPunct && text == punct; }
};

struct LexError {
  int column = 0;  // 0: no error
  std::string message;
};

// The tokens of one line, always ending in a kEnd token; on a malformed token `error`
// says where and the tokens stop there.
std::vector<Token> lex_line(std::string_view line, LexError& error);

// How a token reads in "found X, expected Y" messages: 'mov', end of line, ...
std::string describe(const Token& token);

// Printable form of arbitrary bytes for error messages (fuzzed sources hold any byte),
// at most 64 of them and the length.
std::string printable(std::string_view text);

bool is_ident_start(char c);
bool is_ident_char(char c);

}  // namespace rpu::assembler
