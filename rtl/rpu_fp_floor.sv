// floor(a), exact (soft::floor; IEEE 754-2019 §5.9 roundToIntegralTowardNegative):
// clear the fraction bits below the binary point and, for a negative value that had
// any, add one unit at the binary point to the magnitude. A carry out of the stored
// fraction moves into the exponent field, which is the right encoding of the next
// power of two. Combinational; used by the misc unit (floor) and the fma unit (fract).
module rpu_fp_floor #(
  parameter int unsigned ExpBits  = 8,
  parameter int unsigned FracBits = 23
) (
  input  logic [ExpBits+FracBits:0] a_i,
  output logic [ExpBits+FracBits:0] floor_o
);

  localparam int unsigned Width = 1 + ExpBits + FracBits;
  localparam logic [ExpBits-1:0] BiasField = ExpBits'((1 << (ExpBits - 1)) - 1);
  // Fields at and above bias + FracBits have no fraction bits below the binary point;
  // compared five bits wider than a field, as the sum can exceed the largest field
  // (FracBits <= 23 < 2^5).
  localparam logic [ExpBits+4:0] IntegralField = (ExpBits+5)'((1 << (ExpBits - 1)) - 1 + FracBits);

  logic                sign;
  logic [ExpBits-1:0]  field;
  logic [FracBits-1:0] frac;
  logic [FracBits-1:0] below_point;  // mask of the fraction bits below the binary point
  logic [Width-1:0]    truncated;

  assign sign  = a_i[Width-1];
  assign field = a_i[Width-2:FracBits];
  assign frac  = a_i[FracBits-1:0];
  // For 1 <= |a| < 2^FracBits: FracBits - e bits lie below the point, e = field - bias.
  assign below_point = {FracBits{1'b1}} >> (field - BiasField);
  assign truncated   = a_i & ~(Width'(below_point));

  always_comb begin : floor_value
    if (&field) begin
      // inf stays; every NaN becomes the canonical one.
      floor_o = |frac ? {1'b0, {ExpBits{1'b1}}, 1'b1, {(FracBits - 1){1'b0}}} : a_i;
    end else if (field == '0) begin
      floor_o = {sign, {(Width - 1){1'b0}}};  // zeros and subnormals: signed zero
    end else if ((ExpBits+5)'(field) >= IntegralField) begin
      floor_o = a_i;
    end else if (field < BiasField) begin
      // 0 < |a| < 1: +0, or -1 for a negative value.
      floor_o = sign ? {1'b1, BiasField, {FracBits{1'b0}}} : {Width{1'b0}};
    end else if (sign && |(frac & below_point)) begin
      floor_o = truncated + Width'(below_point) + Width'(1);
    end else begin
      floor_o = truncated;
    end
  end

endmodule
