// The start of one division or square-root pass of the digit recurrence (Ercegovac &
// Lang, "Digital Arithmetic", ch. 5 and 6), combinational: decodes the operands, finds
// the special results, and sets up the partial remainder (division) or the radicand
// (square root) for Steps digits. Shared by the iterative unit (rpu_fp_divsqrt) and
// the pipelined divider (rpu_fp_div_pipe), so both round the same digits.
//   division:    quotient digits q = floor(sig_a / sig_b * 2^(Steps-1)), the digit
//                string's bit 0 of weight 2^exp_o
//   square root: the radicand scaled to an even exponent so that its integer root
//                has exactly Steps bits; b_i is not read
module rpu_fp_divsqrt_load #(
  parameter int unsigned ExpBits  = 8,
  parameter int unsigned FracBits = 23,
  parameter int unsigned Steps    = 26,
  parameter int unsigned ExpWidth = 11
) (
  input  logic                        sqrt_i,
  input  logic [ExpBits+FracBits:0]   a_i,
  input  logic [ExpBits+FracBits:0]   b_i,
  output logic                        sign_o,
  output logic signed [ExpWidth-1:0]  exp_o,
  output logic [Steps+1:0]            rem_o,
  output logic [2*Steps-1:0]          rad_o,
  output logic [FracBits:0]           divisor_o,
  output logic                        special_o,      // the result is special_value_o
  output logic [ExpBits+FracBits:0]   special_value_o
);

  localparam int unsigned Width   = 1 + ExpBits + FracBits;
  localparam int unsigned RemBits = Steps + 2;
  localparam int unsigned RadBits = 2 * Steps;
  localparam logic signed [ExpWidth-1:0] StepsS = ExpWidth'(Steps);
  localparam logic [Width-1:0] CanonicalNan = {1'b0, {ExpBits{1'b1}}, 1'b1, {(FracBits - 1){1'b0}}};
  localparam logic [ExpBits+FracBits-1:0] InfMagnitude = {{ExpBits{1'b1}}, {FracBits{1'b0}}};

  logic                       a_sign, a_zero, a_inf, a_nan;
  logic                       b_sign, b_zero, b_inf, b_nan;
  logic signed [ExpWidth-1:0] a_exp, b_exp;
  logic [FracBits:0]          a_sig, b_sig;

  rpu_fp_classify #(.ExpBits(ExpBits), .FracBits(FracBits), .ExpWidth(ExpWidth)) u_a (
    .value_i(a_i), .sign_o(a_sign), .zero_o(a_zero), .inf_o(a_inf), .nan_o(a_nan),
    .exp_o(a_exp), .sig_o(a_sig)
  );
  rpu_fp_classify #(.ExpBits(ExpBits), .FracBits(FracBits), .ExpWidth(ExpWidth)) u_b (
    .value_i(b_i), .sign_o(b_sign), .zero_o(b_zero), .inf_o(b_inf), .nan_o(b_nan),
    .exp_o(b_exp), .sig_o(b_sig)
  );

  assign divisor_o = b_sig;

  always_comb begin : set_up_pass
    special_o       = 1'b1;
    special_value_o = CanonicalNan;
    rem_o           = '0;
    rad_o           = '0;
    if (sqrt_i) begin
      sign_o = 1'b0;
      // sqrt(a) = sqrt(sig * 2^(e mod 2)) * 2^floor(e / 2).
      exp_o = (a_exp >>> 1) - StepsS;
      rad_o = a_exp[0] ? RadBits'(a_sig) << (RadBits - 1 - FracBits)
                       : RadBits'(a_sig) << (RadBits - 2 - FracBits);
      // §6.3 sqrt(-0) = -0; §7.2(g) a negative operand is invalid.
      if (a_nan) begin
        special_value_o = CanonicalNan;
      end else if (a_zero) begin
        special_value_o = {a_sign, {(Width - 1){1'b0}}};
      end else if (a_sign) begin
        special_value_o = CanonicalNan;
      end else if (a_inf) begin
        special_value_o = {1'b0, InfMagnitude};
      end else begin
        special_o = 1'b0;
      end
    end else begin
      sign_o = a_sign ^ b_sign;
      exp_o  = a_exp - b_exp - StepsS;
      rem_o  = RemBits'(a_sig);
      // §7.2(d) 0/0 and inf/inf are invalid; §7.3 x/0 is an exact infinity.
      if (a_nan || b_nan || (a_inf && b_inf) || (a_zero && b_zero)) begin
        special_value_o = CanonicalNan;
      end else if (a_inf || b_zero) begin
        special_value_o = {sign_o, InfMagnitude};
      end else if (b_inf || a_zero) begin
        special_value_o = {sign_o, {(Width - 1){1'b0}}};
      end else begin
        special_o = 1'b0;
      end
    end
  end

endmodule
