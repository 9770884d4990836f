// One rounded operation as a stage of a pipeline that stalls as a whole (rpu_iu's
// datapaths): the op's core, combinational, then a register loaded when en_i is high.
// Op is an fp_op_e: add, sub and mul run on rpu_fp_fma_core through the fma unit's
// operand mapping, the compares and from_fp32 on rpu_fp_misc_core, so every result has
// the bits the shared units give (a compare's answer sits in bit 0). Operands are 32
// bits wide, format values right-aligned, as in fp_req_t: from_fp32 reads all of them.
module rpu_fp_pipe_op #(
  parameter int unsigned ExpBits  = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits = rpu_pkg::FormatFp32FractionBits,
  parameter logic [rpu_pkg::FpOpBits-1:0] Op = rpu_pkg::FpOpAdd
) (
  input  logic                      clk_i,
  input  logic                      rst_ni,
  input  logic                      en_i,
  input  logic [31:0]               a_i,
  input  logic [31:0]               b_i,
  output logic [ExpBits+FracBits:0] result_o
);

  localparam int unsigned Width = 1 + ExpBits + FracBits;
  localparam bit OnFma = Op == rpu_pkg::FpOpAdd || Op == rpu_pkg::FpOpSub
                         || Op == rpu_pkg::FpOpMul;

  logic [Width-1:0] result;

  if (OnFma) begin : g_fma
    logic [Width-1:0] x, y, z;
    rpu_fp_fma_operands #(.ExpBits(ExpBits), .FracBits(FracBits)) u_operands (
      .op_i(Op), .a_i(a_i[Width-1:0]), .b_i(b_i[Width-1:0]), .c_i('0), .x_o(x), .y_o(y), .z_o(z)
    );
    rpu_fp_fma_core #(.ExpBits(ExpBits), .FracBits(FracBits)) u_core (
      .x_i(x), .y_i(y), .z_i(z), .result_o(result)
    );
    if (Width < 32) begin : g_unused_high
      logic unused_high;
      assign unused_high = ^{a_i[31:Width], b_i[31:Width]};
    end
  end else begin : g_misc
    logic [31:0] wide;
    rpu_fp_misc_core #(.ExpBits(ExpBits), .FracBits(FracBits)) u_core (
      .op_i(Op), .a_i, .b_i, .result_o(wide)
    );
    assign result = wide[Width-1:0];
    if (Width < 32) begin : g_unused_high
      logic unused_high;
      assign unused_high = ^wide[31:Width];
    end
  end

  rpu_en_reg #(.Width(Width)) u_result (.clk_i, .rst_ni, .en_i, .data_i(result), .data_o(result_o));

`ifndef SYNTHESIS
  initial assert (OnFma || Op == rpu_pkg::FpOpFromFp32 || Op == rpu_pkg::FpOpLt
                  || Op == rpu_pkg::FpOpLe || Op == rpu_pkg::FpOpGt || Op == rpu_pkg::FpOpGe
                  || Op == rpu_pkg::FpOpEq || Op == rpu_pkg::FpOpNe)
    else $error("rpu_fp_pipe_op: op %0d is not a single-rounding op", Op);
`endif

endmodule
