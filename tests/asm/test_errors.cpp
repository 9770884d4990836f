// Every class of assembler error, with its file:line:col and message. The columns are
// counted here by hand from the source text.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include <gmock/gmock.h>

#include "memory_sources.hpp"

namespace rpu::isa::test {
namespace {

using ::testing::HasSubstr;

struct ErrorCase {
  const char* name;
  const char* source;
  const char* message;  // must occur in the error text, from "file:line:col" on
};

class AsmError : public ::testing::TestWithParam<ErrorCase> {};

TEST_P(AsmError, NamesFileLineColumnAndWhatWasExpected) {
  const std::string message = assembly_error(GetParam().source);
  EXPECT_THAT(message, HasSubstr(GetParam().message)) << GetParam().source;
  // One error, one line, in the documented shape.
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_THAT(message, HasSubstr(", expected ")) << message;
}

const ErrorCase kCases[] = {
    {"UnknownMnemonicSuggestsTheClosest", "  mvo r1, r2",
     "main.s:1:3: error: unknown mnemonic 'mvo', expected an instruction of docs/isa.md (did you mean 'mov'?)"},
    {"MnemonicsAreLowerCase", "ADD r1, r2, r3", "main.s:1:1: error: unknown mnemonic 'ADD'"},
    {"TooFewOperands", "add r1, r2", "main.s:1:11: error: 2 operands, expected 3 (add d, a, b)"},
    {"TooManyOperands", "mov r1, r2, r3", "main.s:1:13: error: 3 operands, expected 2 (mov d, a)"},
    {"OperandsOfAnInstructionWithoutAny", "halt r1", "main.s:1:6: error: 1 operand, expected 0 (halt)"},
    {"EmptyOperand", "add r1, , r2", "main.s:1:9: error: ',', expected an operand"},
    {"RegisterOutOfRange", "mov r64, r1", "main.s:1:5: error: bad register 'r64', expected r0..r63"},
    {"RegisterWithLeadingZero", "mov r01, r1", "main.s:1:5: error: bad register 'r01'"},
    {"NotARegister", "mov x1, r1", "main.s:1:5: error: 'x1', expected a destination register r0..r63"},
    {"WriteMaskOnASource", "mov r1, r2.none",
     "main.s:1:11: error: write mask '.none' on a source, expected a swizzle"},
    {"SwizzleOnTheDestination", "mov r1.zx, r2",
     "main.s:1:7: error: swizzle '.zx' on the destination, expected a write mask"},
    {"RepeatedLaneInAWriteMask", "mov r1.xx, r2", "main.s:1:7: error: swizzle '.xx' on the destination"},
    {"BadSwizzleLetter", "mov r1, r2.xq", "main.s:1:11: error: bad swizzle '.xq', expected 1 to 4 lanes"},
    {"SwizzleTooLong", "mov r1, r2.xyzwx", "main.s:1:11: error: bad swizzle '.xyzwx'"},
    {"ModifierOnTheDestination", "mov -r1, r2", "main.s:1:5: error: modifier '-' on the destination"},
    {"NegOnAnIntegerInstruction", "iadd r1, -r2, r3",
     "main.s:1:10: error: neg '-' on source a of 'iadd', expected a plain register"},
    {"AbsOnAnIntegerInstruction", "sel r1, r2, |r3|, r4", "main.s:1:13: error: abs '|...|' on source b of 'sel'"},
    {"AbsOnSourceC", "mad r1, r2, r3, -|r4|",
     "main.s:1:18: error: abs '|...|' on source c of 'mad', expected no abs on source c"},
    {"NegOnAnAddressRegister", "ld r1, [-r2]",
     "main.s:1:9: error: neg '-' on the address register of 'ld', expected a plain register"},
    {"SwizzleInsideAbsBars", "mov r1, |r2.x|", "main.s:1:12: error: swizzle '.x' inside |...|"},
    {"UnclosedAbs", "mov r1, |r2", "main.s:1:12: error: end of line, expected '|' closing |r2|"},
    {"MissingBracket", "ld r1, r2", "main.s:1:8: error: 'r2', expected '[' starting a memory operand"},
    {"BadMemoryOperand", "ld r1, [r2 * 4]", "main.s:1:12: error: '*', expected '+', '-' or ']'"},
    {"DuplicateLabel", "a: halt\na: halt",
     "main.s:2:1: error: duplicate symbol 'a' (first defined at main.s:1), expected a new name"},
    {"LabelNamedLikeARegister", "r3: halt", "main.s:1:1: error: register name 'r3' as a label"},
    {"RedefinedMemoryMapSymbol", ".equ LAUNCH_WIDTH_AT, 4",
     "main.s:1:6: error: 'LAUNCH_WIDTH_AT', a predefined memory-map symbol, as a constant"},
    {"UndefinedSymbolSuggestsTheClosest", "loop: bra lopo",
     "main.s:1:11: error: undefined symbol 'lopo', expected a label, .equ constant or memory-map symbol (did "
     "you mean 'loop'?)"},
    {"RegisterAsAnImmediate", "li r1, r2", "main.s:1:8: error: 'r2', expected an integer expression, not a register"},
    {"ImmediateTooLarge", "li r1, 0x100000000",
     "main.s:1:8: error: value 4294967296 (0x100000000) out of range for the imm operand, expected a 32-bit"},
    {"ImmediateTooNegative", "li r1, -2147483649", "main.s:1:8: error: value -2147483649"},
    {"MemoryOffsetTooLarge", "ld r1, [r2 + 1 << 32]",
     "main.s:1:12: error: value 4294967296 (0x100000000) out of range for a memory offset"},
    {"LiteralBeyondSixtyFourBits", "li r1, 18446744073709551616",
     "main.s:1:8: error: '18446744073709551616', expected an integer that fits 64 bits"},
    {"FloatWhereAnIntegerBelongs", "li r1, 1.5", "main.s:1:8: error: '1.5', expected an integer"},
    {"DivisionByZero", "li r1, 4 / (2 - 2)", "main.s:1:10: error: division by zero"},
    {"ShiftTooFar", "li r1, 1 << 64", "main.s:1:10: error: shift by 64, expected a count from 0 to 63"},
    {"UnbalancedParenthesis", "li r1, (1 + 2", "main.s:1:14: error: end of line, expected ')' or an operator"},
    {"DanglingOperator", "li r1, 1 +", "main.s:1:11: error: end of line, expected a number, symbol"},
    {"ConstantDefinedByItself", ".equ A, B + 1\n.equ B, A\nli r1, A",
     "main.s:2:9: error: 'A' defined in terms of itself (A -> B -> A)"},
    {"ConstantOutOfRange", ".equ BIG, 1 << 40", "main.s:1:11: error: value 1099511627776 (0x10000000000) out of range for .equ BIG"},
    {"FloatOverflow", "lif r1, 1e39", "main.s:1:9: error: float literal 1e39 overflows fp32"},
    {"SignedNan", "lif r1, -nan", "main.s:1:9: error: '-nan', expected nan"},
    {"NotAFloat", "lif r1, foo", "main.s:1:9: error: 'foo', expected a float literal"},
    {"RawFloatBitsTooWide", "lif r1, 0x100000000", "main.s:1:9: error: raw float bits '0x100000000'"},
    {"MalformedNumber", "li r1, 12ab", "main.s:1:8: error: malformed number '12ab'"},
    {"UnexpectedCharacter", "li r1, 1 @ 2", "main.s:1:10: error: unexpected character '@'"},
    {"ControlByteShownEscaped", "li r1, \x01", "main.s:1:8: error: unexpected character '\\x01'"},
    {"UnknownDirectiveSuggestsTheClosest", ".wrod 1",
     "main.s:1:1: error: unknown directive '.wrod', expected one of .text .data .equ .include .word .byte .float "
     ".space .align .insn .loc (did you mean '.word'?)"},
    {"DataDirectiveInText", ".word 1", "main.s:1:1: error: '.word' in .text, expected it in .data"},
    {"InstructionInData", ".data\nhalt", "main.s:2:1: error: 'halt' in .data, expected it in .text"},
    {"ByteOutOfRange", ".data\n.byte 256", "main.s:2:7: error: value 256 out of range for .byte, expected -128 to 255"},
    {"AlignNotAPowerOfTwo", ".data\n.align 3", "main.s:2:8: error: .align 3, expected a power of two"},
    {"NegativeSpace", ".data\n.space -1", "main.s:2:8: error: .space -1, expected 0 to"},
    {"SpaceSizedByALaterLabel", ".data\n.space end - start\nstart: .word 1\nend:",
     "main.s:2:8: error: label 'end', which is defined later, expected constants or earlier labels"},
    {"DataLabelAsBranchTarget", "bra table\n.data\ntable: .word 0",
     "main.s:1:5: error: data label 'table' as a branch target, expected a code label"},
    {"IncludeWithoutAString", ".include main.s", "main.s:1:10: error: 'main.s', expected a quoted path"},
    {"UnterminatedString", ".include \"x.s", "main.s:1:10: error: unterminated string"},
    {"DirectiveWithExtraOperand", ".text 1", "main.s:1:7: error: '1' after .text, expected ',' or end of line"},
    {"InsnInData", ".data\n.insn 0", "main.s:2:1: error: '.insn' in .data, expected it in .text"},
    {"TextAfterTheOperand", "mov r1, r2 r3", "main.s:1:12: error: 'r3' after the operand, expected ','"},
    {"StrayToken", ", halt", "main.s:1:1: error: ',', expected a label, instruction or directive"},
    {"SourceLineWithoutAFileName", ".loc 12", "main.s:1:6: error: '12', expected a quoted file name of 1 to 4096"},
    {"SourceLineOfAnEmptyFileName", ".loc \"\", 3", "main.s:1:6: error: string \"\", expected a quoted file name"},
    {"SourceLineWithoutALine", ".loc \"a.rchit\"", "main.s:1:15: error: end of line, expected ',' and a line number"},
    {"SourceLineZero", ".loc \"a.rchit\", 0", "main.s:1:17: error: '0', expected a line number from 1 to"},
    {"SourceLineAfterTheLine", ".loc \"a.rchit\", 3 4", "main.s:1:19: error: '4' after the line number, expected"},
};

INSTANTIATE_TEST_SUITE_P(Classes, AsmError, ::testing::ValuesIn(kCases),
                         [](const auto& param_info) { return std::string(param_info.param.name); });

TEST(AsmErrors, AreCollectedOnePerLine) {
  const std::string message = assembly_error("mvo r1, r2\nhalt\nli r1, undefined_thing\nadd r1\n");
  EXPECT_THAT(message, HasSubstr("main.s:1:1: error: unknown mnemonic 'mvo'"));
  EXPECT_THAT(message, HasSubstr("\nmain.s:3:8: error: undefined symbol 'undefined_thing'"));
  EXPECT_THAT(message, HasSubstr("\nmain.s:4:7: error: 1 operand, expected 3"));
  EXPECT_EQ(std::count(message.begin(), message.end(), '\n'), 2) << message;
}

TEST(AsmErrors, StopAfterTwenty) {
  std::string source;
  for (int i = 0; i < 30; ++i) source += "bogus\n";
  const std::string message = assembly_error(source);
  EXPECT_EQ(std::count(message.begin(), message.end(), '\n'), 20) << message;
  EXPECT_THAT(message, HasSubstr("main.s:20:1: error: unknown mnemonic 'bogus'"));
  EXPECT_EQ(message.find("main.s:21:"), std::string::npos) << message;
  EXPECT_THAT(message, HasSubstr("\ntoo many errors, stopped after 20"));
}

TEST(AsmErrors, AConstantWithAnErrorIsReportedOnceNotAtEveryUse) {
  const std::string message = assembly_error(".equ A, nothing\nli r1, A\nli r2, A\n");
  EXPECT_THAT(message, HasSubstr("main.s:1:9: error: undefined symbol 'nothing'"));
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(AsmErrors, MissingMainFile) {
  MemorySources sources;
  try {
    sources.assemble("nowhere.s");
    ADD_FAILURE() << "assembled a file that does not exist";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("nowhere.s: error: cannot read the file"));
  }
}

TEST(AsmErrors, MissingIncludeNamesTheChain) {
  MemorySources sources;
  sources.files["lib/a.s"] = "halt\n.include \"b.s\"\n";
  const std::string message = assembly_error(".include \"lib/a.s\"", sources);
  EXPECT_THAT(message, HasSubstr("lib/a.s:2:10: error: cannot read 'b.s' (include chain main.s:1 -> lib/a.s:2 -> "
                                 "lib/b.s), expected an existing file"));
}

TEST(AsmErrors, IncludeCycleNamesTheChain) {
  MemorySources sources;
  sources.files["a.s"] = ".include \"b.s\"\n";
  sources.files["b.s"] = "\n.include \"a.s\"\n";
  const std::string message = assembly_error(".include \"a.s\"", sources);
  EXPECT_THAT(message, HasSubstr("b.s:2:10: error: include cycle main.s:1 -> a.s:1 -> b.s:2 -> a.s, expected a file "
                                 "that is not already being included"));
}

TEST(AsmErrors, ErrorsInIncludedFilesNameThatFile) {
  MemorySources sources;
  sources.files["inc/x.s"] = "\n\n   bogus r1\n";
  EXPECT_THAT(assembly_error("halt\n.include \"inc/x.s\"", sources),
              HasSubstr("inc/x.s:3:4: error: unknown mnemonic 'bogus'"));
}

TEST(AsmErrors, DeepExpressionsAreRefusedNotOverflowed) {
  const std::string source = "li r1, " + std::string(5000, '(') + "1" + std::string(5000, ')');
  EXPECT_THAT(assembly_error(source), HasSubstr("main.s:1:"));
  std::string sum = "li r1, 1";
  for (int i = 0; i < 5000; ++i) sum += " + 1";
  EXPECT_THAT(assembly_error(sum), HasSubstr("expected at most 200 levels"));
}

TEST(AsmErrors, LongConstantChainsAreRefusedNotOverflowed) {
  std::string source = "li r1, C0\n";
  for (int i = 0; i < 1000; ++i) source += ".equ C" + std::to_string(i) + ", C" + std::to_string(i + 1) + "\n";
  source += ".equ C1000, 1\n";
  EXPECT_THAT(assembly_error(source), HasSubstr("chain of 100 constants"));
}

}  // namespace
}  // namespace rpu::isa::test
