#include "asm/lexer.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace rpu::assembler {

bool is_ident_start(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_' || c == '.';
}
bool is_ident_char(char c) { return is_ident_start(c) || (c >= '0' && c <= '9'); }

namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_hex(char c) { return is_digit(c) || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F'); }

// Length of the number at the start of s (which starts with a digit): 0x hex, 0b
// binary, or a decimal with optional fraction and exponent. The caller rejects a
// number that runs straight into letters (12ab, 0x1g).
std::size_t number_length(std::string_view s) {
  std::size_t i = 0;
  if (s.size() > 1 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
    i = 2;
    while (i < s.size() && is_hex(s[i])) ++i;
    return i;
  }
  if (s.size() > 1 && s[0] == '0' && (s[1] == 'b' || s[1] == 'B')) {
    i = 2;
    while (i < s.size() && (s[i] == '0' || s[i] == '1')) ++i;
    return i;
  }
  while (i < s.size() && is_digit(s[i])) ++i;
  if (i < s.size() && s[i] == '.') {
    ++i;
    while (i < s.size() && is_digit(s[i])) ++i;
  }
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    std::size_t j = i + 1;
    if (j < s.size() && (s[j] == '+' || s[j] == '-')) ++j;
    if (j < s.size() && is_digit(s[j])) {
      while (j < s.size() && is_digit(s[j])) ++j;
      i = j;
    }
  }
  return i;
}

}  // namespace

std::string printable(std::string_view text) {
  std::string out;
  // A message quotes at most 64 bytes of a token (quote_input).
  constexpr std::size_t kShown = 64;
  for (const char c : text.substr(0, kShown)) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7f) {
      out += c;
    } else {
      out += fmt::format("\\x{:02x}", u);
    }
  }
  if (text.size() > kShown) out += fmt::format("... ({} bytes)", text.size());
  return out;
}

std::string describe(const Token& token) {
  switch (token.kind) {
    case TokenKind::kEnd: return "end of line";
    case TokenKind::kString: return fmt::format("string \"{}\"", printable(token.text));
    default: return fmt::format("'{}'", printable(token.text));
  }
}

std::vector<Token> lex_line(std::string_view line, LexError& error) {
  std::vector<Token> tokens;
  std::size_t i = 0;
  auto fail = [&](std::size_t at, std::string message) {
    error = {static_cast<int>(at) + 1, std::move(message)};
  };
  while (i < line.size() && error.column == 0) {
    const char c = line[i];
    const int column = static_cast<int>(i) + 1;
    if (c == ' ' || c == '\t' || c == '\r') {
      ++i;
    } else if (c == ';') {
      break;
    } else if (is_ident_start(c)) {
      std::size_t j = i;
      while (j < line.size() && is_ident_char(line[j])) ++j;
      tokens.push_back({TokenKind::kIdent, std::string(line.substr(i, j - i)), column});
      i = j;
    } else if (is_digit(c)) {
      const std::size_t n = number_length(line.substr(i));
      std::size_t j = i + n;
      if (j < line.size() && is_ident_char(line[j])) {
        while (j < line.size() && is_ident_char(line[j])) ++j;
        fail(i, fmt::format("malformed number '{}', expected a decimal, 0x hex or 0b binary number",
                            printable(line.substr(i, j - i))));
        break;
      }
      tokens.push_back({TokenKind::kNumber, std::string(line.substr(i, n)), column});
      i = j;
    } else if (c == '"') {
      std::string text;
      std::size_t j = i + 1;
      bool closed = false;
      while (j < line.size()) {
        if (line[j] == '"') {
          closed = true;
          break;
        }
        if (line[j] == '\\' && j + 1 < line.size() && (line[j + 1] == '"' || line[j + 1] == '\\')) ++j;
        text += line[j++];
      }
      if (!closed) {
        fail(i, "unterminated string, expected a closing '\"'");
        break;
      }
      tokens.push_back({TokenKind::kString, std::move(text), column});
      i = j + 1;
    } else if ((c == '<' || c == '>') && i + 1 < line.size() && line[i + 1] == c) {
      tokens.push_back({TokenKind::kPunct, std::string(2, c), column});
      i += 2;
    } else if (std::string_view(",:[]()+-*/%~&|^").find(c) != std::string_view::npos) {
      tokens.push_back({TokenKind::kPunct, std::string(1, c), column});
      ++i;
    } else {
      fail(i, fmt::format("unexpected character '{}', expected an instruction, operand or ; comment",
                          printable(line.substr(i, 1))));
    }
  }
  const std::size_t end = error.column ? static_cast<std::size_t>(error.column - 1) : std::min(i, line.size());
  tokens.push_back({TokenKind::kEnd, "", static_cast<int>(end) + 1});
  return tokens;
}

}  // namespace rpu::assembler
