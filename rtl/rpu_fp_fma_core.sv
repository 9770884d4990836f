// x * y + z with one rounding (soft::fma; IEEE 754-2019 §5.4.1), combinational. The
// fma unit maps add, sub, mul and fract onto it (rpu_fp_fma.sv).
//
// The exact product (2M+2 bits) and the addend meet in one fixed-point frame of
// 4M+8 bits: the product at bit M+3, the addend wherever its exponent puts it. An
// addend far below the frame is shifted in with a sticky bit (the product then has
// at least 3M+3 bits above it, so the rounding decision is kept, as in soft.cpp
// add_exact). An addend whose lowest bit would sit above bit 3M+7 is more than two
// places above the product's top bit: z +- p then lies strictly between z and the
// next rounding boundary, so the frame is re-based on the addend and the product
// shrinks to a sticky bit. Everything else is exact, and rpu_fp_round rounds once.
module rpu_fp_fma_core #(
  parameter int unsigned ExpBits  = 8,
  parameter int unsigned FracBits = 23
) (
  input  logic [ExpBits+FracBits:0] x_i,
  input  logic [ExpBits+FracBits:0] y_i,
  input  logic [ExpBits+FracBits:0] z_i,
  output logic [ExpBits+FracBits:0] result_o
);

  localparam int unsigned Width     = 1 + ExpBits + FracBits;
  localparam int unsigned ProdBits  = 2 * FracBits + 2;
  localparam int unsigned FrameBits = 4 * FracBits + 8;
  localparam int unsigned ProdAt    = FracBits + 3;      // frame bit of the product's bit 0
  localparam int unsigned ZTop      = 3 * FracBits + 7;  // highest frame bit for z's bit 0
  localparam int unsigned ShiftBits = $clog2(FrameBits);
  // Exponents here stay within +-(2^ExpBits + 7*FracBits + 12); one more bit for sign.
  localparam int unsigned ExpWidth = $clog2((2 << ExpBits) + 8 * FracBits + 16) + 1;
  localparam logic signed [ExpWidth-1:0] ShBase = ExpWidth'(2 * FracBits + 3);
  localparam logic signed [ExpWidth-1:0] ZTopS  = ExpWidth'(ZTop);
  localparam logic signed [ExpWidth-1:0] ZLsb   = ExpWidth'(FracBits + ZTop);
  localparam logic signed [ExpWidth-1:0] FrameLsb = ExpWidth'(3 * FracBits + 3);
  localparam logic signed [ExpWidth-1:0] ZAway  = ExpWidth'(FracBits + 1);
  localparam logic [Width-1:0] CanonicalNan = {1'b0, {ExpBits{1'b1}}, 1'b1, {(FracBits - 1){1'b0}}};

  logic                       x_sign, x_zero, x_inf, x_nan;
  logic                       y_sign, y_zero, y_inf, y_nan;
  logic                       z_sign, z_zero, z_inf, z_nan;
  logic signed [ExpWidth-1:0] x_exp, y_exp, z_exp;
  logic [FracBits:0]          x_sig, y_sig, z_sig;

  rpu_fp_classify #(.ExpBits(ExpBits), .FracBits(FracBits), .ExpWidth(ExpWidth)) u_x (
    .value_i(x_i), .sign_o(x_sign), .zero_o(x_zero), .inf_o(x_inf), .nan_o(x_nan),
    .exp_o(x_exp), .sig_o(x_sig)
  );
  rpu_fp_classify #(.ExpBits(ExpBits), .FracBits(FracBits), .ExpWidth(ExpWidth)) u_y (
    .value_i(y_i), .sign_o(y_sign), .zero_o(y_zero), .inf_o(y_inf), .nan_o(y_nan),
    .exp_o(y_exp), .sig_o(y_sig)
  );
  rpu_fp_classify #(.ExpBits(ExpBits), .FracBits(FracBits), .ExpWidth(ExpWidth)) u_z (
    .value_i(z_i), .sign_o(z_sign), .zero_o(z_zero), .inf_o(z_inf), .nan_o(z_nan),
    .exp_o(z_exp), .sig_o(z_sig)
  );

  logic                       p_sign;
  logic [ProdBits-1:0]        product;
  logic signed [ExpWidth-1:0] z_at;        // frame bit of z's bit 0, unclamped
  logic                       z_above;     // z's bit 0 above ZTop: product becomes sticky
  logic [FrameBits-1:0]       p_frame, z_frame;
  logic [FracBits:0]          z_lost;      // z bits shifted out below the frame
  logic [FracBits:0]          z_down;      // z bits kept when z's bit 0 is below the frame
  logic [ShiftBits-1:0]       z_shift;
  logic signed [ExpWidth-1:0] frame_exp;   // exponent of frame bit 0
  logic                       p_ge_z;
  logic [FrameBits:0]         sum;
  logic                       sum_sign;
  logic [Width-1:0]           rounded;

  assign p_sign  = x_sign ^ y_sign;
  assign product = ProdBits'(x_sig) * ProdBits'(y_sig);
  // z's bit 0 has exponent z_exp - M; frame bit 0 has x_exp + y_exp - 2M - (M+3).
  assign z_at    = z_exp - x_exp - y_exp + ShBase;
  assign z_above = !z_zero && z_at > ZTopS;
  assign z_shift = z_at < 0 ? ShiftBits'(-z_at) : ShiftBits'(z_at);
  assign z_lost  = z_sig & ~({(FracBits + 1){1'b1}} << z_shift);
  assign z_down  = z_sig >> z_shift;

  always_comb begin : add_frames
    if (z_zero) begin
      z_frame = '0;
    end else if (z_above) begin
      z_frame = FrameBits'(z_sig) << ZTop;
    end else if (z_at >= 0) begin
      z_frame = FrameBits'(z_sig) << z_shift;
    end else if (z_at <= -ZAway) begin
      z_frame = FrameBits'(1);  // every bit of z lies below the frame: only the sticky
    end else begin
      z_frame = FrameBits'(z_down) | FrameBits'(|z_lost);
    end
    p_frame   = z_above ? FrameBits'(1) : FrameBits'(product) << ProdAt;
    frame_exp = z_above ? z_exp - ZLsb : x_exp + y_exp - FrameLsb;
    p_ge_z    = p_frame >= z_frame;
    if (p_sign == z_sign) begin
      sum      = {1'b0, p_frame} + {1'b0, z_frame};
      sum_sign = p_sign;
    end else if (p_ge_z) begin
      sum      = {1'b0, p_frame - z_frame};
      sum_sign = p_sign;
    end else begin
      sum      = {1'b0, z_frame - p_frame};
      sum_sign = z_sign;
    end
  end

  rpu_fp_round #(
    .ExpBits(ExpBits), .FracBits(FracBits), .SigBits(FrameBits + 1), .ExpWidth(ExpWidth)
  ) u_round (
    .sign_i(sum_sign), .exp_i(frame_exp), .sig_i(sum), .result_o(rounded)
  );

  always_comb begin : pick_result
    if (x_nan || y_nan || z_nan) begin
      result_o = CanonicalNan;
    end else if (x_inf || y_inf) begin
      // §7.2(c): fma(0, inf, c) is invalid for every c; so is inf - inf.
      if (x_zero || y_zero || (z_inf && z_sign != p_sign)) begin
        result_o = CanonicalNan;
      end else begin
        result_o = {p_sign, {ExpBits{1'b1}}, {FracBits{1'b0}}};
      end
    end else if (z_inf) begin
      result_o = {z_sign, {ExpBits{1'b1}}, {FracBits{1'b0}}};
    end else if (x_zero || y_zero) begin
      // §6.3: an exact zero sum is -0 only if both terms are -0; z alone is exact.
      result_o = z_zero ? {p_sign & z_sign, {(Width - 1){1'b0}}} : z_i;
    end else if (sum == '0) begin
      result_o = '0;  // exact cancellation of opposite signs: +0 (§6.3)
    end else begin
      result_o = rounded;
    end
  end

endmodule
