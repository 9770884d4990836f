// The one rounding step of every arithmetic result (soft.cpp round_pack): rounds
// sig_i * 2^exp_i (> 0) to FracBits+1 significant bits, nearest even (IEEE 754-2019
// §4.3.1) with an unbounded exponent, then gives +-inf above the largest finite value
// (§7.4) and a signed zero below the smallest normal (tininess after rounding, §7.5,
// flushed; docs/numbers.md rules 3-5). Combinational.
//
// Bit 0 of sig_i may be a sticky bit standing for nonzero bits below it; that keeps
// the decision exact when the normalised significand has at least FracBits+3 bits,
// hence SigBits >= FracBits + 3 (callers pad with zeros). exp_i + SigBits must fit
// in ExpWidth bits.
module rpu_fp_round #(
  parameter int unsigned ExpBits  = 8,
  parameter int unsigned FracBits = 23,
  parameter int unsigned SigBits  = 26,
  parameter int unsigned ExpWidth = 10
) (
  input  logic                       sign_i,
  input  logic signed [ExpWidth-1:0] exp_i,
  input  logic [SigBits-1:0]         sig_i,
  output logic [ExpBits+FracBits:0]  result_o
);

  localparam int unsigned LzBits = $clog2(SigBits);
  localparam logic signed [ExpWidth-1:0] Top = ExpWidth'(SigBits - 1);
  localparam logic signed [ExpWidth-1:0] Bias = ExpWidth'((1 << (ExpBits - 1)) - 1);
  localparam logic signed [ExpWidth-1:0] FieldMax = ExpWidth'((1 << ExpBits) - 1);

  // Leading-zero count: the highest set bit is the last one the loop sees.
  logic [LzBits-1:0] lz;
  always_comb begin : leading_zeros
    lz = '0;
    for (int unsigned i = 0; i < SigBits; i++) begin
      if (sig_i[i]) lz = LzBits'(SigBits - 1 - i);
    end
  end

  logic [SigBits-1:0]        norm;
  logic [FracBits:0]         kept;
  logic                      guard, sticky, round_up;
  logic [FracBits+1:0]       rounded;
  logic signed [ExpWidth-1:0] field;

  assign norm     = sig_i << lz;
  assign kept     = norm[SigBits-1 -: FracBits+1];
  assign guard    = norm[SigBits-FracBits-2];
  assign sticky   = |norm[SigBits-FracBits-3:0];
  assign round_up = guard & (sticky | kept[0]);
  assign rounded  = {1'b0, kept} + (FracBits+2)'(round_up);
  // Biased exponent of the leading bit; a carry out of the rounding moves it up one
  // binade (the fraction bits are then all zero).
  assign field    = exp_i + Top - $signed(ExpWidth'(lz)) + Bias
                    + $signed(ExpWidth'(rounded[FracBits+1]));

  always_comb begin : pack_result
    if (field >= FieldMax) begin
      result_o = {sign_i, {ExpBits{1'b1}}, {FracBits{1'b0}}};
    end else if (field <= 0) begin
      result_o = {sign_i, {(ExpBits + FracBits){1'b0}}};
    end else begin
      result_o = {sign_i, field[ExpBits-1:0], rounded[FracBits-1:0]};
    end
  end

endmodule
