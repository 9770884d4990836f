// The intersection unit: one ray/triangle test (docs/traversal.md §4 Woop's unit-triangle
// test, or §5 the watertight test, chosen by IsectMode), bit for bit the operation
// sequence of intersect_woop / intersect_watertight in
// cmodel/functional/intersection_unit.hpp. Every rounded operation runs on the shared FP
// units: rpu_fp_fma (add, sub, mul; never a fused multiply-add), rpu_fp_divsqrt (div)
// and rpu_fp_misc (from_fp32 to round the record's words into the format, and the
// compares). The unit itself only sequences ops and moves values; the one exact step it
// does itself is Woop's t = -(oz / dz), a sign flip on the quotient (soft's neg: a NaN
// stays the canonical NaN).
//
// Micro-sequencing: two fixed programs (below) run in order, one feeding rpu_fp_fma and
// the divider (one op a cycle), one feeding rpu_fp_misc. Each value is written once per
// test into its own register (T0, T1, ...), compares into flags; a scoreboard bit says
// when a register has its value, and an op issues when its operands have theirs and
// its unit is ready. The FP response tag names the destination. Nothing depends on the
// data: every op of the program runs, even when an early compare has already rejected
// the triangle, and the FP units' latencies are fixed, so the latency of a test is a
// constant per (mode, format) (docs/rtl.md lists it).
//
// Handshake: one test at a time. req_ready_o is high when idle, or while the response
// is being taken (so at full rate the initiation interval equals the latency).
module rpu_iu #(
  parameter int unsigned ExpBits   = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits  = rpu_pkg::FormatFp32FractionBits,
  parameter int unsigned IsectMode = rpu_pkg::IsectModeWoop
) (
  input  logic             clk_i,
  input  logic             rst_ni,

  input  logic             req_valid_i,
  output logic             req_ready_o,
  input  rpu_pkg::iu_req_t req_i,

  output logic             rsp_valid_o,
  input  logic             rsp_ready_i,
  output rpu_pkg::iu_rsp_t rsp_o
);

  localparam int unsigned W = 1 + ExpBits + FracBits;
  localparam bit Watertight = IsectMode == rpu_pkg::IsectModeWatertight;
  localparam int unsigned Words = rpu_pkg::IsectRecordWords;
  localparam int unsigned OpBits = rpu_pkg::FpOpBits;
  localparam int unsigned TagBits = rpu_pkg::FpTagBits;
  localparam logic [W-1:0] One = {2'b00, {(ExpBits - 1){1'b1}}, {FracBits{1'b0}}};

  // Operand sources, one index space: the request's ray values, two constants, the
  // record's raw fp32 words (only from_fp32 reads them) and the registers T0...
  localparam int unsigned SO = 0;           // origin x, y, z
  localparam int unsigned SD = 3;           // direction x, y, z
  localparam int unsigned STMin = 6;
  localparam int unsigned STBest = 7;
  localparam int unsigned SSx = 8;
  localparam int unsigned SSy = 9;
  localparam int unsigned SZero = 10;       // +0
  localparam int unsigned SOne = 11;
  localparam int unsigned SW = 12;          // record word 0..Words-1
  localparam int unsigned ST = SW + Words;  // register T0
  // Row r of the record (spec/memory_map.toml [triangle_record]): its x, y, z, w words
  // are sources SRr + 0..3.
  localparam int unsigned SR0 = SW + rpu_pkg::TriangleRecordRow0At / 4;
  localparam int unsigned SR1 = SW + rpu_pkg::TriangleRecordRow1At / 4;
  localparam int unsigned SR2 = SW + rpu_pkg::TriangleRecordRow2At / 4;
  localparam int unsigned NumTemps = Watertight ? 60 : 51;
  localparam int unsigned NumFlags = Watertight ? 10 : 6;
  localparam int unsigned NumSrc = ST + NumTemps;
  localparam int unsigned SrcBits = $clog2(NumSrc);
  localparam int unsigned FLen = Watertight ? 48 : 39;  // fma/div program length
  localparam int unsigned MLen = Watertight ? 22 : 18;  // misc program length
  localparam int unsigned PcBits = 6;
  // The registers holding the response (see the programs).
  localparam int unsigned TOutT = Watertight ? 57 : 23;
  localparam int unsigned TOutU = Watertight ? 58 : 48;
  localparam int unsigned TOutV = Watertight ? 59 : 49;

  // A result tag: {flag, negate, index}. flag: the index is a flag (a compare's 0/1),
  // else a register; negate: the sign of the result is flipped on its way in (Woop's t).
  localparam int unsigned IndexBits = TagBits - 2;
  // Watertight: a P' = P - O component goes to register base + rank of its axis
  // (kx 0, ky 1, kz 2), so later ops find P'[kx], P'[ky], P'[kz] at fixed registers.
  localparam int unsigned NoAxis = 3;
  localparam int unsigned UopBits = OpBits + 2 * SrcBits + TagBits + 2;

  // A micro-op word {op, a, b, kind, index, axis}, from integer fields: built by
  // arithmetic so that every bit of the arguments is read (no unused-bit lint), and
  // the fields are small enough that the sum never carries across them.
  localparam int unsigned KindReg = 0, KindNeg = 1, KindFlag = 2;
  function automatic logic [UopBits-1:0] uop_word(input rpu_pkg::fp_op_e op, input int unsigned a,
                                                  input int unsigned b, input int unsigned kind,
                                                  input int unsigned index, input int unsigned axis);
    uop_word = UopBits'((32'(op) << (2 * SrcBits + TagBits + 2)) + (a << (SrcBits + TagBits + 2))
                        + (b << (TagBits + 2)) + (kind << (IndexBits + 2)) + (index << 2) + axis);
  endfunction
  // Result into register t.
  function automatic logic [UopBits-1:0] uop(input rpu_pkg::fp_op_e op, input int unsigned a,
                                             input int unsigned b, input int unsigned t);
    uop = uop_word(op, a, b, KindReg, t, NoAxis);
  endfunction
  // Result with its sign flipped into register t.
  function automatic logic [UopBits-1:0] uop_neg(input rpu_pkg::fp_op_e op, input int unsigned a,
                                                 input int unsigned b, input int unsigned t);
    uop_neg = uop_word(op, a, b, KindNeg, t, NoAxis);
  endfunction
  // Result into flag f.
  function automatic logic [UopBits-1:0] uop_flag(input rpu_pkg::fp_op_e op, input int unsigned a,
                                                  input int unsigned b, input int unsigned f);
    uop_flag = uop_word(op, a, b, KindFlag, f, NoAxis);
  endfunction
  // Result into register t + rank(axis).
  function automatic logic [UopBits-1:0] uop_axis(input rpu_pkg::fp_op_e op, input int unsigned a,
                                                  input int unsigned b, input int unsigned t,
                                                  input int unsigned axis);
    uop_axis = uop_word(op, a, b, KindReg, t, axis);
  endfunction

  // ---------------------------------------------------------------------------------
  // The programs. Tk is source ST + k. Comments give the C++ names.
  // ---------------------------------------------------------------------------------
  logic [PcBits-1:0]  f_pc_d, f_pc_q, m_pc_d, m_pc_q;
  logic [UopBits-1:0] f_uop, m_uop;

  always_comb begin
    f_uop = uop(rpu_pkg::FpOpAdd, SZero, SZero, 0);
    m_uop = uop(rpu_pkg::FpOpFromFp32, SZero, SZero, 0);
    if (!Watertight) begin
      // §4. T0..T11 = the record's words m[0..11] in the format, A (the w words) and
      // row 2 first; T12..T14 = P = O - A.
      unique case (f_pc_q)
        6'd0:  f_uop = uop(rpu_pkg::FpOpSub, SO + 0, ST + 3, 12);   // O0 - A0
        6'd1:  f_uop = uop(rpu_pkg::FpOpSub, SO + 1, ST + 7, 13);   // O1 - A1
        6'd2:  f_uop = uop(rpu_pkg::FpOpSub, SO + 2, ST + 11, 14);  // O2 - A2
        6'd3:  f_uop = uop(rpu_pkg::FpOpMul, ST + 8, ST + 12, 16);  // m8 * P0
        6'd4:  f_uop = uop(rpu_pkg::FpOpMul, ST + 9, ST + 13, 17);  // m9 * P1
        6'd5:  f_uop = uop(rpu_pkg::FpOpMul, ST + 10, ST + 14, 18); // m10 * P2
        6'd6:  f_uop = uop(rpu_pkg::FpOpMul, ST + 8, SD + 0, 19);   // m8 * D0
        6'd7:  f_uop = uop(rpu_pkg::FpOpMul, ST + 9, SD + 1, 20);   // m9 * D1
        6'd8:  f_uop = uop(rpu_pkg::FpOpMul, ST + 10, SD + 2, 21);  // m10 * D2
        6'd9:  f_uop = uop(rpu_pkg::FpOpAdd, ST + 16, ST + 17, 22);
        6'd10: f_uop = uop(rpu_pkg::FpOpAdd, ST + 19, ST + 20, 24);
        6'd11: f_uop = uop(rpu_pkg::FpOpAdd, ST + 22, ST + 18, 25);  // oz = dp3(r2, P)
        6'd12: f_uop = uop(rpu_pkg::FpOpAdd, ST + 24, ST + 21, 26);  // dz
        6'd13: f_uop = uop_neg(rpu_pkg::FpOpDiv, ST + 25, ST + 26, 23);  // t = -(oz / dz)
        // Rows 0 and 1 while the divider works.
        6'd14: f_uop = uop(rpu_pkg::FpOpMul, ST + 0, ST + 12, 27);
        6'd15: f_uop = uop(rpu_pkg::FpOpMul, ST + 1, ST + 13, 28);
        6'd16: f_uop = uop(rpu_pkg::FpOpMul, ST + 2, ST + 14, 29);
        6'd17: f_uop = uop(rpu_pkg::FpOpMul, ST + 0, SD + 0, 30);
        6'd18: f_uop = uop(rpu_pkg::FpOpMul, ST + 1, SD + 1, 31);
        6'd19: f_uop = uop(rpu_pkg::FpOpMul, ST + 2, SD + 2, 32);
        6'd20: f_uop = uop(rpu_pkg::FpOpAdd, ST + 27, ST + 28, 33);
        6'd21: f_uop = uop(rpu_pkg::FpOpAdd, ST + 30, ST + 31, 34);
        6'd22: f_uop = uop(rpu_pkg::FpOpAdd, ST + 33, ST + 29, 35);  // ox = dp3(r0, P)
        6'd23: f_uop = uop(rpu_pkg::FpOpAdd, ST + 34, ST + 32, 36);  // dx
        6'd24: f_uop = uop(rpu_pkg::FpOpMul, ST + 4, ST + 12, 37);
        6'd25: f_uop = uop(rpu_pkg::FpOpMul, ST + 5, ST + 13, 38);
        6'd26: f_uop = uop(rpu_pkg::FpOpMul, ST + 6, ST + 14, 39);
        6'd27: f_uop = uop(rpu_pkg::FpOpMul, ST + 4, SD + 0, 40);
        6'd28: f_uop = uop(rpu_pkg::FpOpMul, ST + 5, SD + 1, 41);
        6'd29: f_uop = uop(rpu_pkg::FpOpMul, ST + 6, SD + 2, 42);
        6'd30: f_uop = uop(rpu_pkg::FpOpAdd, ST + 37, ST + 38, 43);
        6'd31: f_uop = uop(rpu_pkg::FpOpAdd, ST + 40, ST + 41, 44);
        6'd32: f_uop = uop(rpu_pkg::FpOpAdd, ST + 43, ST + 39, 45);  // oy = dp3(r1, P)
        6'd33: f_uop = uop(rpu_pkg::FpOpAdd, ST + 44, ST + 42, 46);  // dy
        6'd34: f_uop = uop(rpu_pkg::FpOpMul, ST + 23, ST + 36, 47);  // t * dx
        6'd35: f_uop = uop(rpu_pkg::FpOpMul, ST + 23, ST + 46, 15);  // t * dy
        6'd36: f_uop = uop(rpu_pkg::FpOpAdd, ST + 35, ST + 47, 48);  // u
        6'd37: f_uop = uop(rpu_pkg::FpOpAdd, ST + 45, ST + 15, 49);  // v
        6'd38: f_uop = uop(rpu_pkg::FpOpAdd, ST + 48, ST + 49, 50);  // u + v
        default: ;
      endcase
      unique case (m_pc_q)
        6'd0:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR0 + 3, SZero, 3);
        6'd1:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR1 + 3, SZero, 7);
        6'd2:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR2 + 3, SZero, 11);
        6'd3:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR2 + 0, SZero, 8);
        6'd4:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR2 + 1, SZero, 9);
        6'd5:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR2 + 2, SZero, 10);
        6'd6:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR0 + 0, SZero, 0);
        6'd7:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR0 + 1, SZero, 1);
        6'd8:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR0 + 2, SZero, 2);
        6'd9:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR1 + 0, SZero, 4);
        6'd10: m_uop = uop(rpu_pkg::FpOpFromFp32, SR1 + 1, SZero, 5);
        6'd11: m_uop = uop(rpu_pkg::FpOpFromFp32, SR1 + 2, SZero, 6);
        6'd12: m_uop = uop_flag(rpu_pkg::FpOpGt, ST + 23, STMin, 0);   // t > t_min
        6'd13: m_uop = uop_flag(rpu_pkg::FpOpLt, ST + 23, STBest, 1);  // t < t_best
        6'd14: m_uop = uop_flag(rpu_pkg::FpOpLe, SZero, ST + 48, 2);   // 0 <= u
        6'd15: m_uop = uop_flag(rpu_pkg::FpOpLe, ST + 48, SOne, 3);    // u <= 1
        6'd16: m_uop = uop_flag(rpu_pkg::FpOpLe, SZero, ST + 49, 4);   // 0 <= v
        6'd17: m_uop = uop_flag(rpu_pkg::FpOpLe, ST + 50, SOne, 5);    // u + v <= 1
        default: ;
      endcase
    end else begin
      // §5. T0..T8 = A, B, C (x, y, z each) in the format; T9..T17 = P' = P - O per
      // vertex as (P'[kx], P'[ky], P'[kz]); T41..T43 = the normal n (the w words);
      // T44..T46 = A' = A - O again, in axis order x, y, z, for t = n.A' / n.D.
      unique case (f_pc_q)
        6'd0:  f_uop = uop_axis(rpu_pkg::FpOpSub, ST + 0, SO + 0, 9, 0);
        6'd1:  f_uop = uop_axis(rpu_pkg::FpOpSub, ST + 1, SO + 1, 9, 1);
        6'd2:  f_uop = uop_axis(rpu_pkg::FpOpSub, ST + 2, SO + 2, 9, 2);
        6'd3:  f_uop = uop_axis(rpu_pkg::FpOpSub, ST + 3, SO + 0, 12, 0);
        6'd4:  f_uop = uop_axis(rpu_pkg::FpOpSub, ST + 4, SO + 1, 12, 1);
        6'd5:  f_uop = uop_axis(rpu_pkg::FpOpSub, ST + 5, SO + 2, 12, 2);
        6'd6:  f_uop = uop_axis(rpu_pkg::FpOpSub, ST + 6, SO + 0, 15, 0);
        6'd7:  f_uop = uop_axis(rpu_pkg::FpOpSub, ST + 7, SO + 1, 15, 1);
        6'd8:  f_uop = uop_axis(rpu_pkg::FpOpSub, ST + 8, SO + 2, 15, 2);
        6'd9:  f_uop = uop(rpu_pkg::FpOpMul, SSx, ST + 11, 18);  // Sx * A'[kz]
        6'd10: f_uop = uop(rpu_pkg::FpOpMul, SSy, ST + 11, 19);  // Sy * A'[kz]
        6'd11: f_uop = uop(rpu_pkg::FpOpMul, SSx, ST + 14, 20);
        6'd12: f_uop = uop(rpu_pkg::FpOpMul, SSy, ST + 14, 21);
        6'd13: f_uop = uop(rpu_pkg::FpOpMul, SSx, ST + 17, 22);
        6'd14: f_uop = uop(rpu_pkg::FpOpMul, SSy, ST + 17, 23);
        6'd15: f_uop = uop(rpu_pkg::FpOpSub, ST + 0, SO + 0, 44);  // A'x
        6'd16: f_uop = uop(rpu_pkg::FpOpSub, ST + 1, SO + 1, 45);  // A'y
        6'd17: f_uop = uop(rpu_pkg::FpOpSub, ST + 2, SO + 2, 46);  // A'z
        6'd18: f_uop = uop(rpu_pkg::FpOpSub, ST + 9, ST + 18, 24);   // Ax
        6'd19: f_uop = uop(rpu_pkg::FpOpSub, ST + 10, ST + 19, 27);  // Ay
        6'd20: f_uop = uop(rpu_pkg::FpOpSub, ST + 12, ST + 20, 25);  // Bx
        6'd21: f_uop = uop(rpu_pkg::FpOpSub, ST + 13, ST + 21, 28);  // By
        6'd22: f_uop = uop(rpu_pkg::FpOpSub, ST + 15, ST + 22, 26);  // Cx
        6'd23: f_uop = uop(rpu_pkg::FpOpSub, ST + 16, ST + 23, 29);  // Cy
        6'd24: f_uop = uop(rpu_pkg::FpOpMul, ST + 26, ST + 28, 30);  // Cx * By
        6'd25: f_uop = uop(rpu_pkg::FpOpMul, ST + 29, ST + 25, 31);  // Cy * Bx
        6'd26: f_uop = uop(rpu_pkg::FpOpMul, ST + 24, ST + 29, 32);  // Ax * Cy
        6'd27: f_uop = uop(rpu_pkg::FpOpMul, ST + 27, ST + 26, 33);  // Ay * Cx
        6'd28: f_uop = uop(rpu_pkg::FpOpMul, ST + 25, ST + 27, 34);  // Bx * Ay
        6'd29: f_uop = uop(rpu_pkg::FpOpMul, ST + 28, ST + 24, 35);  // By * Ax
        6'd30: f_uop = uop(rpu_pkg::FpOpSub, ST + 30, ST + 31, 36);  // U
        6'd31: f_uop = uop(rpu_pkg::FpOpSub, ST + 32, ST + 33, 37);  // V
        6'd32: f_uop = uop(rpu_pkg::FpOpSub, ST + 34, ST + 35, 38);  // W
        6'd33: f_uop = uop(rpu_pkg::FpOpAdd, ST + 36, ST + 37, 39);  // U + V
        6'd34: f_uop = uop(rpu_pkg::FpOpAdd, ST + 39, ST + 38, 40);  // det
        6'd35: f_uop = uop(rpu_pkg::FpOpDiv, ST + 37, ST + 40, 58);  // u = V / det
        // The plane distance while the divider works on u.
        6'd36: f_uop = uop(rpu_pkg::FpOpMul, ST + 41, SD + 0, 52);   // n.x * D.x
        6'd37: f_uop = uop(rpu_pkg::FpOpMul, ST + 42, SD + 1, 53);
        6'd38: f_uop = uop(rpu_pkg::FpOpMul, ST + 43, SD + 2, 54);
        6'd39: f_uop = uop(rpu_pkg::FpOpMul, ST + 41, ST + 44, 47);  // n.x * A'x
        6'd40: f_uop = uop(rpu_pkg::FpOpMul, ST + 42, ST + 45, 48);
        6'd41: f_uop = uop(rpu_pkg::FpOpMul, ST + 43, ST + 46, 49);
        6'd42: f_uop = uop(rpu_pkg::FpOpAdd, ST + 52, ST + 53, 55);
        6'd43: f_uop = uop(rpu_pkg::FpOpAdd, ST + 47, ST + 48, 50);
        6'd44: f_uop = uop(rpu_pkg::FpOpAdd, ST + 55, ST + 54, 56);  // n.D
        6'd45: f_uop = uop(rpu_pkg::FpOpAdd, ST + 50, ST + 49, 51);  // n.A'
        6'd46: f_uop = uop(rpu_pkg::FpOpDiv, ST + 51, ST + 56, 57);  // t = n.A' / n.D
        6'd47: f_uop = uop(rpu_pkg::FpOpDiv, ST + 38, ST + 40, 59);  // v = W / det
        default: ;
      endcase
      unique case (m_pc_q)
        6'd0:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR0 + 0, SZero, 0);
        6'd1:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR0 + 1, SZero, 1);
        6'd2:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR0 + 2, SZero, 2);
        6'd3:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR1 + 0, SZero, 3);
        6'd4:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR1 + 1, SZero, 4);
        6'd5:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR1 + 2, SZero, 5);
        6'd6:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR2 + 0, SZero, 6);
        6'd7:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR2 + 1, SZero, 7);
        6'd8:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR2 + 2, SZero, 8);
        6'd9:  m_uop = uop(rpu_pkg::FpOpFromFp32, SR0 + 3, SZero, 41);   // n.x
        6'd10: m_uop = uop(rpu_pkg::FpOpFromFp32, SR1 + 3, SZero, 42);   // n.y
        6'd11: m_uop = uop(rpu_pkg::FpOpFromFp32, SR2 + 3, SZero, 43);  // n.z
        6'd12: m_uop = uop_flag(rpu_pkg::FpOpLt, ST + 36, SZero, 0);  // U < 0
        6'd13: m_uop = uop_flag(rpu_pkg::FpOpLt, ST + 37, SZero, 1);  // V < 0
        6'd14: m_uop = uop_flag(rpu_pkg::FpOpLt, ST + 38, SZero, 2);  // W < 0
        6'd15: m_uop = uop_flag(rpu_pkg::FpOpGt, ST + 36, SZero, 3);  // U > 0
        6'd16: m_uop = uop_flag(rpu_pkg::FpOpGt, ST + 37, SZero, 4);  // V > 0
        6'd17: m_uop = uop_flag(rpu_pkg::FpOpGt, ST + 38, SZero, 5);  // W > 0
        6'd18: m_uop = uop_flag(rpu_pkg::FpOpLt, ST + 40, SZero, 6);  // det < 0
        6'd19: m_uop = uop_flag(rpu_pkg::FpOpGt, ST + 40, SZero, 7);  // det > 0
        6'd20: m_uop = uop_flag(rpu_pkg::FpOpGt, ST + 57, STMin, 8);  // t > t_min
        6'd21: m_uop = uop_flag(rpu_pkg::FpOpLt, ST + 57, STBest, 9); // t < t_best
        default: ;
      endcase
    end
  end

  // ---------------------------------------------------------------------------------
  // State: the request, the registers with their scoreboard, the flags.
  // ---------------------------------------------------------------------------------
  typedef enum logic [1:0] {
    StIdle,  // waiting for a request
    StRun,   // issuing the programs and collecting results
    StDone   // holding the response
  } state_e;

  state_e                      state_d, state_q;
  rpu_pkg::iu_req_t            req_d, req_q;
  logic [NumTemps*W-1:0]       temps_d, temps_q;
  logic [NumTemps-1:0]         ready_d, ready_q;       // register holds this test's value
  logic [NumFlags-1:0]         flags_d, flags_q;
  logic [NumFlags-1:0]         flag_ready_d, flag_ready_q;

  // Every source as 32 bits (format values right-aligned), for the operand reads.
  // (Continuous assignments throughout: Yosys 0.23's proc_mux takes minutes on loops of
  // conditional slice assignments to vectors this wide.)
  logic [NumSrc*32-1:0] sources;
  assign sources[SO*32 +: 3*32]     = req_q.origin;
  assign sources[SD*32 +: 3*32]     = req_q.direction;
  assign sources[STMin*32 +: 32]    = req_q.t_min;
  assign sources[STBest*32 +: 32]   = req_q.t_best;
  assign sources[SSx*32 +: 32]      = req_q.shear_x;
  assign sources[SSy*32 +: 32]      = req_q.shear_y;
  assign sources[SZero*32 +: 32]    = '0;
  assign sources[SOne*32 +: 32]     = 32'(One);
  assign sources[SW*32 +: Words*32] = req_q.record;
  for (genvar i = 0; i < NumTemps; i++) begin : gen_sources
    assign sources[(ST + i)*32 +: 32] = 32'(temps_q[i*W +: W]);
  end

  // Which sources have their value: all but the registers always.
  logic [NumSrc-1:0] available;
  assign available = {ready_q, {ST{1'b1}}};

  // The decoded micro-ops.
  logic [OpBits-1:0]    f_op, m_op;
  logic [SrcBits-1:0]   f_a, f_b, m_a, m_b;
  logic [TagBits-1:0]   f_tag, m_tag;
  logic [1:0]           f_axis, m_axis;
  assign {f_op, f_a, f_b, f_tag, f_axis} = f_uop;
  assign {m_op, m_a, m_b, m_tag, m_axis} = m_uop;

  // Watertight: the register offset of a P' component of axis f_axis.
  logic [1:0] rank;
  always_comb begin
    if (f_axis == 2'(NoAxis)) rank = 2'd0;
    else if (f_axis == req_q.kx) rank = 2'd0;
    else if (f_axis == req_q.ky) rank = 2'd1;
    else rank = 2'd2;
  end

  // ---------------------------------------------------------------------------------
  // The FP units.
  // ---------------------------------------------------------------------------------
  logic             fma_req_valid, fma_req_ready, fma_rsp_valid;
  logic             div_req_valid, div_req_ready, div_rsp_valid;
  logic             misc_req_valid, misc_req_ready, misc_rsp_valid;
  rpu_pkg::fp_req_t f_req, m_req;
  rpu_pkg::fp_rsp_t fma_rsp, div_rsp, misc_rsp;

  logic f_done, m_done, f_is_div, f_issue, m_issue;
  assign f_done   = f_pc_q == PcBits'(FLen);
  assign m_done   = m_pc_q == PcBits'(MLen);
  assign f_is_div = f_op == rpu_pkg::FpOpDiv;
  assign f_issue  = state_q == StRun && !f_done && available[f_a] && available[f_b]
                    && (f_is_div ? div_req_ready : fma_req_ready);
  assign m_issue  = state_q == StRun && !m_done && available[m_a] && available[m_b] && misc_req_ready;

  // The op field is an enum: a packed-vector assignment sets it without a type cast
  // (which Yosys 0.23 does not read). The destination's rank goes into the tag.
  // (Indexed part-selects of one flat vector: Yosys 0.23 turns an array read at a
  // variable index into a memory.)
  assign f_req = {f_op, f_tag + TagBits'(rank), sources[f_a*32 +: 32], sources[f_b*32 +: 32], 32'd0};
  assign m_req = {m_op, m_tag, sources[m_a*32 +: 32], sources[m_b*32 +: 32], 32'd0};
  assign fma_req_valid  = f_issue && !f_is_div;
  assign div_req_valid  = f_issue && f_is_div;
  assign misc_req_valid = m_issue;

  rpu_fp_fma #(.ExpBits(ExpBits), .FracBits(FracBits)) u_fma (
    .clk_i, .rst_ni,
    .req_valid_i(fma_req_valid), .req_ready_o(fma_req_ready), .req_i(f_req),
    .rsp_valid_o(fma_rsp_valid), .rsp_ready_i(1'b1), .rsp_o(fma_rsp)
  );

  rpu_fp_divsqrt #(.ExpBits(ExpBits), .FracBits(FracBits)) u_div (
    .clk_i, .rst_ni,
    .req_valid_i(div_req_valid), .req_ready_o(div_req_ready), .req_i(f_req),
    .rsp_valid_o(div_rsp_valid), .rsp_ready_i(1'b1), .rsp_o(div_rsp)
  );

  rpu_fp_misc #(.ExpBits(ExpBits), .FracBits(FracBits)) u_misc (
    .clk_i, .rst_ni,
    .req_valid_i(misc_req_valid), .req_ready_o(misc_req_ready), .req_i(m_req),
    .rsp_valid_o(misc_rsp_valid), .rsp_ready_i(1'b1), .rsp_o(misc_rsp)
  );

  // soft's neg: flip the sign, but a NaN stays the canonical NaN.
  logic [W-1:0] div_value;
  logic         div_nan;
  assign div_nan   = &div_rsp.result[W-2:FracBits] && |div_rsp.result[FracBits-1:0];
  assign div_value = div_rsp.tag[IndexBits] && !div_nan ? div_rsp.result[W-1:0] ^ {1'b1, {(W - 1){1'b0}}}
                                                         : div_rsp.result[W-1:0];

  // ---------------------------------------------------------------------------------
  // Sequencing.
  // ---------------------------------------------------------------------------------
  logic accept, finished;
  assign req_ready_o = state_q == StIdle || (state_q == StDone && rsp_ready_i);
  assign accept      = req_valid_i && req_ready_o;

  // Issues advance the programs; results come back tagged with their destination. A
  // new request clears the scoreboard.
  assign req_d  = accept ? req_i : req_q;
  assign f_pc_d = accept ? '0 : f_issue ? f_pc_q + PcBits'(1) : f_pc_q;
  assign m_pc_d = accept ? '0 : m_issue ? m_pc_q + PcBits'(1) : m_pc_q;
  for (genvar i = 0; i < NumTemps; i++) begin : gen_temps
    logic fma_write, div_write, misc_write;
    assign fma_write  = fma_rsp_valid && fma_rsp.tag[IndexBits-1:0] == IndexBits'(i);
    assign div_write  = div_rsp_valid && div_rsp.tag[IndexBits-1:0] == IndexBits'(i);
    assign misc_write = misc_rsp_valid && !misc_rsp.tag[IndexBits+1] && misc_rsp.tag[IndexBits-1:0] == IndexBits'(i);
    assign temps_d[i*W +: W] = fma_write  ? fma_rsp.result[W-1:0]
                             : div_write  ? div_value
                             : misc_write ? misc_rsp.result[W-1:0]
                             : temps_q[i*W +: W];
    assign ready_d[i] = !accept && (ready_q[i] || fma_write || div_write || misc_write);
  end
  for (genvar i = 0; i < NumFlags; i++) begin : gen_flags
    logic write;
    assign write = misc_rsp_valid && misc_rsp.tag[IndexBits+1] && misc_rsp.tag[IndexBits-1:0] == IndexBits'(i);
    assign flags_d[i]      = write ? misc_rsp.result[0] : flags_q[i];
    assign flag_ready_d[i] = !accept && (flag_ready_q[i] || write);
  end

  // Done when both programs have issued everything and the flags and the response's
  // registers have their values (as they are written this cycle).
  assign finished = f_pc_d == PcBits'(FLen) && m_pc_d == PcBits'(MLen) && &flag_ready_d
                    && ready_d[TOutT] && ready_d[TOutU] && ready_d[TOutV];

  always_comb begin
    state_d = state_q;
    unique case (state_q)
      StIdle:  ;
      StRun:   if (finished) state_d = StDone;
      StDone:  if (rsp_ready_i) state_d = StIdle;
      default: state_d = StIdle;
    endcase
    if (accept) state_d = StRun;
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      state_q      <= StIdle;
      req_q        <= '0;
      temps_q      <= '0;
      ready_q      <= '0;
      flags_q      <= '0;
      flag_ready_q <= '0;
      f_pc_q       <= '0;
      m_pc_q       <= '0;
    end else begin
      state_q      <= state_d;
      req_q        <= req_d;
      temps_q      <= temps_d;
      ready_q      <= ready_d;
      flags_q      <= flags_d;
      flag_ready_q <= flag_ready_d;
      f_pc_q       <= f_pc_d;
      m_pc_q       <= m_pc_d;
    end
  end

  // ---------------------------------------------------------------------------------
  // The response.
  // ---------------------------------------------------------------------------------
  logic hit;
  if (Watertight) begin : gen_hit_watertight
    // Reject if edges have both signs; det must be nonzero (and not NaN); t in range.
    assign hit = !((flags_q[0] || flags_q[1] || flags_q[2]) && (flags_q[3] || flags_q[4] || flags_q[5]))
                 && (flags_q[6] || flags_q[7]) && flags_q[8] && flags_q[9];
  end else begin : gen_hit_woop
    assign hit = &flags_q;
  end

  assign rsp_valid_o = state_q == StDone;
  assign rsp_o.tag   = req_q.tag;
  assign rsp_o.hit   = hit;
  assign rsp_o.t     = hit ? 32'(temps_q[TOutT*W +: W]) : '0;
  assign rsp_o.u     = hit ? 32'(temps_q[TOutU*W +: W]) : '0;
  assign rsp_o.v     = hit ? 32'(temps_q[TOutV*W +: W]) : '0;

  // kz is the axis neither kx nor ky names; the misc program has no axis; compares
  // answer in bit 0 and results sit in the format's low bits.
  logic unused;
  assign unused = ^{req_q.kz, m_axis, fma_rsp.tag[TagBits-1:IndexBits], div_rsp.tag[TagBits-1],
                    misc_rsp.tag[IndexBits]};
  if (W < 32) begin : gen_unused_high
    logic unused_high;
    assign unused_high = ^{fma_rsp.result[31:W], div_rsp.result[31:W], misc_rsp.result[31:W]};
  end

endmodule
