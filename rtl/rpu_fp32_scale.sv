// fp32 bits times 2^exp_i, as rpu::fp::scale_fp32 (cmodel/fp/format.hpp): exact while
// the result is normal; a zero or subnormal input gives a signed zero (DAZ), a result
// below the normal range a signed zero (FTZ), one beyond it a signed infinity;
// infinities and NaNs pass unchanged. The traversal unit moves rays into the image's
// kd space with it and hit distances back (docs/traversal.md §1, §6). Combinational:
// an exponent add, no rounding.
module rpu_fp32_scale (
  input  logic [31:0]       value_i,
  input  logic signed [9:0] exp_i,
  output logic [31:0]       value_o
);

  logic [7:0]        field;
  logic signed [9:0] scaled;

  assign field  = value_i[30:23];
  // field in [1, 254] and exp_i in [-128, 128] keep the sum inside 10 bits.
  assign scaled = $signed({2'b00, field}) + exp_i;

  always_comb begin : scale
    if (&field) begin
      value_o = value_i;
    end else if (field == 8'd0 || scaled <= 10'sd0) begin
      value_o = {value_i[31], 31'd0};
    end else if (scaled >= 10'sd255) begin
      value_o = {value_i[31], 8'hff, 23'd0};
    end else begin
      value_o = {value_i[31], scaled[7:0], value_i[22:0]};
    end
  end

endmodule
