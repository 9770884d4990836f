// The top that the IU harness (sim/iu_cosim.cpp) and the netlist simulation drive:
// rpu_iu with each stream one flat port of its rpu_pkg width (spec/streams.toml), filled
// from rpu::streams words, so neither the harness nor the testbench lists a field or a
// bit offset. Only wiring: a synthesis of this top has the unit's cells.
module rpu_iu_cosim_top #(
  parameter int unsigned ExpBits   = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits  = rpu_pkg::FormatFp32FractionBits,
  parameter int unsigned IsectMode = rpu_pkg::IsectModeWoop
) (
  input  logic                           clk_i,
  input  logic                           rst_ni,

  input  logic                           req_valid_i,
  output logic                           req_ready_o,
  input  logic [rpu_pkg::IuReqBits-1:0]  req_i,

  output logic                           rsp_valid_o,
  input  logic                           rsp_ready_i,
  output logic [rpu_pkg::IuRspBits-1:0]  rsp_o
);

  rpu_pkg::iu_req_t req;
  rpu_pkg::iu_rsp_t rsp;

  assign req   = req_i;
  assign rsp_o = rsp;

  rpu_iu #(.ExpBits(ExpBits), .FracBits(FracBits), .IsectMode(IsectMode)) u_iu (
    .clk_i, .rst_ni, .req_valid_i, .req_ready_o, .req_i(req),
    .rsp_valid_o, .rsp_ready_i, .rsp_o(rsp)
  );

endmodule
