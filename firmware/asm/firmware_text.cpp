#include "asm/firmware_text.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "isa/instruction.hpp"
#include "rpu/spec.hpp"

namespace rpu::isa {

namespace {

// Runs of zero bytes at least this long become one .space line.
constexpr std::size_t kSpaceRun = 16;
constexpr std::size_t kWordsPerLine = 4;

using Labels = std::vector<std::pair<std::uint32_t, std::string>>;  // (position, name), sorted

Labels labels_of(const Firmware& fw, Symbol::Kind kind, std::uint32_t base) {
  Labels out;
  for (const auto& [name, symbol] : fw.symbols) {
    if (symbol.kind == kind) out.emplace_back(symbol.value - base, name);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Prints the labels at `position`, advancing `next` past them.
void print_labels(std::string& out, const Labels& labels, std::size_t& next, std::uint64_t position) {
  for (; next < labels.size() && labels[next].first == position; ++next) out += labels[next].second + ":\n";
}

std::size_t zero_run(const std::vector<std::uint8_t>& data, std::size_t from, std::size_t end) {
  std::size_t i = from;
  while (i < end && data[i] == 0) ++i;
  return i - from;
}

// Bytes [from, end) of .data, which no label splits.
void print_data(std::string& out, const std::vector<std::uint8_t>& data, std::size_t from, std::size_t end) {
  std::size_t i = from;
  while (i < end) {
    if (const std::size_t zeros = zero_run(data, i, end); zeros >= kSpaceRun) {
      out += fmt::format("    .space {}\n", zeros);
      i += zeros;
    } else if (end - i >= 4) {
      std::string line = "    .word ";
      for (std::size_t n = 0; n < kWordsPerLine && end - i >= 4 && zero_run(data, i, end) < kSpaceRun; ++n, i += 4) {
        const std::uint32_t w = data[i] | data[i + 1] << 8 | data[i + 2] << 16 | static_cast<std::uint32_t>(data[i + 3]) << 24;
        line += fmt::format("{}{:#010x}", n ? ", " : "", w);
      }
      out += line + "\n";
    } else {
      std::string line = "    .byte ";
      for (std::size_t n = 0; i < end; ++n, ++i) line += fmt::format("{}{:#04x}", n ? ", " : "", data[i]);
      out += line + "\n";
    }
  }
}

}  // namespace

std::string source_line_directive(std::string_view file, std::uint32_t line) {
  if (line == 0) return ".loc";
  std::string quoted;
  for (const char c : file) {
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += c;
  }
  return fmt::format(".loc \"{}\", {}", quoted, line);
}

std::string firmware_to_text(const Firmware& fw) {
  std::string out = fmt::format("; {} instructions, {} data bytes, {} symbols\n", fw.code.size(), fw.data.size(),
                                fw.symbols.size());
  for (const auto& [name, symbol] : fw.symbols) {
    if (symbol.kind == Symbol::Kind::kConstant) out += fmt::format(".equ {}, {:#x}\n", name, symbol.value);
  }
  out += ".text\n";
  const Labels code_labels = labels_of(fw, Symbol::Kind::kCode, 0);
  std::size_t next = 0;
  // Every run of the line table starts with its .loc, and pc 0 has one even without a
  // line, so that the text's own lines are in no instruction's place.
  auto run = fw.lines.runs.begin();
  for (std::size_t pc = 0; pc < fw.code.size(); ++pc) {
    print_labels(out, code_labels, next, pc);
    if (run != fw.lines.runs.end() && run->pc == pc) {
      const SourceLine& s = run->source;
      out += fmt::format("    {}\n", source_line_directive(s.line ? fw.lines.files[s.file] : "", s.line));
      ++run;
    } else if (pc == 0) {
      out += "    .loc\n";
    }
    out += fmt::format("    {:<40} ; {}\n", disassemble(fw.code[pc]), pc);
  }
  print_labels(out, code_labels, next, fw.code.size());

  const Labels data_labels = labels_of(fw, Symbol::Kind::kData, spec::memory::kDeviceDataBase);
  if (fw.data.empty() && data_labels.empty()) return out;
  out += ".data\n";
  next = 0;
  std::size_t from = 0;
  for (const auto& [offset, name] : data_labels) {
    print_data(out, fw.data, from, offset);
    print_labels(out, data_labels, next, offset);
    from = offset;
  }
  print_data(out, fw.data, from, fw.data.size());
  return out;
}

}  // namespace rpu::isa
