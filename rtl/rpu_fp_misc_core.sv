// The single-cycle operations, combinational: floor, min, max, the six quiet
// compares, and the conversions from_fp32, to_fp32, from_int32, to_int32 (soft.hpp,
// docs/numbers.md). Inputs and the result are 32 bits wide because the conversions
// need all of them; format values sit right-aligned (fp_req_t).
module rpu_fp_misc_core #(
  parameter int unsigned ExpBits  = 8,
  parameter int unsigned FracBits = 23
) (
  input  logic [rpu_pkg::FpOpBits-1:0]      op_i,
  input  logic [rpu_pkg::FpOperandBits-1:0] a_i,
  input  logic [rpu_pkg::FpOperandBits-1:0] b_i,
  output logic [rpu_pkg::FpOperandBits-1:0] result_o
);

  localparam int unsigned Width = 1 + ExpBits + FracBits;
  localparam int unsigned OpBits = rpu_pkg::FpOperandBits;
  // Exponents here (format, fp32 and int32 magnitudes) stay within +-(127 + 23 + 32).
  localparam int unsigned ExpWidth = 10;
  localparam logic [Width-1:0] CanonicalNan = {1'b0, {ExpBits{1'b1}}, 1'b1, {(FracBits - 1){1'b0}}};
  localparam logic [OpBits-1:0] Fp32Nan = 32'h7fc0_0000;
  localparam logic signed [ExpWidth-1:0] Fp32Bias = 10'sd127;

  logic [Width-1:0] a, b;
  assign a = a_i[Width-1:0];
  assign b = b_i[Width-1:0];

  logic                       a_sign, a_zero, a_inf, a_nan;
  logic                       b_sign, b_zero, b_inf, b_nan;
  logic signed [ExpWidth-1:0] a_exp, b_exp;
  logic [FracBits:0]          a_sig, b_sig;

  rpu_fp_classify #(.ExpBits(ExpBits), .FracBits(FracBits), .ExpWidth(ExpWidth)) u_a (
    .value_i(a), .sign_o(a_sign), .zero_o(a_zero), .inf_o(a_inf), .nan_o(a_nan),
    .exp_o(a_exp), .sig_o(a_sig)
  );
  rpu_fp_classify #(.ExpBits(ExpBits), .FracBits(FracBits), .ExpWidth(ExpWidth)) u_b (
    .value_i(b), .sign_o(b_sign), .zero_o(b_zero), .inf_o(b_inf), .nan_o(b_nan),
    .exp_o(b_exp), .sig_o(b_sig)
  );

  // The input flush (rule 1): subnormals to signed zero, every NaN canonical.
  logic [Width-1:0] a_flushed, b_flushed;
  assign a_flushed = a_nan ? CanonicalNan : a_zero ? {a_sign, {(Width - 1){1'b0}}} : a;
  assign b_flushed = b_nan ? CanonicalNan : b_zero ? {b_sign, {(Width - 1){1'b0}}} : b;

  // Orders flushed non-NaN values with -0 below +0 (soft.cpp min_max_key); the
  // compares then treat two zeros as equal (compare_key).
  logic any_nan, both_zero, a_below_b, b_below_a, equal;
  assign any_nan   = a_nan | b_nan;
  assign both_zero = a_zero & b_zero;
  always_comb begin : order_operands
    if (a_sign != b_sign) begin
      a_below_b = a_sign;
      b_below_a = b_sign;
    end else if (!a_sign) begin
      a_below_b = a_flushed[Width-2:0] < b_flushed[Width-2:0];
      b_below_a = b_flushed[Width-2:0] < a_flushed[Width-2:0];
    end else begin
      a_below_b = a_flushed[Width-2:0] > b_flushed[Width-2:0];
      b_below_a = b_flushed[Width-2:0] > a_flushed[Width-2:0];
    end
  end
  assign equal = (a_flushed == b_flushed) | both_zero;

  logic is_eq, is_ne, is_lt, is_le, is_gt, is_ge;
  assign is_eq = ~any_nan & equal;
  assign is_ne = ~is_eq;
  assign is_lt = ~any_nan & a_below_b & ~both_zero;
  assign is_le = is_lt | is_eq;
  assign is_gt = ~any_nan & b_below_a & ~both_zero;
  assign is_ge = is_gt | is_eq;

  // soft::min keeps a when key(a) <= key(b), soft::max when key(a) >= key(b).
  logic [Width-1:0] min_result, max_result;
  assign min_result = any_nan ? CanonicalNan : b_below_a ? b_flushed : a_flushed;
  assign max_result = any_nan ? CanonicalNan : a_below_b ? b_flushed : a_flushed;

  logic [Width-1:0] a_floor;
  rpu_fp_floor #(.ExpBits(ExpBits), .FracBits(FracBits)) u_floor (.a_i(a), .floor_o(a_floor));

  // to_fp32: exact widening; fp32's range and precision hold every format value.
  logic [OpBits-1:0]          to_fp32;
  logic [7:0]                 fp32_field;
  assign fp32_field = 8'(a_exp + Fp32Bias);
  always_comb begin : widen_to_fp32
    if (a_nan) begin
      to_fp32 = Fp32Nan;
    end else if (a_inf) begin
      to_fp32 = {a_sign, 8'hff, 23'd0};
    end else if (a_zero) begin
      to_fp32 = {a_sign, 31'd0};
    end else begin
      to_fp32 = {a_sign, fp32_field, 23'(a_sig[FracBits-1:0]) << (23 - FracBits)};
    end
  end

  // to_int32: toward zero; |a| >= 2^31 and inf saturate, NaN gives 0.
  logic [OpBits-1:0]       to_int32;
  logic [FracBits+31:0]    int_shifted;
  logic [OpBits-1:0]       int_magnitude;
  assign int_shifted   = (FracBits + 32)'(a_sig) << a_exp[4:0];
  assign int_magnitude = OpBits'(int_shifted >> FracBits);
  always_comb begin : convert_to_int32
    if (a_nan || a_zero || (!a_inf && a_exp < 0)) begin
      to_int32 = '0;
    end else if (a_inf || a_exp >= 31) begin
      to_int32 = a_sign ? 32'h8000_0000 : 32'h7fff_ffff;
    end else begin
      to_int32 = a_sign ? -int_magnitude : int_magnitude;
    end
  end

  // from_fp32 and from_int32 share one rounding step.
  logic                       f_sign, f_zero, f_inf, f_nan;
  logic signed [ExpWidth-1:0] f_exp;
  logic [23:0]                f_sig;
  rpu_fp_classify #(.ExpBits(8), .FracBits(23), .ExpWidth(ExpWidth)) u_fp32 (
    .value_i(a_i), .sign_o(f_sign), .zero_o(f_zero), .inf_o(f_inf), .nan_o(f_nan),
    .exp_o(f_exp), .sig_o(f_sig)
  );

  logic                       int_sign;
  logic [OpBits-1:0]          int_abs;
  logic                       round_sign;
  logic signed [ExpWidth-1:0] round_exp;
  logic [OpBits-1:0]          round_sig;
  logic [Width-1:0]           rounded;
  assign int_sign = a_i[OpBits-1];
  assign int_abs  = int_sign ? -a_i : a_i;
  always_comb begin : pick_round_operands
    if (op_i == rpu_pkg::FpOpFromInt32) begin
      round_sign = int_sign;
      round_exp  = '0;
      round_sig  = int_abs;
    end else begin
      // value = f_sig * 2^(f_exp - 23) = (f_sig << 8) * 2^(f_exp - 31)
      round_sign = f_sign;
      round_exp  = f_exp - 10'sd31;
      round_sig  = {f_sig, 8'd0};
    end
  end

  rpu_fp_round #(
    .ExpBits(ExpBits), .FracBits(FracBits), .SigBits(OpBits), .ExpWidth(ExpWidth)
  ) u_round (
    .sign_i(round_sign), .exp_i(round_exp), .sig_i(round_sig), .result_o(rounded)
  );

  logic [Width-1:0] from_fp32, from_int32;
  always_comb begin : from_fp32_and_int32
    if (f_nan) begin
      from_fp32 = CanonicalNan;
    end else if (f_inf) begin
      from_fp32 = {f_sign, {ExpBits{1'b1}}, {FracBits{1'b0}}};
    end else if (f_zero) begin
      from_fp32 = {f_sign, {(Width - 1){1'b0}}};
    end else begin
      from_fp32 = rounded;
    end
    from_int32 = a_i == '0 ? '0 : rounded;
  end

  always_comb begin : pick_result
    unique case (op_i)
      rpu_pkg::FpOpFloor:     result_o = OpBits'(a_floor);
      rpu_pkg::FpOpMin:       result_o = OpBits'(min_result);
      rpu_pkg::FpOpMax:       result_o = OpBits'(max_result);
      rpu_pkg::FpOpEq:        result_o = OpBits'(is_eq);
      rpu_pkg::FpOpNe:        result_o = OpBits'(is_ne);
      rpu_pkg::FpOpLt:        result_o = OpBits'(is_lt);
      rpu_pkg::FpOpLe:        result_o = OpBits'(is_le);
      rpu_pkg::FpOpGt:        result_o = OpBits'(is_gt);
      rpu_pkg::FpOpGe:        result_o = OpBits'(is_ge);
      rpu_pkg::FpOpFromFp32:  result_o = OpBits'(from_fp32);
      rpu_pkg::FpOpToFp32:    result_o = to_fp32;
      rpu_pkg::FpOpFromInt32: result_o = OpBits'(from_int32);
      rpu_pkg::FpOpToInt32:   result_o = to_int32;
      // Ops of other units never reach this one.
      default:                result_o = '0;
    endcase
  end

  // b's exponent and significand are not needed: compares work on the bit patterns.
  logic unused_b;
  assign unused_b = ^{b_exp, b_sig, b_inf};
  if (Width < OpBits) begin : g_unused_high
    logic unused_high;
    assign unused_high = ^b_i[OpBits-1:Width];
  end

endmodule
