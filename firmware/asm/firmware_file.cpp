#include "asm/firmware_file.hpp"

#include <algorithm>
#include <fstream>

#include <fmt/format.h>

#include "asm/assembler.hpp"
#include "asm/lexer.hpp"
#include "common/error.hpp"
#include "common/input_file.hpp"
#include "common/output_file.hpp"
#include "rpu/spec.hpp"

namespace rpu::isa {

namespace {

constexpr std::uint32_t kSymbolKinds = 3;  // Symbol::Kind: code, data, constant

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

std::uint32_t checked_u32(std::size_t n, std::string_view what) {
  if (n > UINT32_MAX) throw Error(fmt::format("firmware has {} {}, more than a .rfw file can hold", n, what));
  return static_cast<std::uint32_t>(n);
}

// Reads the input front to back; every read is bounds-checked and a failure names
// the offset where the missing or bad field starts.
class Reader {
 public:
  Reader(std::span<const std::uint8_t> bytes, const std::string& name) : bytes_(bytes), name_(name) {}

  [[noreturn]] void fail(std::size_t at, const std::string& message) const {
    throw Error(fmt::format("{}: offset {}: {}", name_, at, message));
  }

  std::size_t offset() const { return at_; }

  void need(std::uint64_t n, std::string_view what) const {
    if (n > bytes_.size() - at_) {
      fail(at_, fmt::format("{} needs {} bytes but the file ends after {}, expected a complete .rfw file", what, n,
                            bytes_.size() - at_));
    }
  }

  std::uint32_t u32(std::string_view what) {
    need(4, what);
    std::uint32_t v = 0;
    for (std::size_t i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(bytes_[at_ + i]) << (8 * i);
    at_ += 4;
    return v;
  }

  std::uint64_t u64(std::string_view what) {
    need(8, what);
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(bytes_[at_ + i]) << (8 * i);
    at_ += 8;
    return v;
  }

  std::span<const std::uint8_t> take(std::uint64_t n, std::string_view what) {
    need(n, what);
    const auto out = bytes_.subspan(at_, static_cast<std::size_t>(n));
    at_ += static_cast<std::size_t>(n);
    return out;
  }

  std::size_t left() const { return bytes_.size() - at_; }

 private:
  std::span<const std::uint8_t> bytes_;
  const std::string& name_;
  std::size_t at_ = 0;
};

// The line table after the symbols, checked to be canonical (isa::LineTable), so that a
// file loads as the one table that writes it.
void read_line_table(Reader& r, std::uint32_t code_words, LineTable& lines) {
  const std::size_t files_at = r.offset();
  const std::uint32_t file_count = r.u32("the source file count");
  // Each name takes at least 5 bytes (its length and one byte).
  if (file_count > r.left() / 5) {
    r.fail(files_at, fmt::format("{} source files, expected at most {} in the {} bytes left", file_count, r.left() / 5,
                                 r.left()));
  }
  for (std::uint32_t i = 0; i < file_count; ++i) {
    const std::size_t start = r.offset();
    const std::uint32_t length = r.u32("a source file name length");
    if (length == 0 || length > LineTable::kMaxFileName) {
      r.fail(start, fmt::format("a source file name of {} bytes, expected 1 to {}", length, LineTable::kMaxFileName));
    }
    const auto text = r.take(length, "a source file name");
    std::string file(text.begin(), text.end());
    if (std::any_of(file.begin(), file.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20; })) {
      r.fail(start + 4, fmt::format("source file name '{}' holds a control character", assembler::printable(file)));
    }
    lines.files.push_back(std::move(file));
  }
  const std::size_t runs_at = r.offset();
  const std::uint32_t run_count = r.u32("the count of runs of source lines");
  if (run_count > r.left() / 12) {
    r.fail(runs_at, fmt::format("{} runs of source lines, expected at most {} in the {} bytes left", run_count,
                                r.left() / 12, r.left()));
  }
  std::uint32_t files_named = 0;
  for (std::uint32_t i = 0; i < run_count; ++i) {
    const std::size_t start = r.offset();
    LineTable::Run run;
    run.pc = r.u32("a run's pc");
    run.source.file = r.u32("a run's source file");
    run.source.line = r.u32("a run's line");
    if (run.pc >= code_words || (i > 0 && run.pc <= lines.runs.back().pc)) {
      r.fail(start, fmt::format("a run of source lines at pc {}, expected a pc after {} and below {} (the code size)",
                                run.pc, i > 0 ? fmt::format("{}", lines.runs.back().pc) : std::string("none"),
                                code_words));
    }
    const bool known = run.source.file < files_named ||
                       (run.source.file == files_named && run.source.line != 0 && files_named < file_count);
    if (run.source.line == 0 ? run.source.file != 0 : !known) {
      r.fail(start + 4, fmt::format("a run at pc {} names source file {}, expected {}", run.pc, run.source.file,
                                    run.source.line == 0 ? std::string("0 (it has no line)")
                                                         : fmt::format("one of the {} named before or the next, {}",
                                                                       files_named, files_named)));
    }
    if (i == 0 ? run.source.line == 0 : run.source == lines.runs.back().source) {
      r.fail(start + 8, fmt::format("a run at pc {} with the line of the run before it (or none first), expected "
                                    "runs that change the line",
                                    run.pc));
    }
    files_named = std::max(files_named, run.source.line == 0 ? 0 : run.source.file + 1);
    lines.runs.push_back(run);
  }
  if (files_named != file_count) {
    r.fail(files_at, fmt::format("{} source files, of which the runs name {}; expected each named", file_count,
                                 files_named));
  }
}

bool is_predefined(std::string_view name) {
  for (const auto& s : spec::isa::kAsmSymbols) {
    if (s.name == name) return true;
  }
  return false;
}

}  // namespace

std::vector<std::uint8_t> firmware_to_bytes(const Firmware& firmware) {
  std::vector<std::uint8_t> out;
  put_u32(out, kFirmwareMagic);
  put_u32(out, kFirmwareVersion);
  put_u32(out, checked_u32(firmware.code.size(), "instructions"));
  put_u32(out, checked_u32(firmware.data.size(), "data bytes"));
  put_u32(out, checked_u32(firmware.symbols.size(), "symbols"));
  for (const std::uint64_t word : firmware.code) {
    put_u32(out, static_cast<std::uint32_t>(word));
    put_u32(out, static_cast<std::uint32_t>(word >> 32));
  }
  out.insert(out.end(), firmware.data.begin(), firmware.data.end());
  // std::map order: names ascending, which the loader requires (one file per firmware).
  for (const auto& [name, symbol] : firmware.symbols) {
    put_u32(out, static_cast<std::uint32_t>(symbol.kind));
    put_u32(out, symbol.value);
    put_u32(out, checked_u32(name.size(), "bytes in a symbol name"));
    out.insert(out.end(), name.begin(), name.end());
  }
  put_u32(out, checked_u32(firmware.lines.files.size(), "source files"));
  for (const std::string& file : firmware.lines.files) {
    put_u32(out, checked_u32(file.size(), "bytes in a source file name"));
    out.insert(out.end(), file.begin(), file.end());
  }
  put_u32(out, checked_u32(firmware.lines.runs.size(), "runs of source lines"));
  for (const LineTable::Run& run : firmware.lines.runs) {
    put_u32(out, run.pc);
    put_u32(out, run.source.file);
    put_u32(out, run.source.line);
  }
  return out;
}

Firmware firmware_from_bytes(std::span<const std::uint8_t> bytes, const std::string& name) {
  Reader r(bytes, name);
  const std::uint32_t magic = r.u32("the magic number");
  if (magic != kFirmwareMagic) {
    r.fail(0, fmt::format("magic {:#010x}, expected {:#010x} (\"RFW1\"): not an rpu firmware file", magic,
                          kFirmwareMagic));
  }
  const std::uint32_t version = r.u32("the version");
  if (version != kFirmwareVersion) {
    r.fail(4, fmt::format("version {}, expected {} (re-assemble the source with this rpu)", version,
                          kFirmwareVersion));
  }
  const std::uint32_t code_words = r.u32("the instruction count");
  const std::uint32_t data_bytes = r.u32("the data size");
  const std::uint32_t symbol_count = r.u32("the symbol count");
  Firmware fw;
  // Sizes are checked against the file before anything is allocated for them.
  r.need(std::uint64_t{code_words} * 8, fmt::format("the code of {} instructions", code_words));
  fw.code.reserve(code_words);
  for (std::uint32_t i = 0; i < code_words; ++i) fw.code.push_back(r.u64("an instruction"));
  const auto data = r.take(data_bytes, fmt::format("the data of {} bytes", data_bytes));
  fw.data.assign(data.begin(), data.end());
  // Each symbol takes at least 13 bytes (12 of fields and a 1-byte name).
  if (symbol_count > r.left() / 13) {
    r.fail(16, fmt::format("{} symbols, expected at most {} in the {} bytes left", symbol_count, r.left() / 13,
                           r.left()));
  }
  const std::string* previous = nullptr;
  for (std::uint32_t i = 0; i < symbol_count; ++i) {
    const std::size_t start = r.offset();
    const std::uint32_t kind = r.u32("a symbol kind");
    const std::uint32_t value = r.u32("a symbol value");
    const std::uint32_t length = r.u32("a symbol name length");
    const auto text = r.take(length, "a symbol name");
    std::string symbol_name(text.begin(), text.end());
    const std::string shown = assembler::printable(symbol_name);
    if (kind >= kSymbolKinds) {
      r.fail(start, fmt::format("symbol '{}' has kind {}, expected 0 (code), 1 (data) or 2 (constant)", shown, kind));
    }
    if (!is_symbol_name(symbol_name) || is_predefined(symbol_name)) {
      r.fail(start + 12, fmt::format("symbol name '{}', expected an assembler identifier that is not a register or "
                                     "a predefined memory-map symbol",
                                     shown));
    }
    if (previous && !(*previous < symbol_name)) {
      r.fail(start + 12, fmt::format("symbol '{}' after '{}', expected names in ascending byte order, each once", shown,
                                     assembler::printable(*previous)));
    }
    const auto k = static_cast<Symbol::Kind>(kind);
    if (k == Symbol::Kind::kCode && value > code_words) {
      r.fail(start + 4, fmt::format("code label '{}' at pc {}, expected at most {} (the code size)", shown, value,
                                    code_words));
    }
    const std::uint64_t data_base = spec::memory::kDeviceDataBase;
    if (k == Symbol::Kind::kData && (value < data_base || value - data_base > data_bytes)) {
      r.fail(start + 4, fmt::format("data label '{}' at {:#010x}, expected {:#010x} to {:#010x}", shown, value,
                                    data_base, data_base + data_bytes));
    }
    const auto it = fw.symbols.emplace(std::move(symbol_name), Symbol{k, value}).first;
    previous = &it->first;
  }
  read_line_table(r, code_words, fw.lines);
  if (r.left() != 0) {
    r.fail(r.offset(), fmt::format("{} bytes after the line table, expected the end of the file", r.left()));
  }
  return fw;
}

void save_firmware(const Firmware& firmware, const std::filesystem::path& file) {
  const std::vector<std::uint8_t> bytes = firmware_to_bytes(firmware);
  OutputFile out(file);
  out.stream().write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  out.commit();
}

namespace {

std::vector<std::uint8_t> read_firmware_bytes(const std::filesystem::path& file) {
  const std::string bytes = read_input_file(file, "the firmware file");
  return {bytes.begin(), bytes.end()};
}

}  // namespace

Firmware load_firmware(const std::filesystem::path& file) {
  return firmware_from_bytes(read_firmware_bytes(file), file.string());
}

Firmware load_firmware_or_assemble(const std::filesystem::path& file) {
  check_input_file(file, "the firmware");
  std::ifstream in(file, std::ios::binary);
  std::uint8_t head[4] = {};
  in.read(reinterpret_cast<char*>(head), sizeof head);
  std::uint32_t word = 0;
  for (int i = 0; i < 4; ++i) word |= std::uint32_t{head[i]} << (8 * i);
  const bool magic = in.gcount() == sizeof head && word == kFirmwareMagic;
  // A .rfw without the magic is a damaged firmware file, not a source: the loader says
  // what the first bytes are instead.
  if (magic || file.extension() == ".rfw") return load_firmware(file);
  return assemble(file);
}

}  // namespace rpu::isa
