; Directives and expressions (fuzz seed).
.equ A, (1 + 2) * 3 << 1 | 0x10 & ~0b11 ^ -4 / 2 % 3
.equ B, A + C
.equ C, LAUNCH_WIDTH_AT + DEVICE_DATA_BASE
.include "x.s"
.text
start: li r1.none, B
  lif r2, -2e-3
  lif r3, inf
  lif r4, 0x7fc00001
  ld r1, [r2.w - 4 + 2]
  st1 [r1 + table], r3.x
  bnz r1.y, start
  .insn 0xffffffffffffffff
.data
table: .word 1, -1, 0xffffffff, start
  .byte 1, 255, -128
  .align 16
f: .float 1.0, -0.0, nan, 1e-45
  .space 7
end:
