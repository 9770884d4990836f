// Count restoring steps of the radix-2 digit recurrence, combinational (Ercegovac &
// Lang ch. 5 and 6): each compares the partial remainder with the divisor (division)
// or with 4 * root + 1 (square root), keeps the difference if it fits, and shifts the
// digit into the root. rpu_fp_divsqrt runs one block a cycle on its registers;
// rpu_fp_div_pipe lays the blocks out as pipeline stages.
module rpu_fp_divsqrt_steps #(
  parameter int unsigned FracBits = 23,
  parameter int unsigned Steps    = 26,  // digits of the whole recurrence
  parameter int unsigned Count    = 2    // digits of this block
) (
  input  logic               sqrt_i,
  input  logic [Steps+1:0]   rem_i,
  input  logic [Steps-1:0]   root_i,
  input  logic [2*Steps-1:0] rad_i,
  input  logic [FracBits:0]  divisor_i,
  output logic [Steps+1:0]   rem_o,
  output logic [Steps-1:0]   root_o,
  output logic [2*Steps-1:0] rad_o
);

  localparam int unsigned RemBits = Steps + 2;
  localparam int unsigned RadBits = 2 * Steps;

  logic [RemBits-1:0] candidate, trial;
  logic               fits;
  always_comb begin : recurrence_steps
    candidate = '0;
    trial     = '0;
    fits      = 1'b0;
    rem_o     = rem_i;
    root_o    = root_i;
    rad_o     = rad_i;
    for (int unsigned s = 0; s < Count; s++) begin
      candidate = sqrt_i ? {rem_o[RemBits-3:0], rad_o[RadBits-1 -: 2]} : rem_o;
      trial     = sqrt_i ? {root_o, 2'b01} : RemBits'(divisor_i);
      fits      = candidate >= trial;
      rem_o     = fits ? candidate - trial : candidate;
      if (!sqrt_i) rem_o = rem_o << 1;
      root_o    = {root_o[Steps-2:0], fits};
      rad_o     = rad_o << 2;
    end
  end

endmodule
