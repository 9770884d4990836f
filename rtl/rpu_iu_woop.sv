// Woop's unit-triangle test (docs/traversal.md §4) as a pipeline: every rounded
// operation of intersect_woop (cmodel/functional/intersection_unit.hpp) has its own
// operator, one stage each, in the C++ order, so a test is accepted every cycle and
// answered a fixed number of cycles later. Stage by stage (the request is stage 0):
//   1  the record's 12 words into the format: the rows' linear parts L_r and A
//   2  P = O - A;  L_r * D (9 products)
//   3  L_r * P (9 products);  partial sums of the L_r * D
//   4  partial sums of the L_r * P;  d_r = dp3(L_r, D)
//   5  o_r = dp3(L_r, P)
//   6  t = -(o_2 / d_2) on rpu_fp_div_pipe (its stages), with what later stages need
//      riding alongside
//   +1 t * d_0, t * d_1;  t > t_min, t < t_best
//   +2 u = o_0 + t d_0, v = o_1 + t d_1
//   +3 u + v;  0 <= u, u <= 1, 0 <= v
//   +4 the answer: u + v <= 1 and the other flags, t, u, v (zero on a miss)
// The whole pipeline moves when en_i is high.
module rpu_iu_woop #(
  parameter int unsigned ExpBits  = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits = rpu_pkg::FormatFp32FractionBits
) (
  input  logic             clk_i,
  input  logic             rst_ni,
  input  logic             en_i,

  input  logic             valid_i,
  input  rpu_pkg::iu_req_t req_i,

  // The last stage's answer, combinational (rpu_iu registers it).
  output logic                          valid_o,
  output logic [rpu_pkg::RayTagBits-1:0] tag_o,
  output logic                          hit_o,
  output logic [ExpBits+FracBits:0]     t_o,
  output logic [ExpBits+FracBits:0]     u_o,
  output logic [ExpBits+FracBits:0]     v_o
);

  localparam int unsigned W = 1 + ExpBits + FracBits;
  localparam int unsigned TagBits = rpu_pkg::RayTagBits;
  localparam logic [W-1:0] One = {2'b00, {(ExpBits - 1){1'b1}}, {FracBits{1'b0}}};
  localparam logic [W-1:0] SignBit = {1'b1, {(W - 1){1'b0}}};
  // The first word of row r (spec/memory_map.toml [triangle_record]); its w is word + 3.
  localparam int unsigned Row0 = rpu_pkg::TriangleRecordRow0At / 4;
  localparam int unsigned Row1 = rpu_pkg::TriangleRecordRow1At / 4;
  localparam int unsigned Row2 = rpu_pkg::TriangleRecordRow2At / 4;

  // A format value as an operand (right-aligned in 32 bits).
  function automatic logic [31:0] ext(input logic [W-1:0] x);
    ext = 32'(x);
  endfunction

  // What passes beside the arithmetic: valid, tag, t_min, t_best.
  localparam int unsigned CtlBits = 1 + TagBits + 2 * W;
  logic [CtlBits-1:0] ctl0, ctl1, ctl2, ctl3, ctl4, ctl5;
  assign ctl0 = {valid_i, req_i.tag, req_i.t_min[W-1:0], req_i.t_best[W-1:0]};
  rpu_en_reg #(.Width(CtlBits)) u_ctl1 (.clk_i, .rst_ni, .en_i, .data_i(ctl0), .data_o(ctl1));
  rpu_en_reg #(.Width(CtlBits)) u_ctl2 (.clk_i, .rst_ni, .en_i, .data_i(ctl1), .data_o(ctl2));
  rpu_en_reg #(.Width(CtlBits)) u_ctl3 (.clk_i, .rst_ni, .en_i, .data_i(ctl2), .data_o(ctl3));
  rpu_en_reg #(.Width(CtlBits)) u_ctl4 (.clk_i, .rst_ni, .en_i, .data_i(ctl3), .data_o(ctl4));
  rpu_en_reg #(.Width(CtlBits)) u_ctl5 (.clk_i, .rst_ni, .en_i, .data_i(ctl4), .data_o(ctl5));

  // Stage 1: m[4r + k] is word k of row r in the format (k = 3: A_r).
  logic [12*W-1:0] m1;
  for (genvar r = 0; r < 3; r++) begin : g_row
    localparam int unsigned At = r == 0 ? Row0 : r == 1 ? Row1 : Row2;
    for (genvar k = 0; k < 4; k++) begin : g_word
      rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpFromFp32)) u_load (
        .clk_i, .rst_ni, .en_i, .a_i(req_i.record[(At + k)*32 +: 32]), .b_i('0),
        .result_o(m1[(4*r + k)*W +: W])
      );
    end
  end
  logic [3*W-1:0] o1, d1;  // the ray, a stage on
  for (genvar i = 0; i < 3; i++) begin : g_ray
    rpu_en_reg #(.Width(2 * W)) u_ray (
      .clk_i, .rst_ni, .en_i, .data_i({req_i.origin[i*32 +: W], req_i.direction[i*32 +: W]}),
      .data_o({o1[i*W +: W], d1[i*W +: W]})
    );
  end

  // Stage 2: P = O - A; L_r * D. Stage 3: L_r * P; (L_r0 D0 + L_r1 D1).
  // Stage 4: (L_r0 P0 + L_r1 P1); d_r = (...) + L_r2 D2. Stage 5: o_r = (...) + L_r2 P2.
  logic [3*W-1:0] p2;
  logic [9*W-1:0] l2;          // the linear parts, a stage on
  logic [3*W-1:0] o5, d4, d5;  // o_r, d_r at stages 4 and 5
  for (genvar i = 0; i < 3; i++) begin : g_p
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpSub)) u_p (
      .clk_i, .rst_ni, .en_i, .a_i(ext(o1[i*W +: W])), .b_i(ext(m1[(4*i + 3)*W +: W])), .result_o(p2[i*W +: W])
    );
  end
  for (genvar r = 0; r < 3; r++) begin : g_dot
    logic [3*W-1:0] ld2, lp3;  // L_r * D, L_r * P
    logic [W-1:0]   ld3_2, lp4_2, sd3, sp4;
    for (genvar i = 0; i < 3; i++) begin : g_term
      rpu_en_reg #(.Width(W)) u_l (.clk_i, .rst_ni, .en_i, .data_i(m1[(4*r + i)*W +: W]), .data_o(l2[(3*r + i)*W +: W]));
      rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpMul)) u_ld (
        .clk_i, .rst_ni, .en_i, .a_i(ext(m1[(4*r + i)*W +: W])), .b_i(ext(d1[i*W +: W])), .result_o(ld2[i*W +: W])
      );
      rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpMul)) u_lp (
        .clk_i, .rst_ni, .en_i, .a_i(ext(l2[(3*r + i)*W +: W])), .b_i(ext(p2[i*W +: W])), .result_o(lp3[i*W +: W])
      );
    end
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpAdd)) u_sd (
      .clk_i, .rst_ni, .en_i, .a_i(ext(ld2[0 +: W])), .b_i(ext(ld2[W +: W])), .result_o(sd3)
    );
    rpu_en_reg #(.Width(W)) u_ld2 (.clk_i, .rst_ni, .en_i, .data_i(ld2[2*W +: W]), .data_o(ld3_2));
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpAdd)) u_d (
      .clk_i, .rst_ni, .en_i, .a_i(ext(sd3)), .b_i(ext(ld3_2)), .result_o(d4[r*W +: W])
    );
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpAdd)) u_sp (
      .clk_i, .rst_ni, .en_i, .a_i(ext(lp3[0 +: W])), .b_i(ext(lp3[W +: W])), .result_o(sp4)
    );
    rpu_en_reg #(.Width(W)) u_lp2 (.clk_i, .rst_ni, .en_i, .data_i(lp3[2*W +: W]), .data_o(lp4_2));
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpAdd)) u_dot_p (
      .clk_i, .rst_ni, .en_i, .a_i(ext(sp4)), .b_i(ext(lp4_2)), .result_o(o5[r*W +: W])
    );
  end
  rpu_en_reg #(.Width(3 * W)) u_d5 (.clk_i, .rst_ni, .en_i, .data_i(d4), .data_o(d5));

  // The division, with the control, o_0, o_1, d_0 and d_1 beside it.
  localparam int unsigned SideBits = CtlBits + 4 * W;
  logic [W-1:0]       quotient, o0q, o1q, d0q, d1q;
  logic [CtlBits-1:0] ctlq;
  rpu_fp_div_pipe #(.ExpBits(ExpBits), .FracBits(FracBits), .SideBits(SideBits)) u_div (
    .clk_i, .rst_ni, .en_i, .a_i(o5[2*W +: W]), .b_i(d5[2*W +: W]),
    .side_i({ctl5, o5[0 +: W], o5[W +: W], d5[0 +: W], d5[W +: W]}),
    .quotient_o(quotient), .side_o({ctlq, o0q, o1q, d0q, d1q})
  );

  // t = -(o_2 / d_2): soft's neg flips the sign, but a NaN stays the canonical NaN.
  logic [W-1:0] t;
  logic         quotient_nan;
  assign quotient_nan = &quotient[W-2:FracBits] && |quotient[FracBits-1:0];
  assign t = quotient_nan ? quotient : quotient ^ SignBit;

  logic          valid_q;
  logic [TagBits-1:0] tag_q;
  logic [W-1:0]  t_min_q, t_best_q;
  assign {valid_q, tag_q, t_min_q, t_best_q} = ctlq;

  // +1: t d_0, t d_1; t > t_min, t < t_best.
  logic [W-1:0] tdx, tdy, gt_min, lt_best, t_a, o0a, o1a;
  logic [1+TagBits-1:0] ctla, ctlb, ctlc;
  rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpMul)) u_tdx (
    .clk_i, .rst_ni, .en_i, .a_i(ext(t)), .b_i(ext(d0q)), .result_o(tdx)
  );
  rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpMul)) u_tdy (
    .clk_i, .rst_ni, .en_i, .a_i(ext(t)), .b_i(ext(d1q)), .result_o(tdy)
  );
  rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpGt)) u_gt_min (
    .clk_i, .rst_ni, .en_i, .a_i(ext(t)), .b_i(ext(t_min_q)), .result_o(gt_min)
  );
  rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpLt)) u_lt_best (
    .clk_i, .rst_ni, .en_i, .a_i(ext(t)), .b_i(ext(t_best_q)), .result_o(lt_best)
  );
  rpu_en_reg #(.Width(1 + TagBits + 3 * W)) u_carry_a (
    .clk_i, .rst_ni, .en_i, .data_i({valid_q, tag_q, t, o0q, o1q}), .data_o({ctla, t_a, o0a, o1a})
  );

  // +2: u = o_0 + t d_0, v = o_1 + t d_1.
  logic [W-1:0] u_b, v_b, t_b;
  logic         flags_b;
  rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpAdd)) u_u (
    .clk_i, .rst_ni, .en_i, .a_i(ext(o0a)), .b_i(ext(tdx)), .result_o(u_b)
  );
  rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpAdd)) u_v (
    .clk_i, .rst_ni, .en_i, .a_i(ext(o1a)), .b_i(ext(tdy)), .result_o(v_b)
  );
  rpu_en_reg #(.Width(1 + TagBits + W + 1)) u_carry_b (
    .clk_i, .rst_ni, .en_i, .data_i({ctla, t_a, gt_min[0] && lt_best[0]}), .data_o({ctlb, t_b, flags_b})
  );

  // +3: u + v; 0 <= u, u <= 1, 0 <= v.
  logic [W-1:0] uv_c, u_c, v_c, t_c, u_ge0, u_le1, v_ge0;
  logic         flags_c;
  rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpAdd)) u_uv (
    .clk_i, .rst_ni, .en_i, .a_i(ext(u_b)), .b_i(ext(v_b)), .result_o(uv_c)
  );
  rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpLe)) u_u_ge0 (
    .clk_i, .rst_ni, .en_i, .a_i('0), .b_i(ext(u_b)), .result_o(u_ge0)
  );
  rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpLe)) u_u_le1 (
    .clk_i, .rst_ni, .en_i, .a_i(ext(u_b)), .b_i(ext(One)), .result_o(u_le1)
  );
  rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpLe)) u_v_ge0 (
    .clk_i, .rst_ni, .en_i, .a_i('0), .b_i(ext(v_b)), .result_o(v_ge0)
  );
  rpu_en_reg #(.Width(1 + TagBits + 3 * W + 1)) u_carry_c (
    .clk_i, .rst_ni, .en_i, .data_i({ctlb, t_b, u_b, v_b, flags_b}), .data_o({ctlc, t_c, u_c, v_c, flags_c})
  );

  // +4: u + v <= 1 decides; the answer.
  logic [31:0] uv_le1;
  rpu_fp_misc_core #(.ExpBits(ExpBits), .FracBits(FracBits)) u_uv_le1 (
    .op_i(rpu_pkg::FpOpLe), .a_i(ext(uv_c)), .b_i(ext(One)), .result_o(uv_le1)
  );
  assign hit_o = flags_c && u_ge0[0] && u_le1[0] && v_ge0[0] && uv_le1[0];

  assign valid_o = ctlc[TagBits];
  assign tag_o   = ctlc[TagBits-1:0];
  assign t_o     = t_c;
  assign u_o     = u_c;
  assign v_o     = v_c;

  // Woop's test has no axes or shear; compares answer in bit 0; words above the
  // format's width carry nothing.
  logic unused;
  assign unused = ^{req_i.kx, req_i.ky, req_i.kz, req_i.shear_x, req_i.shear_y, gt_min[W-1:1], lt_best[W-1:1],
                    u_ge0[W-1:1], u_le1[W-1:1], v_ge0[W-1:1], uv_le1[31:1]};
  if (W < 32) begin : g_unused_high
    logic unused_high;
    assign unused_high = ^{req_i.origin[95:64+W], req_i.origin[63:32+W], req_i.origin[31:W],
                           req_i.direction[95:64+W], req_i.direction[63:32+W], req_i.direction[31:W],
                           req_i.t_min[31:W], req_i.t_best[31:W]};
  end

endmodule
