// The fused multiply-add unit: add, sub, mul, fma and fract (spec/fp_units.toml) on
// one rpu_fp_fma_core, so all five round through the same datapath:
//   add(a, b) = fma(a, 1, b)      sub(a, b) = fma(a, 1, -b)
//   mul(a, b) = fma(a, b, -0)     (-0 is the identity of addition, also for a zero
//                                  product: p + -0 = p, so the product's sign stays)
//   fract(a)  = fma(a, 1, -floor(a)), which is soft::fract's sub(a, floor(a)).
// Each identity is exact before rounding, so the one rounding gives the same bits as
// the op's own definition.
//
// Pipeline: stage 1 registers the selected operands (floor is formed in front of it),
// stage 2 the rounded result. Latency 2 cycles from req_valid_i && req_ready_o to
// rsp_valid_o; initiation interval 1. Stalls propagate back through rpu_pipe_reg.
module rpu_fp_fma #(
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

  localparam int unsigned Width = 1 + ExpBits + FracBits;
  localparam int unsigned StageBits = rpu_pkg::FpTagBits + 3 * Width;

  // Stage 1: operand selection.
  logic [Width-1:0] a, b, c;
  logic [Width-1:0] x_d, y_d, z_d;

  assign a = req_i.a[Width-1:0];
  assign b = req_i.b[Width-1:0];
  assign c = req_i.c[Width-1:0];

  rpu_fp_fma_operands #(.ExpBits(ExpBits), .FracBits(FracBits)) u_operands (
    .op_i(req_i.op), .a_i(a), .b_i(b), .c_i(c), .x_o(x_d), .y_o(y_d), .z_o(z_d)
  );

  logic                         s1_valid, s1_ready;
  logic [StageBits-1:0]         s1_q;
  logic [rpu_pkg::FpTagBits-1:0] s1_tag;
  logic [Width-1:0]             x_q, y_q, z_q;

  // The stages' clock runs while an op is offered or in a stage: with every valid low
  // a clock edge changes nothing (rpu_pipe_reg), so the gate only saves the work.
  logic stage_clk;
  rpu_clock_gate u_stage_gate (
    .clk_i, .en_i(req_valid_i || s1_valid || rsp_valid_o), .clk_o(stage_clk)
  );

  rpu_pipe_reg #(.Width(StageBits)) u_stage1 (
    .clk_i(stage_clk), .rst_ni,
    .valid_i(req_valid_i), .ready_o(req_ready_o), .data_i({req_i.tag, x_d, y_d, z_d}),
    .valid_o(s1_valid), .ready_i(s1_ready), .data_o(s1_q)
  );
  assign {s1_tag, x_q, y_q, z_q} = s1_q;

  // Stage 2: the fused multiply-add and its rounding.
  logic [Width-1:0]       result;
  rpu_pkg::fp_rsp_t       rsp_d;

  rpu_fp_fma_core #(.ExpBits(ExpBits), .FracBits(FracBits)) u_core (
    .x_i(x_q), .y_i(y_q), .z_i(z_q), .result_o(result)
  );

  assign rsp_d.tag    = s1_tag;
  assign rsp_d.result = rpu_pkg::FpOperandBits'(result);

  rpu_pipe_reg #(.Width($bits(rsp_d))) u_stage2 (
    .clk_i(stage_clk), .rst_ni,
    .valid_i(s1_valid), .ready_o(s1_ready), .data_i(rsp_d),
    .valid_o(rsp_valid_o), .ready_i(rsp_ready_i), .data_o(rsp_o)
  );

  // Operand bits above the format's width carry nothing (fp_req_t); op and c are
  // used only by some ops.
  if (Width < rpu_pkg::FpOperandBits) begin : g_unused_high
    logic unused_high;
    assign unused_high = ^{req_i.a[rpu_pkg::FpOperandBits-1:Width],
                           req_i.b[rpu_pkg::FpOperandBits-1:Width],
                           req_i.c[rpu_pkg::FpOperandBits-1:Width]};
  end

endmodule
