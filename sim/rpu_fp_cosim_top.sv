// The top that the Verilator harness and the netlist simulation drive: the unit chosen by
// Unit (rpu_pkg::FpUnit*) with each stream one flat port of its rpu_pkg width
// (spec/streams.toml), filled from rpu::streams words by the C++ harness and from the
// vector file by the netlist testbench. Only wiring: a synthesis of this top has the
// unit's cells.
module rpu_fp_cosim_top #(
  parameter int unsigned Unit     = rpu_pkg::FpUnitFma,
  parameter int unsigned ExpBits  = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits = rpu_pkg::FormatFp32FractionBits
) (
  input  logic                           clk_i,
  input  logic                           rst_ni,

  input  logic                           req_valid_i,
  output logic                           req_ready_o,
  input  logic [rpu_pkg::FpReqBits-1:0]  req_i,

  output logic                           rsp_valid_o,
  input  logic                           rsp_ready_i,
  output logic [rpu_pkg::FpRspBits-1:0]  rsp_o
);

  rpu_pkg::fp_req_t req;
  rpu_pkg::fp_rsp_t rsp;

  // The op field is an enum; a packed-vector assignment sets it without a type cast
  // (which Yosys 0.23 does not read).
  assign req   = req_i;
  assign rsp_o = rsp;

  if (Unit == rpu_pkg::FpUnitFma) begin : g_fma
    rpu_fp_fma #(.ExpBits(ExpBits), .FracBits(FracBits)) u_unit (
      .clk_i, .rst_ni, .req_valid_i, .req_ready_o, .req_i(req),
      .rsp_valid_o, .rsp_ready_i, .rsp_o(rsp)
    );
  end else if (Unit == rpu_pkg::FpUnitMisc) begin : g_misc
    rpu_fp_misc #(.ExpBits(ExpBits), .FracBits(FracBits)) u_unit (
      .clk_i, .rst_ni, .req_valid_i, .req_ready_o, .req_i(req),
      .rsp_valid_o, .rsp_ready_i, .rsp_o(rsp)
    );
  end else begin : g_divsqrt
    rpu_fp_divsqrt #(.ExpBits(ExpBits), .FracBits(FracBits)) u_unit (
      .clk_i, .rst_ni, .req_valid_i, .req_ready_o, .req_i(req),
      .rsp_valid_o, .rsp_ready_i, .rsp_o(rsp)
    );
  end

endmodule
