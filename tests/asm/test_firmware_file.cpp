// The .rfw firmware file: the byte layout of docs/assembler.md, save/load round trip,
// and rejection of every malformed file with the offset of the problem.
#include <gtest/gtest.h>

#include <gmock/gmock.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "asm/firmware_file.hpp"
#include "common/error.hpp"
#include "memory_sources.hpp"

namespace rpu::isa::test {
namespace {

using ::testing::HasSubstr;

Firmware small_firmware() {
  Firmware fw;
  fw.code = {0x0102030405060708ull};
  fw.data = {0xaa, 0xbb};
  fw.symbols["go"] = {Symbol::Kind::kCode, 1};
  fw.symbols["K"] = {Symbol::Kind::kConstant, 0xdeadbeef};
  fw.symbols["d"] = {Symbol::Kind::kData, 0x50000002};
  fw.lines.add(0, "a.s", 7);
  return fw;
}

// docs/assembler.md, written out by hand.
const std::vector<std::uint8_t> kSmallFile{
    'R', 'F', 'W', '1',                              // magic
    2, 0, 0, 0,                                      // version
    1, 0, 0, 0,                                      // instructions
    2, 0, 0, 0,                                      // data bytes
    3, 0, 0, 0,                                      // symbols
    0x08, 0x07, 0x06, 0x05, 0x04, 0x03, 0x02, 0x01,  // code[0]
    0xaa, 0xbb,                                      // data
    2, 0, 0, 0, 0xef, 0xbe, 0xad, 0xde, 1, 0, 0, 0, 'K',  // "K" < "d" < "go" byte-wise
    1, 0, 0, 0, 0x02, 0, 0, 0x50, 1, 0, 0, 0, 'd',
    0, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 'g', 'o',
    1, 0, 0, 0, 3, 0, 0, 0, 'a', '.', 's',           // source files: "a.s"
    1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 7, 0, 0, 0,  // runs: pc 0 from file 0, line 7
};

void expect_same(const Firmware& a, const Firmware& b) {
  EXPECT_EQ(a.code, b.code);
  EXPECT_EQ(a.data, b.data);
  ASSERT_EQ(a.symbols.size(), b.symbols.size());
  for (const auto& [name, s] : a.symbols) {
    ASSERT_TRUE(b.symbols.contains(name)) << name;
    EXPECT_EQ(b.symbols.at(name).kind, s.kind) << name;
    EXPECT_EQ(b.symbols.at(name).value, s.value) << name;
  }
  EXPECT_EQ(a.lines, b.lines);
}

std::string load_error(const std::vector<std::uint8_t>& bytes) {
  try {
    firmware_from_bytes(bytes, "t.rfw");
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted a bad file of " << bytes.size() << " bytes";
  return "";
}

TEST(FirmwareFile, LayoutIsAsDocumented) {
  EXPECT_EQ(firmware_to_bytes(small_firmware()), kSmallFile);
  expect_same(firmware_from_bytes(kSmallFile, "t.rfw"), small_firmware());
}

TEST(FirmwareFile, SaveAndLoadAnAssembledProgram) {
  const Firmware fw = assemble_text(".equ N, 3\nmain: li r1, N\nhalt\n.data\nt: .word 1, 2\n.byte 9\nend:\n");
  const auto path = std::filesystem::path(testing::TempDir()) / "round_trip.rfw";
  save_firmware(fw, path);
  expect_same(load_firmware(path), fw);
  std::filesystem::remove(path);
}

TEST(FirmwareFile, EveryTruncationIsRejectedWithAnOffset) {
  for (std::size_t n = 0; n < kSmallFile.size(); ++n) {
    const std::vector<std::uint8_t> cut(kSmallFile.begin(), kSmallFile.begin() + static_cast<std::ptrdiff_t>(n));
    EXPECT_THAT(load_error(cut), HasSubstr("t.rfw: offset ")) << n << " bytes";
  }
}

TEST(FirmwareFile, BadMagicIsNotFirmware) {
  std::vector<std::uint8_t> bytes = kSmallFile;
  bytes[0] = 0x7f;
  EXPECT_THAT(load_error(bytes), HasSubstr("t.rfw: offset 0: magic 0x3157467f, expected 0x31574652"));
}

TEST(FirmwareFile, OtherVersionIsRejected) {
  std::vector<std::uint8_t> bytes = kSmallFile;
  bytes[4] = 1;  // a file from before the line table
  EXPECT_THAT(load_error(bytes), HasSubstr("t.rfw: offset 4: version 1, expected 2 (re-assemble the source"));
}

TEST(FirmwareFile, HugeCountsFailBeforeAllocating) {
  std::vector<std::uint8_t> bytes = kSmallFile;
  bytes[8] = bytes[9] = bytes[10] = bytes[11] = 0xff;
  EXPECT_THAT(load_error(bytes), HasSubstr("t.rfw: offset 20: the code of 4294967295 instructions needs"));
  bytes = kSmallFile;
  bytes[16] = bytes[17] = bytes[18] = bytes[19] = 0xff;
  EXPECT_THAT(load_error(bytes), HasSubstr("t.rfw: offset 16: 4294967295 symbols"));
}

TEST(FirmwareFile, BadSymbolsAreRejectedAtTheirOffset) {
  constexpr std::size_t kFirst = 30;  // the first symbol: after 20 header, 8 code, 2 data bytes
  std::vector<std::uint8_t> bytes = kSmallFile;
  bytes[kFirst] = 3;
  EXPECT_THAT(load_error(bytes), HasSubstr("offset 30: symbol 'K' has kind 3, expected 0 (code)"));
  bytes = kSmallFile;
  bytes[kFirst + 12] = '1';
  EXPECT_THAT(load_error(bytes), HasSubstr("offset 42: symbol name '1', expected an assembler identifier"));
  bytes = kSmallFile;
  bytes[kFirst + 12] = 'z';  // "z" > "d": out of order
  EXPECT_THAT(load_error(bytes), HasSubstr("offset 55: symbol 'd' after 'z', expected names in ascending"));
  bytes = kSmallFile;
  bytes[kFirst + 26 + 4] = 2;  // "go" at pc 2 of a 1-instruction program
  EXPECT_THAT(load_error(bytes), HasSubstr("offset 60: code label 'go' at pc 2, expected at most 1"));
  bytes = kSmallFile;
  bytes[kFirst + 13 + 4] = 3;  // "d" at 0x50000003, past the 2 data bytes
  EXPECT_THAT(load_error(bytes), HasSubstr("offset 47: data label 'd' at 0x50000003"));
  bytes = kSmallFile;
  bytes.push_back(0);
  EXPECT_THAT(load_error(bytes), HasSubstr("offset 97: 1 bytes after the line table"));
}

TEST(FirmwareFile, BadLineTablesAreRejectedAtTheirOffset) {
  constexpr std::size_t kFiles = 70, kRun = 85;  // after the symbols; the first run after "a.s"
  std::vector<std::uint8_t> bytes = kSmallFile;
  bytes[kFiles + 4] = 0;
  EXPECT_THAT(load_error(bytes), HasSubstr("offset 74: a source file name of 0 bytes, expected 1 to 4096"));
  bytes = kSmallFile;
  bytes[kFiles + 8] = '\n';
  EXPECT_THAT(load_error(bytes), HasSubstr("offset 78: source file name"));
  EXPECT_THAT(load_error(bytes), HasSubstr("holds a control character"));
  bytes = kSmallFile;
  bytes[kRun] = 1;
  EXPECT_THAT(load_error(bytes), HasSubstr("offset 85: a run of source lines at pc 1, expected a pc after none and "
                                           "below 1 (the code size)"));
  bytes = kSmallFile;
  bytes[kRun + 4] = 1;
  EXPECT_THAT(load_error(bytes), HasSubstr("offset 89: a run at pc 0 names source file 1, expected one of the 0 "
                                           "named before or the next, 0"));
  bytes = kSmallFile;
  bytes[kRun + 8] = 0;
  EXPECT_THAT(load_error(bytes), HasSubstr("offset 93: a run at pc 0 with the line of the run before it (or none "
                                           "first)"));
  // Written by firmware_to_bytes, refused by the loader: tables that are not canonical.
  Firmware fw = small_firmware();
  fw.lines.files.push_back("b.s");
  EXPECT_THAT(load_error(firmware_to_bytes(fw)), HasSubstr("offset 70: 2 source files, of which the runs name 1"));
  fw = small_firmware();
  fw.code.push_back(0);
  fw.lines.runs.push_back({1, {0, 7}});
  EXPECT_THAT(load_error(firmware_to_bytes(fw)), HasSubstr("a run at pc 1 with the line of the run before it"));
}

TEST(FirmwareFile, MissingFileNamesIt) {
  try {
    load_firmware("/nonexistent/x.rfw");
    ADD_FAILURE() << "loaded a missing file";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("the firmware file /nonexistent/x.rfw: no such file"));
  }
}

}  // namespace
}  // namespace rpu::isa::test
