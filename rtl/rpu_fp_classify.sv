// Decodes a value of the format (docs/numbers.md) after the input flush: exponent
// field 0 is a signed zero whatever the fraction (DAZ), all ones is inf or NaN. For
// a finite nonzero value, value = sig_o * 2^(exp_o - FracBits) with the hidden bit
// in sig_o[FracBits]. Combinational; one instance per operand of every unit.
module rpu_fp_classify #(
  parameter int unsigned ExpBits  = 8,
  parameter int unsigned FracBits = 23,
  // Two's complement width of exp_o; must exceed ExpBits.
  parameter int unsigned ExpWidth = 10
) (
  input  logic [ExpBits+FracBits:0]  value_i,
  output logic                       sign_o,
  output logic                       zero_o,
  output logic                       inf_o,
  output logic                       nan_o,
  output logic signed [ExpWidth-1:0] exp_o,
  output logic [FracBits:0]          sig_o
);

  localparam logic signed [ExpWidth-1:0] Bias = ExpWidth'((1 << (ExpBits - 1)) - 1);

  logic [ExpBits-1:0]  field;
  logic [FracBits-1:0] frac;
  logic                field_max;

  assign sign_o    = value_i[ExpBits+FracBits];
  assign field     = value_i[ExpBits+FracBits-1:FracBits];
  assign frac      = value_i[FracBits-1:0];
  assign field_max = &field;
  assign zero_o    = ~|field;
  assign inf_o     = field_max & ~|frac;
  assign nan_o     = field_max & |frac;
  assign exp_o     = $signed(ExpWidth'(field)) - Bias;
  assign sig_o     = {1'b1, frac};

endmodule
