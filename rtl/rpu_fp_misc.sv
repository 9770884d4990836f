// The misc unit: floor, min, max, eq, ne, lt, le, gt, ge and the conversions
// from_fp32, to_fp32, from_int32, to_int32 (spec/fp_units.toml) on rpu_fp_misc_core.
//
// Pipeline: stage 1 registers the request, stage 2 the result. Latency 2 cycles from
// req_valid_i && req_ready_o to rsp_valid_o; initiation interval 1.
module rpu_fp_misc #(
  parameter int unsigned ExpBits  = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits = rpu_pkg::FormatFp32FractionBits
) (
  input  logic             clk_i,
  input  logic             rst_ni,

  input  logic             req_valid_i,
  output logic             req_ready_o,
  input  rpu_pkg::fp_req_t req_i,

  output logic             rsp_valid_o,
  input  logic             rsp_ready_i,
  output rpu_pkg::fp_rsp_t rsp_o
);

  localparam int unsigned OpBits = rpu_pkg::FpOperandBits;
  localparam int unsigned StageBits = rpu_pkg::FpOpBits + rpu_pkg::FpTagBits + 2 * OpBits;

  logic                          s1_valid, s1_ready;
  logic [StageBits-1:0]          s1_q;
  logic [rpu_pkg::FpOpBits-1:0]  s1_op;
  logic [rpu_pkg::FpTagBits-1:0] s1_tag;
  logic [OpBits-1:0]             s1_a, s1_b;

  // The stages' clock runs while an op is offered or in a stage: with every valid low
  // a clock edge changes nothing (rpu_pipe_reg), so the gate only saves the work.
  logic stage_clk;
  rpu_clock_gate u_stage_gate (
    .clk_i, .en_i(req_valid_i || s1_valid || rsp_valid_o), .clk_o(stage_clk)
  );

  rpu_pipe_reg #(.Width(StageBits)) u_stage1 (
    .clk_i(stage_clk), .rst_ni,
    .valid_i(req_valid_i), .ready_o(req_ready_o), .data_i({req_i.op, req_i.tag, req_i.a, req_i.b}),
    .valid_o(s1_valid), .ready_i(s1_ready), .data_o(s1_q)
  );
  assign {s1_op, s1_tag, s1_a, s1_b} = s1_q;

  rpu_pkg::fp_rsp_t rsp_d;
  assign rsp_d.tag = s1_tag;

  rpu_fp_misc_core #(.ExpBits(ExpBits), .FracBits(FracBits)) u_core (
    .op_i(s1_op), .a_i(s1_a), .b_i(s1_b), .result_o(rsp_d.result)
  );

  rpu_pipe_reg #(.Width($bits(rsp_d))) u_stage2 (
    .clk_i(stage_clk), .rst_ni,
    .valid_i(s1_valid), .ready_o(s1_ready), .data_i(rsp_d),
    .valid_o(rsp_valid_o), .ready_i(rsp_ready_i), .data_o(rsp_o)
  );

  // No misc op has a third operand.
  logic unused_c;
  assign unused_c = ^req_i.c;

endmodule
