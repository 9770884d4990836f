// The fma unit's operand mapping, combinational: add, sub, mul, fma and fract as
// x * y + z on rpu_fp_fma_core (rpu_fp_fma.sv gives the identities). Shared by the fma
// unit and the pipelined datapaths (rpu_fp_pipe_op), so an add rounds the same in both.
module rpu_fp_fma_operands #(
  parameter int unsigned ExpBits  = 8,
  parameter int unsigned FracBits = 23
) (
  input  logic [rpu_pkg::FpOpBits-1:0] op_i,
  input  logic [ExpBits+FracBits:0] a_i,
  input  logic [ExpBits+FracBits:0] b_i,
  input  logic [ExpBits+FracBits:0] c_i,
  output logic [ExpBits+FracBits:0] x_o,
  output logic [ExpBits+FracBits:0] y_o,
  output logic [ExpBits+FracBits:0] z_o
);

  localparam int unsigned Width = 1 + ExpBits + FracBits;
  localparam logic [Width-1:0] One = {2'b00, {(ExpBits - 1){1'b1}}, {FracBits{1'b0}}};
  localparam logic [Width-1:0] SignBit = {1'b1, {(Width - 1){1'b0}}};

  logic [Width-1:0] a_floor;
  rpu_fp_floor #(.ExpBits(ExpBits), .FracBits(FracBits)) u_floor (.a_i, .floor_o(a_floor));

  always_comb begin : map_operands
    x_o = a_i;
    y_o = One;
    z_o = b_i;
    unique case (op_i)
      rpu_pkg::FpOpAdd:   z_o = b_i;
      rpu_pkg::FpOpSub:   z_o = b_i ^ SignBit;
      rpu_pkg::FpOpMul: begin
        y_o = b_i;
        z_o = SignBit;
      end
      rpu_pkg::FpOpFma: begin
        y_o = b_i;
        z_o = c_i;
      end
      rpu_pkg::FpOpFract: z_o = a_floor ^ SignBit;
      // Ops of other units never reach this one; add is as good a mapping as any.
      default:            z_o = b_i;
    endcase
  end

endmodule
